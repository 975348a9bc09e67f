#include "host/pattern/disc_evidence.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace ceilnav::host::pattern {
namespace {

// Signed distance (px, > 0 outside) of pixel (u, v) from the ellipse
// (q - c)^T mi (q - c) = 1 in normalised coordinates: (rho - 1) over the
// pixel gradient of rho (exact for a circle).
double pixel_distance(const CameraModel& camera, const Eigen::Vector2d& c,
                      const Eigen::Matrix2d& mi, double u, double v) {
  const Eigen::Vector2d q = camera.normalise(u, v) - c;
  const Eigen::Vector2d mq = mi * q;
  const double rho2 = q.dot(mq);
  if (!(rho2 > 1e-24)) return -1e9;
  const double rho = std::sqrt(rho2);
  constexpr double h = 0.5;
  Eigen::Matrix2d j;
  j.col(0) = (camera.normalise(u + h, v) - camera.normalise(u - h, v)) / (2.0 * h);
  j.col(1) = (camera.normalise(u, v + h) - camera.normalise(u, v - h)) / (2.0 * h);
  const double gn = (j.transpose() * mq).norm();
  if (!(gn > 0.0)) return 1e9;
  return (rho - 1.0) * rho / gn;
}

}  // namespace

bool one_run_per_row(std::span<const stream::RunRecord> disc_runs, int height) {
  if (disc_runs.empty()) return false;
  if (disc_runs.size() > static_cast<std::size_t>(std::max(height, 0))) return false;
  int row_min = disc_runs.front().row, row_max = row_min;
  for (const stream::RunRecord& r : disc_runs) {
    row_min = std::min(row_min, static_cast<int>(r.row));
    row_max = std::max(row_max, static_cast<int>(r.row));
  }
  const double rows = row_max - row_min + 1;
  return static_cast<double>(disc_runs.size()) <= kMaxDiscRunsPerRow * rows + 2.0;
}

bool runs_fit_ellipse(std::span<const stream::RunRecord> disc_runs, const Ellipse& start,
                      const CameraModel& camera, int width, int height) {
  if (!one_run_per_row(disc_runs, height)) return false;
  const Eigen::Matrix2d shape = 4.0 * start.cov;
  if (!(shape(0, 0) > 0.0) || !(shape.determinant() > 0.0)) return false;
  const Eigen::Matrix2d mi = shape.inverse();
  const Eigen::Vector2d c(start.cx, start.cy);
  for (const stream::RunRecord& r : disc_runs) {
    if (r.row == 0 || r.row + 1 >= height || r.x_start == 0 || r.x_end + 1 >= width) continue;
    for (const int x : {static_cast<int>(r.x_start), static_cast<int>(r.x_end)}) {
      const double d = pixel_distance(camera, c, mi, x, r.row);
      if (!(std::abs(d) <= kRunEndTolerancePx)) return false;
    }
  }
  return true;
}

}  // namespace ceilnav::host::pattern
