// Camera mount calibration from straight runs along a tape in both
// directions (docs/navigation.md, "Fusion filter", mount calibration): the
// camera's effective yaw on the robot, its effective lateral offset, the
// scale of the measured tape offset and (optionally) its pitch error, from
// tape measurements and the odometry's travelled distance alone; and the
// split of the effective values into the camera's mounting yaw, roll and
// pitch errors.
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

struct MountCalibrationOptions {
  double forward_m = 0.0;  // camera centre ahead of the axis midpoint (drawings)
  // Sigma of one measured offset; <= 0: taken from the fit's residuals
  // (RMS times sqrt(n / (n - parameters))).
  double offset_sigma_m = 5e-3;
  // Fit the camera's pitch error delta too. A pitch error about the camera's
  // horizontal axis adds -h delta sin(camera yaw) to the measured offset and
  // (offset / h) delta to the measured yaw, h = the configured ceiling height
  // above the camera (docs/navigation.md, "Mount calibration"): it is told
  // from the forward offset by the known forward_m.
  bool fit_pitch = false;
  double ceiling_above_camera_m = 0.0;  // h, > 0 when fit_pitch
};

struct MountCalibration {
  bool ok = false;
  double yaw_rad = 0.0;          // effective camera yaw relative to the robot's heading
  double lateral_m = 0.0;        // camera's lateral offset (left), mount plus roll's shift
  double offset_scale = 1.0;     // measured offset / true offset (ceiling height error)
  double pitch_error_rad = 0.0;  // fitted pitch error (0 unless fit_pitch)
  // (yaw, lateral, scale, pitch error); the pitch row and column are zero
  // unless fit_pitch.
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  double offset_sigma_m = 0.0;  // the sigma the covariance rests on
  double rms_residual_m = 0.0;
  int samples = 0;
  int iterations = 0;
};

// Model per sample, robot heading relative to the tape
// psi_i = yaw_i - mu - (offset_i / h) delta, axis-midpoint lateral position
// Y(s) = Y0 + integral of sin(psi) ds (trapezoidal over the samples), and
//   offset_i = k (Y(s_i) + forward_m sin psi_i) + c cos psi_i - h delta sin(psi_i + mu)
// (delta = 0 unless fit_pitch). Unknowns mu, c, k, delta and the start
// position Y0 of each run not turned in place; Gauss-Newton on the offsets.
// mu and k need the heading to change along a run (e.g. +-4 deg halves); c
// needs a run turned in place (otherwise only cos psi tells it from the start
// positions). c is the body-fixed part of the measured offset: k times the
// mount's lateral plus the shift a camera roll gives; mu includes the yaw a
// camera roll gives (both are what the filter needs as CameraMount). Not ok
// when fewer than 10 samples, the first run is turned in place, fit_pitch
// without a ceiling height, or the normal equations are singular.
MountCalibration calibrate_mount(const std::vector<CalibrationRun>& runs,
                                 const MountCalibrationOptions& options);
// The same without the pitch: calibrate_mount(runs, {forward_m, offset_sigma_m}).
MountCalibration calibrate_mount(const std::vector<CalibrationRun>& runs, double forward_m,
                                 double offset_sigma_m);

// The camera's mounting errors from the effective values, to first order in
// the small angles (docs/navigation.md, "Mount calibration"): a roll phi
// about the optical axis adds phi sin p to the measured yaw and
// -phi h cos p to the measured offset (p: the configured pitch above the
// horizontal, h: the configured ceiling height above the camera), so with
// the mount's lateral l known (drawings)
//   roll = (k l - c) / (h (cos p - delta sin p)),   yaw = mu - roll sin p,
//   pitch = delta
// (the delta sin p: the model's pitch term turns with mu, not with the
// mounting yaw, and c takes up the difference h delta roll sin p).
// Not separable without l: roll and l trade one for the other in c.
struct MountErrors {
  double yaw_rad = 0.0, roll_rad = 0.0, pitch_rad = 0.0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // (yaw, roll, pitch)
};
// left_sigma_m: the drawings' uncertainty of l (adds to the roll's and the
// yaw's covariance).
MountErrors split_mount(const MountCalibration& calibration, double left_m, double pitch_rad,
                        double ceiling_above_camera_m, double left_sigma_m = 0.0);

}  // namespace ceilnav::nav
