// Camera mount calibration from straight runs along a tape in both
// directions (docs/navigation.md, "Fusion filter", mount calibration): the
// camera's effective yaw on the robot, its effective lateral offset and the
// scale of the measured tape offset, from tape measurements and the
// odometry's travelled distance alone.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace ceilnav::nav {

// One frame of a run: the odometry's travel of the wheel-axis midpoint since
// the run's start, and the tape measurement (camera yaw relative to the tape's
// direction of travel, camera offset, positive left).
struct CalibrationSample {
  double distance_m = 0.0;
  double yaw_rad = 0.0;
  double offset_m = 0.0;
};

// A run along one straight tape. `end_distance_m`: the travel at which the
// run ended (>= the last sample's). `turned_in_place`: the run starts where
// the previous one ended, the robot having turned about its axis midpoint to
// drive back along the same tape (its lateral position is then minus the
// previous run's final one); otherwise the run's start position is unknown.
struct CalibrationRun {
  std::vector<CalibrationSample> samples;
  double end_distance_m = 0.0;
  bool turned_in_place = false;
};

struct MountCalibration {
  bool ok = false;
  double yaw_rad = 0.0;       // camera yaw relative to the robot's heading
  double lateral_m = 0.0;     // camera's lateral offset (left), mount plus roll's shift
  double offset_scale = 1.0;  // measured offset / true offset (pitch, ceiling height error)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // (yaw, lateral, scale)
  double rms_residual_m = 0.0;
  int iterations = 0;
};

// Model per sample, robot heading relative to the tape psi_i = yaw_i - mu,
// axis-midpoint lateral position Y(s) = Y0 + integral of sin(psi) ds
// (trapezoidal over the samples), and
//   offset_i = k (Y(s_i) + forward_m sin psi_i) + c cos psi_i.
// Unknowns mu, c, k and the start position Y0 of each run not turned in
// place; Gauss-Newton on the offsets (sigma offset_sigma_m). mu and k need the
// heading to change along a run (e.g. +-4 deg halves); c needs a run turned in
// place (otherwise only cos psi tells it from the start positions). c is the
// body-fixed part of the measured offset: k times the mount's lateral plus the
// shift a camera roll gives; mu includes the yaw a camera roll gives (both are
// what the filter needs as CameraMount). Not ok when fewer than 10 samples,
// the first run is turned in place, or the normal equations are singular.
MountCalibration calibrate_mount(const std::vector<CalibrationRun>& runs, double forward_m,
                                 double offset_sigma_m);

}  // namespace ceilnav::nav
