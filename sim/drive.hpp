// The closed loop: a simulated robot drives a course on ceilnav. Time
// advances in odometry ticks; the camera exposes a frame at its rate, the
// frame is rendered from the robot's true motion over the exposure, runs
// through the device (fast, model or RTL backend) and the host, and its tape
// measurement reaches the filter after the pipeline's latency, which applies
// it at the exposure time (retroactive correction); the path follower steers
// on the filter's estimate. docs/navigation.md, "Closed loop".
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "drivers/device.hpp"
#include "host/flow_height.hpp"
#include "host/nav_measurements.hpp"
#include "host/navigator.hpp"
#include "nav/ekf.hpp"
#include "nav/guidance.hpp"
#include "sim/course.hpp"
#include "sim/course_render.hpp"
#include "sim/robot.hpp"
#include "sim/route.hpp"

namespace ceilnav::sim {

struct DriveConfig {
  Course course = default_course();
  // The camera as the host is told it; its ceiling_height_m and
  // camera_height_m are overridden from the course (ceiling: the course's
  // default height) and the robot.
  host::CameraConfig camera;
  double camera_height_m = 0.3;
  RobotParams robot;
  CameraMount mount;                // the true mount
  nav::CameraMount believed_mount;  // what the filter assumes (after calibration)
  nav::EkfOptions ekf;              // its mount is set from believed_mount
  nav::FollowerOptions follower;
  host::TapeNoiseModel tape_noise;
  // Landmark distances (host::detect_junctions): the detector's own sigma
  // (pixel quantisation at the junction) scaled like the distance by the
  // ceiling's height, the exposure's smear (speed x exposure, uniform: /
  // sqrt 12; where the threshold cuts a moving end) and a floor for the
  // map's survey of the point.
  struct LandmarkNoise {
    double floor_sigma_m = 0.5e-3;
  } landmark_noise;
  bool landmarks = true;  // false: tape measurements only
  // The ceiling's height above the camera where it looks (docs/navigation.md,
  // "Ceiling height"): the vision measures its offsets and distances with the
  // map's height there; the filter's ceiling scale state (ekf.bias) holds
  // that height's relative error, observed by the landmarks and, with
  // `flow`, by the flow of tape ends against the wheel odometry (seed 000,
  // eq. 44: host::FlowTrack) as CeilingHeight measurements.
  struct Ceiling {
    bool flow = true;
    // The map's heights (the default ceiling's and every zone's) are the
    // course's times this: a wrong survey, for tests.
    double map_scale = 1.0;
  } ceiling;
  // Pattern station fixes (docs/navigation.md, "Pattern station fixes"): a
  // frame in which the filter's predicted camera view shows a mapped
  // station's panel whole (margin_px inside the image) is also analysed as
  // a pattern frame (analyse_pattern_frame) on a window of the sensor's
  // full resolution around the predicted panel (and, when that reads no
  // code, on the window turned 180 deg); an ok pose (bars measured, the
  // identity the station's, its mirror's when read turned, or unread)
  // becomes a PatternFix at the camera. Noise model: the camera's floor position with sigmas along
  // and across the horizontal line of sight to the disc, each a + b D (D: the camera's distance to
  // the disc), and the yaw's sigma; from the scatter of 80 fixes at D = 3.4-3.65 m on the default
  // and random courses (RMS 0.19 mm along, 0.56 mm across, 0.010 deg), inflated 1.1-1.3 times.
  struct StationFixes {
    bool enabled = true;
    // The frame the tapes use is the sensor's binned window_scale times;
    // the station's window is read at the full resolution.
    int window_scale = 4;
    double margin_px = 2.0;  // at the tape frame's resolution
    double along_sigma_m = 1e-4, along_sigma_per_m = 4e-5;
    double across_sigma_m = 2e-4, across_sigma_per_m = 1.2e-4;
    double yaw_sigma_rad = 1.75e-4;
    // The host's time for the pattern maths after the device's passes.
    double host_time_s = 0.004;
  } station_fixes;
  // Where the map puts the pattern stations (unset: where the course has
  // them); a test moves one to see what the filter makes of a wrong map.
  std::optional<std::vector<PatternStation>> station_map;
  host::NavigatorOptions navigator;
  DriveRenderParams render;
  // The device's backend (drivers::DeviceOptions; the rtl backend needs its
  // bus factory, apps' device_options gives it) and its name for the summary.
  drivers::DeviceOptions device;
  std::string backend = "fast";
  double odometry_rate_hz = 100.0;
  double frame_rate_hz = 30.0;
  double exposure_s = 0.004;
  // Latency: the frame streams through the pipeline at one pixel per clock
  // as the sensor reads it out (the device's cycles per pass, times the
  // passes the host ran), then the host computes for host_time_s.
  double pixel_clock_hz = 25.0e6;
  double host_time_s = 0.002;
  bool vision = true;
  // Stop the simulation after this long (0: three times the route at
  // the cruise speed, plus a minute).
  double max_time_s = 0.0;
  // Initial uncertainty of the start pose (sigmas): the filter starts at the
  // course's start with these, the truth at a draw from them (robot.seed).
  double start_sigma_m = 0.002, start_sigma_yaw_rad = 0.001;
};

// A pattern frame of the drive: what the host made of it, the fix, and for
// the record the true camera at mid-exposure and the fix's error.
struct PatternFixRecord {
  int frame = 0, station = 0;  // station: index in the map's stations
  double exposure_s = 0.0, available_s = 0.0;
  std::string status;  // ok, or why there is no fix (the pose's or code's status, wrong_identity)
  double d_m = 0.0, theta_rad = 0.0;
  bool code_read = false;  // the bar code's identity was read (and is the station's when ok)
  nav::PatternFix fix;
  nav::Pose2 truth;     // the true camera's floor position and heading
  std::string outcome;  // the filter's decision ("" until applied)
};

// One odometry tick of the drive.
struct DriveRow {
  double t_s = 0.0;
  nav::Pose2 truth, estimate;
  double sigma_x_m = 0.0, sigma_y_m = 0.0, sigma_yaw_rad = 0.0;
  double v_cmd_mps = 0.0, omega_cmd_radps = 0.0;
  nav::FollowerMode mode = nav::FollowerMode::follow;
  int leg = 0;
  double lateral_error_m = 0.0;    // truth: wheel-axis midpoint from the leg's centre line
  double heading_error_rad = 0.0;  // truth: yaw - the leg's direction
  double pose_nees = 0.0;
  // The filter's odometry calibration: wheel scale errors and heading scale error.
  double left_scale_error = 0.0, right_scale_error = 0.0, yaw_scale_error = 0.0;
  double distance_m = 0.0;  // truth: travelled so far
  double blind_m = 0.0;     // odometry distance since the last accepted tape measurement
  // The frame whose measurement was applied this tick (-1: none) and what
  // became of it; the frame exposed this tick (-1: none) and its host status.
  int frame = -1;
  std::string frame_status;
  std::string outcome;
  int station = -1;  // the applied measurement is a fix of this map station (index)
  // The ceiling above the camera where it looks: the filter's estimate (the
  // map's height over 1 + its ceiling scale) and sigma, the map's height,
  // and the truth (the course's).
  double ceiling_est_m = 0.0, ceiling_sigma_m = 0.0, ceiling_map_m = 0.0, ceiling_true_m = 0.0;
};

struct DriveSummary {
  std::string course, backend;
  double route_length_m = 0.0, driven_m = 0.0, sim_time_s = 0.0;
  bool finished = false;  // the follower reached the route's end
  bool lost = false;      // it stopped for lack of vision
  int frames = 0, frames_ok = 0;
  double lateral_rms_m = 0.0, lateral_max_m = 0.0, heading_rms_rad = 0.0;
  int junctions_planned = 0, junctions_taken = 0;
  int gaps_on_route = 0, gaps_crossed = 0;
  // Fraction of ticks whose pose NEES lies in the 95 % band of chi-square(3).
  double nees_in_band = 0.0;
  nav::Counters counters;
  double final_position_error_m = 0.0;
  // Per mapped station: the robot's position error |truth - estimate| (the
  // wheel-axis midpoint) on the tick before its first accepted fix was
  // applied and on the tick its last one was; the goal: <= 10 mm before,
  // <= 3 mm after.
  struct Station {
    int id = 0;
    int frames_analysed = 0, fixes_ok = 0, fixes_accepted = 0;
    double error_before_m = -1.0, error_after_m = -1.0;  // -1: no accepted fix
    bool goal_met() const {
      return fixes_accepted > 0 && error_before_m <= 0.010 && error_after_m <= 0.003;
    }
  };
  std::vector<Station> stations;
  // The filter's position sigma at the end (sqrt of the trace of its xy
  // covariance) and the end's pose NEES.
  double final_position_sigma_m = 0.0, final_pose_nees = 0.0;
  double wall_time_s = 0.0, realtime_factor = 0.0;
  // The filter's ceiling height where the camera looks against the truth
  // over the ticks (RMS and largest error, relative), and the map's own.
  double ceiling_error_rms = 0.0, ceiling_error_max = 0.0, ceiling_map_error_rms = 0.0;
};

class Drive {
 public:
  explicit Drive(const DriveConfig& config);
  ~Drive();
  // One odometry tick; false once the drive is over (finished, lost, or out
  // of time).
  bool step();
  // Runs to the end; progress(distance driven, route length) after each frame.
  void run(const std::function<void(double, double)>& progress = {});
  const std::vector<DriveRow>& rows() const { return rows_; }
  const RoutePlan& plan() const { return plan_; }
  const std::vector<PatternFixRecord>& pattern_fixes() const { return pattern_records_; }
  DriveSummary summary() const;
  const DriveConfig& config() const { return config_; }

 private:
  struct Pending {
    enum class Kind { tape, landmark, pattern, height };
    Kind kind = Kind::tape;
    nav::TapeMeasurement m;
    nav::LandmarkMeasurement landmark;
    nav::PatternFix pattern;
    nav::CeilingHeight height;
    int frame = 0;
    int record = -1;  // pattern: index in pattern_records_
    double available_s() const {
      return kind == Kind::landmark  ? landmark.time.available_s
             : kind == Kind::pattern ? pattern.time.available_s
             : kind == Kind::height  ? height.time.available_s
                                     : m.time.available_s;
    }
  };
  void expose_frame(int index, double t0);
  // The ceiling above the camera at `camera`'s look point: the map's zone
  // and height, the filter's estimate, and the truth.
  struct CeilingView {
    int zone = -1;
    double map_m = 0.0, estimate_m = 0.0, sigma_m = 0.0, truth_m = 0.0;
  };
  CeilingView ceiling_view(const nav::Pose2& camera) const;
  // A tape end's flow against the odometry (frame `index`, exposed at `time`).
  void track_tape_end(int index, const cv::Mat& frame, const host::FrameOutcome& out,
                      const host::TapePose& pose, const nav::MeasurementTime& time);
  // A frame without the tape end: the current track ends after five.
  void flow_idle();
  // The current track's fit as a CeilingHeight measurement, then forget it.
  void submit_flow_fit();
  // The nearest mapped station whose panel the filter's predicted view
  // shows whole, and the image region the pattern passes stream.
  struct StationView {
    int station = 0;  // index in stations_
    cv::Rect region;
  };
  std::optional<StationView> station_in_view() const;
  void analyse_station(int index, const StationView& view, double t0, double tape_latency_s);
  // The camera at the sensor's full resolution (station_fixes.window_scale
  // times the tape frame's).
  host::CameraConfig sensor_camera() const;
  double frame_latency_s(const host::FrameOutcome& o) const;
  double pass_time_s(int pixels) const;

  DriveConfig config_;
  RoutePlan plan_;
  golden::CeilingScene strips_;
  Robot robot_;
  PoseTrack track_;
  nav::TapeMap map_;
  std::unique_ptr<nav::Ekf> ekf_;
  Course map_course_;  // the course as the map has it (its heights: ceiling.map_scale)
  // Tape-end flow: the odometry's own dead reckoning (nominal wheel scales),
  // the current track, its latest fit and that fit's frame (time, index),
  // frames since it last grew.
  nav::Pose2 odometry_pose_;
  PoseTrack odometry_track_;
  std::unique_ptr<host::FlowTrack> flow_;
  std::optional<host::FlowFit> flow_fit_;
  nav::MeasurementTime flow_time_;
  int flow_frame_ = -1;
  int flow_idle_frames_ = 0;
  nav::PathFollower follower_;
  std::unique_ptr<drivers::Device> device_;  // the Navigator's and the stations'
  std::unique_ptr<host::Navigator> navigator_;
  std::vector<PatternStation> stations_;       // the map's
  drivers::Device* pattern_device_ = nullptr;  // device_ when stations are analysed
  std::unique_ptr<host::CameraModel> sensor_model_;
  std::vector<PatternFixRecord> pattern_records_;
  std::vector<Pending> pending_;
  std::vector<DriveRow> rows_;
  double t_ = 0.0, dt_ = 0.01, t_end_ = 0.0;
  int next_frame_ = 0;
  int frames_ = 0, frames_ok_ = 0;
  double blind_m_ = 0.0, driven_m_ = 0.0;
  double odometry_speed_mps_ = 0.0;  // the last tick's, from the wheels
  std::string exposed_status_;
  int exposed_frame_ = -1;
  bool over_ = false;
  double wall_s_ = 0.0;
};

// trajectory.csv: one row per tick (DriveRow), with a header.
void write_trajectory_csv(const std::string& path, const std::vector<DriveRow>& rows);

}  // namespace ceilnav::sim
