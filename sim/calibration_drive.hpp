// The mount calibration drive: the simulated robot drives along a straight
// tape with its heading held at +4 deg and then -4 deg relative to it, turns
// in place and drives back likewise; its camera's frames run through the
// device and the host, and the tape poses with the odometry's distances go
// to nav::calibrate_mount, whose effective values split_mount turns into
// the camera's mounting yaw, roll and pitch errors. docs/navigation.md,
// "Mount calibration".
#pragma once

#include <vector>

#include "common/camera_config.hpp"
#include "drivers/device.hpp"
#include "host/navigator.hpp"
#include "nav/mount_calibration.hpp"
#include "sim/course.hpp"
#include "sim/course_render.hpp"
#include "sim/robot.hpp"

namespace ceilnav::sim {

// A straight tape along +X from x = -3 m to x = run_length_m + 3 m under a
// ceiling of `ceiling_height_m`, the robot starting at the origin facing +X.
Course calibration_course(double run_length_m, double ceiling_height_m = 2.5);

struct CalibrationDriveConfig {
  // The course: its first tape's first segment is the one driven along; the
  // robot starts at course.start, roughly along it (within a few degrees).
  Course course = calibration_course(4.0);
  // The camera as the host is told it; its ceiling_height_m and
  // camera_height_m are overridden from the course and camera_height_m.
  host::CameraConfig camera;
  double camera_height_m = 0.3;
  RobotParams robot;
  CameraMount mount;  // the true mount (position and errors)
  // What the drawings say of the mount: its forward and lateral position
  // (the calibration needs forward; the split needs lateral) and the yaw
  // taken for it while steering (0: the camera looks straight ahead).
  double drawing_forward_m = 0.0, drawing_left_m = 0.0, drawing_left_sigma_m = 0.0;
  double assumed_yaw_rad = 0.0;
  host::NavigatorOptions navigator;
  DriveRenderParams render;
  drivers::DeviceOptions device;
  double odometry_rate_hz = 100.0;
  double frame_rate_hz = 30.0;
  double exposure_s = 0.004;
  // The drive: each run run_length_m long at speed_mps, the heading
  // +heading_rad relative to the tape for its first half and -heading_rad
  // for the second.
  double run_length_m = 4.0;
  double speed_mps = 0.5;
  double heading_rad = 0.0698131700797732;  // 4 deg
  double standstill_s = 0.5;                // before each run: frames to find the tape's direction
  double heading_gain_per_s = 4.0;          // omega = gain * heading error (odometry)
  // Per frame with a tape pose while driving, the tape's direction steered
  // on moves this fraction of the way to the one the frame's yaw gives (0:
  // odometry heading only after the standstill).
  double tape_steering_gain = 0.05;
  bool fit_pitch = true;
};

// A frame of the drive, for plots and checks.
struct CalibrationFrame {
  int run = 0;  // 0, 1; -1: a standstill frame (used for the heading reference only)
  double t_s = 0.0;
  double distance_m = 0.0;  // odometry travel since the run's start at mid-exposure
  bool ok = false;
  double yaw_rad = 0.0, offset_m = 0.0;            // host
  double true_yaw_rad = 0.0, true_offset_m = 0.0;  // tape_truth of the camera
  nav::Pose2 truth;                                // the robot at mid-exposure
};

struct CalibrationDriveResult {
  std::vector<nav::CalibrationRun> runs;
  std::vector<CalibrationFrame> frames;
  int frames_ok = 0;
  nav::MountCalibration calibration;
  nav::MountErrors errors;  // split_mount with the drawings' lateral
  // The truth the effective values stand for, to first order: the filter's
  // mount yaw m + roll sin p, lateral left - roll h cos p (h: the ceiling
  // above the camera), scale 1 (the configured ceiling is the course's).
  double true_effective_yaw_rad = 0.0, true_effective_lateral_m = 0.0;
  // The heading relative to the tape the robot believed at each run's start
  // (from the standstill frames) and the true one.
  double believed_start_heading_rad[2] = {0.0, 0.0}, true_start_heading_rad[2] = {0.0, 0.0};
  double max_abs_true_heading_rad = 0.0;  // over the runs' frames
  double sim_time_s = 0.0, wall_time_s = 0.0;
};

// Runs the drive and the calibration. Throws std::invalid_argument on a bad
// configuration (rates, lengths, a course whose first tape is not straight
// enough to drive run_length_m along).
CalibrationDriveResult calibration_drive(const CalibrationDriveConfig& config);

}  // namespace ceilnav::sim
