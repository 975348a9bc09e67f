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
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "drivers/device.hpp"
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
  // The filter's position sigma at the end (sqrt of the trace of its xy
  // covariance) and the end's pose NEES.
  double final_position_sigma_m = 0.0, final_pose_nees = 0.0;
  double wall_time_s = 0.0, realtime_factor = 0.0;
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
  DriveSummary summary() const;
  const DriveConfig& config() const { return config_; }

 private:
  struct Pending {
    nav::TapeMeasurement m;
    bool is_landmark = false;
    nav::LandmarkMeasurement landmark;
    int frame = 0;
    double available_s() const {
      return is_landmark ? landmark.time.available_s : m.time.available_s;
    }
  };
  void expose_frame(int index, double t0);
  double frame_latency_s(const host::FrameOutcome& o) const;

  DriveConfig config_;
  RoutePlan plan_;
  golden::CeilingScene strips_;
  Robot robot_;
  PoseTrack track_;
  nav::TapeMap map_;
  std::unique_ptr<nav::Ekf> ekf_;
  nav::PathFollower follower_;
  std::unique_ptr<host::Navigator> navigator_;
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
