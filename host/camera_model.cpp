#include "host/camera_model.hpp"

#include <cmath>

namespace ceilnav::host {

CameraModel::CameraModel(const CameraConfig& cfg)
    : fx_(cfg.fx()),
      fy_(cfg.fy()),
      cx_(cfg.cx()),
      cy_(cfg.cy()),
      inv_fx_(1.0 / cfg.fx()),
      inv_fy_(1.0 / cfg.fy()),
      k1_(cfg.distortion_coefficients[0]),
      k2_(cfg.distortion_coefficients[1]),
      p1_(cfg.distortion_coefficients[2]),
      p2_(cfg.distortion_coefficients[3]),
      k3_(cfg.distortion_coefficients[4]),
      has_distortion_(cfg.has_distortion()) {
  if (!has_distortion_) return;
  grid_cols_ = (cfg.image_width + 1) / kGridStep + 2;
  grid_rows_ = (cfg.image_height + 1) / kGridStep + 2;
  grid_.resize(static_cast<size_t>(grid_cols_) * static_cast<size_t>(grid_rows_));
  for (int j = 0; j < grid_rows_; ++j) {
    for (int i = 0; i < grid_cols_; ++i) {
      const double xd = (-1.0 + kGridStep * i - cx_) * inv_fx_;
      const double yd = (-1.0 + kGridStep * j - cy_) * inv_fy_;
      grid_[static_cast<size_t>(j * grid_cols_ + i)] = newton(xd, yd, xd, yd);
    }
  }
}

Eigen::Vector2d CameraModel::distort(const Eigen::Vector2d& xy) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double g = 1.0 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
  return {x * g + 2.0 * p1_ * x * y + p2_ * (r2 + 2.0 * x * x),
          y * g + p1_ * (r2 + 2.0 * y * y) + 2.0 * p2_ * x * y};
}

Eigen::Vector2d CameraModel::distort_to_pixel(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d d = has_distortion_ ? distort(xy) : xy;
  return {fx_ * d.x() + cx_, fy_ * d.y() + cy_};
}

Eigen::Vector2d CameraModel::normalise(double u_px, double v_px) const {
  const double xd = (u_px - cx_) * inv_fx_;
  const double yd = (v_px - cy_) * inv_fy_;
  if (!has_distortion_) return {xd, yd};
  const double gu = (u_px + 1.0) / kGridStep, gv = (v_px + 1.0) / kGridStep;
  if (gu >= 0.0 && gv >= 0.0 && gu < grid_cols_ - 1 && gv < grid_rows_ - 1) {
    const int i = static_cast<int>(gu), j = static_cast<int>(gv);
    const double a = gu - i, b = gv - j;
    const size_t k = static_cast<size_t>(j * grid_cols_ + i);
    const size_t cols = static_cast<size_t>(grid_cols_);
    const Eigen::Vector2d g = (1.0 - b) * ((1.0 - a) * grid_[k] + a * grid_[k + 1]) +
                              b * ((1.0 - a) * grid_[k + cols] + a * grid_[k + cols + 1]);
    return newton(xd, yd, g.x(), g.y());
  }
  return newton(xd, yd, xd, yd);
}

Eigen::Vector2d CameraModel::newton(double xd, double yd, double x, double y) const {
  // Newton on F(x, y) = distort(x, y) - (xd, yd). With g' = dg/dr2:
  //   dXd/dx = g + 2 x^2 g' + 2 p1 y + 6 p2 x    dXd/dy = 2 x y g' + 2 p1 x + 2 p2 y
  //   dYd/dx = 2 x y g' + 2 p1 x + 2 p2 y        dYd/dy = g + 2 y^2 g' + 6 p1 y + 2 p2 x
  for (int it = 0; it < 20; ++it) {
    const double r2 = x * x + y * y;
    const double g = 1.0 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
    const double gp = k1_ + r2 * (2.0 * k2_ + 3.0 * r2 * k3_);
    const double fxv = x * g + 2.0 * p1_ * x * y + p2_ * (r2 + 2.0 * x * x) - xd;
    const double fyv = y * g + p1_ * (r2 + 2.0 * y * y) + 2.0 * p2_ * x * y - yd;
    if (std::abs(fxv) < 1e-13 && std::abs(fyv) < 1e-13) break;
    const double j11 = g + 2.0 * x * x * gp + 2.0 * p1_ * y + 6.0 * p2_ * x;
    const double j12 = 2.0 * x * y * gp + 2.0 * p1_ * x + 2.0 * p2_ * y;
    const double j22 = g + 2.0 * y * y * gp + 6.0 * p1_ * y + 2.0 * p2_ * x;
    const double det = j11 * j22 - j12 * j12;
    if (!(std::abs(det) > 1e-12)) break;  // fold of the distortion map: keep the last iterate
    const double dx = (j22 * fxv - j12 * fyv) / det;
    const double dy = (j11 * fyv - j12 * fxv) / det;
    x -= dx;
    y -= dy;
    if (dx * dx + dy * dy < 1e-26) break;
  }
  return {x, y};
}

}  // namespace ceilnav::host
