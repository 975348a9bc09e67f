#include "nav/mount_calibration.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace ceilnav::nav {
namespace {

// Parameters: mu, c, k, then delta (when fitted), then one Y0 per run not
// turned in place.
Eigen::VectorXd residuals(const std::vector<CalibrationRun>& runs, const MountCalibrationOptions& o,
                          const Eigen::VectorXd& p, std::size_t n) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(n));
  const double mu = p(0), c = p(1), k = p(2);
  const double delta = o.fit_pitch ? p(3) : 0.0;
  const double h = o.fit_pitch ? o.ceiling_above_camera_m : 0.0;
  Eigen::Index next_start = o.fit_pitch ? 4 : 3, i = 0;
  double previous_end = 0.0;
  for (const CalibrationRun& run : runs) {
    double y = run.turned_in_place ? -previous_end : p(next_start++);
    double s_prev = 0.0, sin_prev = 0.0;
    bool first = true;
    for (const CalibrationSample& smp : run.samples) {
      // The pitch error's yaw bias (offset / h) delta is taken off the
      // measured yaw (the offset as measured: k cancels, both scale with h).
      const double psi = smp.yaw_rad - mu - (h > 0.0 ? smp.offset_m / h * delta : 0.0);
      const double sn = std::sin(psi);
      // From the run's start (taken at the first sample's heading) to here.
      y += first ? smp.distance_m * sn : 0.5 * (sin_prev + sn) * (smp.distance_m - s_prev);
      first = false;
      s_prev = smp.distance_m;
      sin_prev = sn;
      r(i++) = smp.offset_m -
               (k * (y + o.forward_m * sn) + c * std::cos(psi) - h * delta * std::sin(psi + mu));
    }
    previous_end = y + sin_prev * (run.end_distance_m - s_prev);
  }
  return r;
}

}  // namespace

MountCalibration calibrate_mount(const std::vector<CalibrationRun>& runs,
                                 const MountCalibrationOptions& options) {
  MountCalibration out;
  std::size_t n = 0;
  const Eigen::Index fixed = options.fit_pitch ? 4 : 3;
  Eigen::Index params = fixed;
  for (const CalibrationRun& run : runs) {
    n += run.samples.size();
    if (!run.turned_in_place) ++params;
  }
  if (n < 10 || runs.empty() || runs.front().turned_in_place) return out;
  if (options.fit_pitch && !(options.ceiling_above_camera_m > 0.0)) return out;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(params);
  p(2) = 1.0;
  Eigen::MatrixXd j(static_cast<Eigen::Index>(n), params);
  Eigen::MatrixXd normal;
  for (out.iterations = 1; out.iterations <= 20; ++out.iterations) {
    const Eigen::VectorXd r0 = residuals(runs, options, p, n);
    for (Eigen::Index q = 0; q < params; ++q) {
      const double h = 1e-7;
      Eigen::VectorXd a = p, b = p;
      a(q) += h;
      b(q) -= h;
      // d(residual)/dp = -d(model)/dp.
      j.col(q) = (residuals(runs, options, a, n) - residuals(runs, options, b, n)) / (2 * h);
    }
    normal = j.transpose() * j;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
    if (lu.rank() < params) return out;
    const Eigen::VectorXd step = -lu.solve(j.transpose() * r0);
    p += step;
    if (step.cwiseAbs().maxCoeff() < 1e-12) break;
  }
  const Eigen::VectorXd r = residuals(runs, options, p, n);
  out.samples = static_cast<int>(n);
  out.rms_residual_m = std::sqrt(r.squaredNorm() / static_cast<double>(n));
  out.offset_sigma_m = options.offset_sigma_m;
  if (!(out.offset_sigma_m > 0.0)) {
    const auto dof = static_cast<double>(static_cast<Eigen::Index>(n) - params);
    if (dof < 1.0) return out;
    out.offset_sigma_m = std::sqrt(r.squaredNorm() / dof);
  }
  out.ok = true;
  out.yaw_rad = p(0);
  out.lateral_m = p(1);
  out.offset_scale = p(2);
  const Eigen::MatrixXd cov = out.offset_sigma_m * out.offset_sigma_m * normal.inverse();
  out.covariance.topLeftCorner(fixed, fixed) = cov.topLeftCorner(fixed, fixed);
  if (options.fit_pitch) out.pitch_error_rad = p(3);
  return out;
}

MountCalibration calibrate_mount(const std::vector<CalibrationRun>& runs, double forward_m,
                                 double offset_sigma_m) {
  MountCalibrationOptions o;
  o.forward_m = forward_m;
  o.offset_sigma_m = offset_sigma_m;
  return calibrate_mount(runs, o);
}

MountErrors split_mount(const MountCalibration& calibration, double left_m, double pitch_rad,
                        double ceiling_above_camera_m, double left_sigma_m) {
  MountErrors e;
  // The model's pitch term turns with mu, the camera with the mounting yaw
  // mu - roll sin p: the fitted c holds h delta roll sin p more, hence the
  // factor cos p - delta sin p (docs/navigation.md, "Mount calibration").
  const double delta = calibration.pitch_error_rad, sp = std::sin(pitch_rad);
  const double hc = ceiling_above_camera_m * (std::cos(pitch_rad) - delta * sp);
  const double k = calibration.offset_scale;
  e.roll_rad = (k * left_m - calibration.lateral_m) / hc;
  e.yaw_rad = calibration.yaw_rad - e.roll_rad * sp;
  e.pitch_rad = delta;
  // d(yaw, roll, pitch) / d(mu, c, k, delta, l).
  Eigen::Matrix<double, 3, 5> jac = Eigen::Matrix<double, 3, 5>::Zero();
  jac(1, 1) = -1.0 / hc;
  jac(1, 2) = left_m / hc;
  jac(1, 3) = e.roll_rad * ceiling_above_camera_m * sp / hc;
  jac(1, 4) = k / hc;
  jac.row(0) = -sp * jac.row(1);
  jac(0, 0) = 1.0;
  jac(2, 3) = 1.0;
  Eigen::Matrix<double, 5, 5> cov = Eigen::Matrix<double, 5, 5>::Zero();
  cov.topLeftCorner<4, 4>() = calibration.covariance;
  cov(4, 4) = left_sigma_m * left_sigma_m;
  e.covariance = jac * cov * jac.transpose();
  return e;
}

}  // namespace ceilnav::nav
