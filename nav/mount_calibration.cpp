#include "nav/mount_calibration.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace ceilnav::nav {
namespace {

// Parameters: mu, c, k, then one Y0 per run not turned in place.
Eigen::VectorXd residuals(const std::vector<CalibrationRun>& runs, double forward_m,
                          const Eigen::VectorXd& p, std::size_t n) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(n));
  const double mu = p(0), c = p(1), k = p(2);
  Eigen::Index next_start = 3, i = 0;
  double previous_end = 0.0;
  for (const CalibrationRun& run : runs) {
    double y = run.turned_in_place ? -previous_end : p(next_start++);
    double s_prev = 0.0, sin_prev = 0.0;
    bool first = true;
    for (const CalibrationSample& smp : run.samples) {
      const double psi = smp.yaw_rad - mu;
      const double sn = std::sin(psi);
      // From the run's start (taken at the first sample's heading) to here.
      y += first ? smp.distance_m * sn : 0.5 * (sin_prev + sn) * (smp.distance_m - s_prev);
      first = false;
      s_prev = smp.distance_m;
      sin_prev = sn;
      r(i++) = smp.offset_m - (k * (y + forward_m * sn) + c * std::cos(psi));
    }
    previous_end = y + sin_prev * (run.end_distance_m - s_prev);
  }
  return r;
}

}  // namespace

MountCalibration calibrate_mount(const std::vector<CalibrationRun>& runs, double forward_m,
                                 double offset_sigma_m) {
  MountCalibration out;
  std::size_t n = 0;
  Eigen::Index params = 3;
  for (const CalibrationRun& run : runs) {
    n += run.samples.size();
    if (!run.turned_in_place) ++params;
  }
  if (n < 10 || runs.empty() || runs.front().turned_in_place) return out;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(params);
  p(2) = 1.0;
  Eigen::MatrixXd j(static_cast<Eigen::Index>(n), params);
  Eigen::MatrixXd normal;
  for (out.iterations = 1; out.iterations <= 20; ++out.iterations) {
    const Eigen::VectorXd r0 = residuals(runs, forward_m, p, n);
    for (Eigen::Index q = 0; q < params; ++q) {
      const double h = 1e-7;
      Eigen::VectorXd a = p, b = p;
      a(q) += h;
      b(q) -= h;
      // d(residual)/dp = -d(model)/dp.
      j.col(q) = (residuals(runs, forward_m, a, n) - residuals(runs, forward_m, b, n)) / (2 * h);
    }
    normal = j.transpose() * j;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
    if (lu.rank() < params) return out;
    const Eigen::VectorXd step = -lu.solve(j.transpose() * r0);
    p += step;
    if (step.cwiseAbs().maxCoeff() < 1e-12) break;
  }
  const Eigen::VectorXd r = residuals(runs, forward_m, p, n);
  out.rms_residual_m = std::sqrt(r.squaredNorm() / static_cast<double>(n));
  out.ok = true;
  out.yaw_rad = p(0);
  out.lateral_m = p(1);
  out.offset_scale = p(2);
  out.covariance = (offset_sigma_m * offset_sigma_m * normal.inverse()).topLeftCorner<3, 3>();
  return out;
}

}  // namespace ceilnav::nav
