// The subcommands of the ceilnav program. Each returns the process exit code;
// errors the user can fix (bad files, arguments) throw std::runtime_error and
// are reported by main() with exit code 1.
#pragma once

#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "drivers/device.hpp"

namespace ceilnav::app {

inline constexpr double kDeg = std::numbers::pi / 180.0;  // radians per degree

struct DemoOptions {
  std::string out_dir = "ceilnav-demo";
  int frames = 40;
  std::string backend = "fast";  // fast | model | rtl (see drivers::DeviceOptions)
  bool quiet = false;
};
int run_demo(const DemoOptions& o);

struct RunOptions {
  std::string frames_dir;
  std::string scene_file;
  std::string out_csv;
  std::string backend = "fast";  // fast | model | rtl
  double gap_probability = 0.0;
  double backpressure_probability = 0.0;
  uint64_t seed = 1;
  // N > 0: an overlay PNG of every N-th frame (frame 0 included) into
  // overlays/ beside the CSV; 0: none.
  int overlay_every = 0;
  // The frames are one sequence from a moving robot: a pose farther from the
  // previous frame's than the robot can move is `jump` (host::TrackOptions).
  bool track = false;
  // Measured odometry (docs/navigation_io.md): the flow and tape-width
  // ceiling heights and the odometry scale per frame in extra CSV columns.
  std::string odometry_file;     // t_s,left_ticks,right_ticks or t_s,v_mps,omega_radps
  std::string robot_file;        // wheel base and metres per count (counts format)
  std::string frame_times_file;  // frame,t_s (frame = PNG file name)
  double fps = 0.0;              // > 0 and no frame-time file: frame i at i / fps
};
int run_frames(const RunOptions& o);

// `ceilnav render-drive`: frames rendered along a straight or gently curving path
// over the default corridor, with the wheel odometry the robot would log (a
// chosen scale error, encoder quantisation) and the frames' exposure times.
struct RenderDriveOptions {
  std::string out_dir;
  std::string path = "curve";  // straight | curve
  double length_m = 14.0;
  double speed_mps = 0.5;
  double fps = 2.0;
  double tick_hz = 50.0;
  double scale_error = 0.0;  // the odometry reports (1 + e) times the travel
  double wheel_base_m = 0.4;
  double m_per_count = 1e-4;
  uint64_t seed = 1;
};
int run_render_drive(const RenderDriveOptions& o);

struct RenderOptions {
  std::string out_dir;
  int frames = 20;
  bool random_poses = false;  // random poses in the accuracy ranges instead of the demo drive
  uint64_t seed = 1;
  double noise_sigma = -1.0;  // < 0: the default scene's
  double blur_sigma = -1.0;
  double pitch_deg = 45.0;
  int width = 640, height = 480;
  bool distortion = true;
};
int run_render(const RenderOptions& o);

struct AccuracyOptions {
  int frames = 200;
  uint64_t seed = 1;
  double pitch_min_deg = 20.0, pitch_max_deg = 60.0;
  double yaw_max_deg = 15.0;
  double offset_max_m = 0.5;
  double noise_max = 5.0;
  double blur_max = 1.0;
  int width = 640, height = 480;
  bool distortion = true;
  double tape_gain = -1.0;         // < 0: the default scene's (grey * m^2)
  double background_grey = -1.0;   // < 0: the default scene's
  double ceiling_height_m = -1.0;  // < 0: the default camera's
  double tape_width_m = -1.0;      // < 0: the default camera's
  std::string csv;                 // per-frame errors, optional
  bool require = false;            // exit 1 unless yaw RMS <= 0.02 deg and offset RMS <= 1 mm
  double yaw_rms_limit_deg = 0.02;
  double offset_rms_limit_m = 0.001;
};
int run_accuracy(const AccuracyOptions& o);

struct ExposureOptions {
  int frames = 48;
  double pitch_deg = 45.0;
  double step_m = 0.4;            // travel between frames
  double tape_gain = -1.0;        // < 0: the default scene's (grey * m^2 at nominal exposure)
  double background_grey = -1.0;  // < 0: the default scene's (at nominal exposure)
  double noise_sigma = -1.0;      // < 0: the default scene's (read noise, exposure-independent)
  uint64_t seed = 1;
  std::string backend = "fast";
  std::string csv;  // per-frame, per-policy rows, optional
};
int run_exposure(const ExposureOptions& o);
// The exposure of frame i of the sweep (relative to nominal).
double exposure_of_frame(int i);

struct DriveOptions {
  std::string out_dir = "ceilnav-drive";
  std::string course_file;     // empty: the built-in default course (or a random one)
  int64_t random_course = -1;  // >= 0: sim::random_course(this seed, random_length_m)
  double random_length_m = 100.0;
  std::string backend = "fast";
  uint64_t seed = 1;
  int monte_carlo = 1;
  bool vision = true;
  std::string steering = "feedback";  // feedback | linear | pure-pursuit
  // 60 deg: the view's near edge is 0.2 m ahead of the camera, so the robot
  // drives blind only the last 0.3 m into a corner (45 deg: 0.9 m; measured:
  // heading RMS 0.05-0.08 deg against 0.15-0.32 deg on the default and two
  // random courses).
  double pitch_deg = 60.0;
  int width = 320, height = 240;  // the camera: the demo camera scaled (scaled_camera)
  double max_time_s = 0.0;        // 0: from the route's length
  // The map's ceiling heights are the course's times this (a wrong survey:
  // the flow's estimate of the height shows it, docs/navigation.md).
  double map_height_scale = 1.0;
  bool plot = true;
  bool quiet = false;
  bool require = false;  // exit 1 unless the goals are met
  // A corridor without tape (seed 002): "default" or a corridor file; the
  // robot is guided by the corridor lines (run_corridor_drive). Empty: the
  // tape course.
  std::string corridor;
  double length_m = 50.0;  // the corridor drive's length
};
int run_drive(const DriveOptions& o);
// `ceilnav drive --corridor`: the closed corridor loop (sim/corridor_drive.hpp).
int run_corridor_drive(const DriveOptions& o);

// `ceilnav corridor`: seed 002's corridor guidance (docs/corridor.md,
// "ceilnav corridor"): learn a model of the ceiling lines from a driven
// path, then guide. Built-in: frames rendered in the default corridor (or
// the scene file's); --frames: recorded frames, the first learn_frames
// of them the learning drive.
struct CorridorOptions {
  std::string out_dir = "ceilnav-corridor";
  std::string scene_file;   // corridor file (docs/navigation_io.md); empty: built-in
  std::string camera_file;  // OpenCV camera YAML; empty: 640 x 480, f = 500
  std::string frames_dir;   // recorded frames (PNG, name order); empty: rendered
  int learn_frames = 17;
  std::optional<double> tilt_deg, swing_deg, camera_height_m;  // else the scene's camera
  double noise_grey = 2.0;  // rendered frames: the noise's sigma, grey levels
  int overlays = 4;         // overlay PNGs of the first guided frames
  bool quiet = false;
  bool require = false;  // exit 1 unless the goals are met (frames with truth)
};
int run_corridor(const CorridorOptions& o);

// `ceilnav homing`: seed 004's homing sites recorded on a structured
// ceiling (a ceiling file, docs/navigation_io.md; default the built-in
// office ceiling), then the triangle race and optionally the capture zone
// (docs/homing.md).
struct HomingOptions {
  std::string out_dir = "ceilnav-homing";
  std::string ceiling_file;  // empty: golden::ceiling::default_homing_world()
  std::string camera_file;   // OpenCV camera YAML (the lens); empty: 640 x 480, f = 500
  std::string map_file;      // a recorded site map (map.json); empty: record the sites
  // Recorded frames (PNG, name order): every site of --map searched in every
  // frame (frames.csv); no race.
  std::string frames_dir;
  int loops = 7;
  double noise_grey = 2.0;
  bool capture = false;  // the capture zone study of --capture-site
  int capture_site = 1;
  std::vector<double> capture_radii_m{0.5, 0.75, 1.0, 1.15, 1.3, 1.5};  // ascending
  uint64_t seed = 1;
  // The orientation histograms from the homing device on this backend
  // (fast | model | rtl; see drivers::DeviceOptions).
  std::string backend = "fast";
  bool plot = true;
  bool quiet = false;
  bool require = false;  // exit 1 unless the goals are met
};
int run_homing(const HomingOptions& o);

// `ceilnav calibrate-mount`: the mount calibration drive (sim::calibration_drive)
// with these true mount errors; calibration.json and frames.csv.
struct CalibrateMountOptions {
  std::string out_dir = "ceilnav-calibration";
  double yaw_deg = 0.8, roll_deg = 0.5, pitch_error_deg = 1.0;  // the true mount errors
  double forward_m = 0.1, left_m = 0.02;                        // the true mount position
  // The drawings' lateral differs from the true one by this; its sigma
  // enters the roll's and the yaw's covariance.
  double left_error_mm = 0.0, left_sigma_mm = 0.0;
  std::string backend = "fast";
  uint64_t seed = 1;
  int monte_carlo = 1;
  double run_length_m = 4.0;  // each direction
  double speed_mps = 0.5;
  double heading_deg = 4.0;  // relative to the tape, each half of a run
  double pitch_deg = 60.0;
  double ceiling_height_m = 2.5;
  int width = 320, height = 240;
  bool fit_pitch = true;
  bool quiet = false;
  bool require = false;  // exit 1 unless every run's mounting yaw is within 0.05 deg
};
int run_calibrate_mount(const CalibrateMountOptions& o);

// The device for a backend name (fast, model, or rtl when this build has the
// Verilated RTL; std::runtime_error otherwise); the bus backends with the
// demo's tvalid gaps (0.1) and run-stream back-pressure (0.3).
drivers::DeviceOptions device_options(const std::string& backend);

// The default camera (golden/default_scene.hpp) for another frame size: focal
// lengths and principal point scaled from 640x480.
host::CameraConfig scaled_camera(int width, int height, bool distortion);

}  // namespace ceilnav::app
