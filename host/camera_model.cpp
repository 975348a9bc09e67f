#include "host/camera_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace ceilnav::host {
namespace {

constexpr double kResidualTol = 1e-13;  // |F| per coordinate, normalised
constexpr double kMinDet = 1e-12;
constexpr double kMinStep2 = 1e-26;
constexpr int kMaxNewtonIterations = 20;

struct Coeffs {
  double k1, k2, p1, p2, k3;
};

// Newton on F(x, y) = distort(x, y) - (xd, yd), on a double or lane-wise on a
// GCC vector of doubles: the same operations in the same order, so the same
// roundings (no contraction into FMA: no target here enables it).
template <typename T>
struct Residual {
  T r2, g, fx, fy;  // x^2 + y^2, the radial gain, F
};

template <typename T>
[[gnu::always_inline]] inline Residual<T> residual(const Coeffs& c, const T& xd, const T& yd,
                                                   const T& x, const T& y) {
  Residual<T> f;
  f.r2 = x * x + y * y;
  f.g = 1.0 + f.r2 * (c.k1 + f.r2 * (c.k2 + f.r2 * c.k3));
  f.fx = x * f.g + 2.0 * c.p1 * x * y + c.p2 * (f.r2 + 2.0 * x * x) - xd;
  f.fy = y * f.g + c.p1 * (f.r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y - yd;
  return f;
}

template <typename T>
struct Step {
  T det, dx, dy;  // Jacobian determinant, the step J^-1 F
};

// With g' = dg/dr2:
//   dXd/dx = g + 2 x^2 g' + 2 p1 y + 6 p2 x    dXd/dy = 2 x y g' + 2 p1 x + 2 p2 y
//   dYd/dx = 2 x y g' + 2 p1 x + 2 p2 y        dYd/dy = g + 2 y^2 g' + 6 p1 y + 2 p2 x
template <typename T>
[[gnu::always_inline]] inline Step<T> step(const Coeffs& c, const Residual<T>& f, const T& x,
                                           const T& y) {
  const T gp = c.k1 + f.r2 * (2.0 * c.k2 + 3.0 * f.r2 * c.k3);
  const T j11 = f.g + 2.0 * x * x * gp + 2.0 * c.p1 * y + 6.0 * c.p2 * x;
  const T j12 = 2.0 * x * y * gp + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
  const T j22 = f.g + 2.0 * y * y * gp + 6.0 * c.p1 * y + 2.0 * c.p2 * x;
  Step<T> s;
  s.det = j11 * j22 - j12 * j12;
  s.dx = (j22 * f.fx - j12 * f.fy) / s.det;
  s.dy = (j11 * f.fy - j12 * f.fx) / s.det;
  return s;
}

// The scalar iteration (CameraModel::newton).
Eigen::Vector2d newton_scalar(const Coeffs& c, double xd, double yd, double x, double y) {
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    const Residual<double> f = residual(c, xd, yd, x, y);
    if (std::abs(f.fx) < kResidualTol && std::abs(f.fy) < kResidualTol) break;
    const Step<double> s = step(c, f, x, y);
    if (!(std::abs(s.det) > kMinDet)) break;  // fold of the distortion map: keep the last iterate
    x -= s.dx;
    y -= s.dy;
    if (s.dx * s.dx + s.dy * s.dy < kMinStep2) break;
  }
  return {x, y};
}

// newton_scalar on kBlock points side by side in vectors V of doubles (lane
// masks M: -1 true, 0 false). Every lane computes each round; a lane takes
// the update only while newton_scalar would still be iterating.
constexpr size_t kBlock = 16;
struct Block {
  std::array<double, kBlock> xd, yd, x, y;  // start in x, y; result out
  std::array<int64_t, kBlock> live;         // -1: a point, 0: a spare lane
};

template <typename V, typename M>
[[gnu::always_inline]] inline void newton_lanes(const Coeffs& c, Block& b) {
  constexpr size_t kWidth = sizeof(V) / sizeof(double);
  constexpr size_t kVecs = kBlock / kWidth;
  std::array<V, kVecs> xd, yd, x, y;
  std::array<M, kVecs> active;
  for (size_t k = 0; k < kVecs; ++k) {
    __builtin_memcpy(&xd[k], &b.xd[k * kWidth], sizeof(V));
    __builtin_memcpy(&yd[k], &b.yd[k * kWidth], sizeof(V));
    __builtin_memcpy(&x[k], &b.x[k * kWidth], sizeof(V));
    __builtin_memcpy(&y[k], &b.y[k * kWidth], sizeof(V));
    __builtin_memcpy(&active[k], &b.live[k * kWidth], sizeof(M));
  }
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    // Residuals first: the last round stops there, before the Jacobian.
    std::array<Residual<V>, kVecs> f;
    std::array<M, kVecs> go;
    M any{};
    for (size_t k = 0; k < kVecs; ++k) {
      f[k] = residual(c, xd[k], yd[k], x[k], y[k]);
      const M converged = (f[k].fx < kResidualTol) & (f[k].fx > -kResidualTol) &
                          (f[k].fy < kResidualTol) & (f[k].fy > -kResidualTol);
      go[k] = active[k] & ~converged;
      any |= go[k];
    }
    int64_t any_lane = 0;
    for (size_t l = 0; l < kWidth; ++l) any_lane |= any[l];
    if (any_lane == 0) break;
    for (size_t k = 0; k < kVecs; ++k) {
      const Step<V> s = step(c, f[k], x[k], y[k]);
      const M update = go[k] & ((s.det > kMinDet) | (s.det < -kMinDet));
      x[k] = update ? x[k] - s.dx : x[k];
      y[k] = update ? y[k] - s.dy : y[k];
      active[k] = update & ~(s.dx * s.dx + s.dy * s.dy < kMinStep2);
    }
  }
  for (size_t k = 0; k < kVecs; ++k) {
    __builtin_memcpy(&b.x[k * kWidth], &x[k], sizeof(V));
    __builtin_memcpy(&b.y[k * kWidth], &y[k], sizeof(V));
  }
}

using V2 = double __attribute__((vector_size(16)));
using M2 = int64_t __attribute__((vector_size(16)));

void newton_block_sse2(const Coeffs& c, Block& b) {
  newton_lanes<V2, M2>(c, b);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define CEILNAV_NEWTON_AVX 1
using V4 = double __attribute__((vector_size(32)));
using M4 = int64_t __attribute__((vector_size(32)));

// Four lanes per instruction where the CPU has AVX (checked at run time; the
// build targets baseline x86-64). AVX alone has no FMA: same roundings.
__attribute__((target("avx"))) void newton_block_avx(const Coeffs& c, Block& b) {
  newton_lanes<V4, M4>(c, b);
}
#endif

void newton_block(const Coeffs& c, Block& b) {
#if CEILNAV_NEWTON_AVX
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) {
    newton_block_avx(c, b);
    return;
  }
#endif
  newton_block_sse2(c, b);
}

}  // namespace

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

inline void CameraModel::newton_start(double u_px, double v_px, double& xd, double& yd, double& x,
                                      double& y) const {
  xd = (u_px - cx_) * inv_fx_;
  yd = (v_px - cy_) * inv_fy_;
  x = xd;
  y = yd;
  const double gu = (u_px + 1.0) / kGridStep, gv = (v_px + 1.0) / kGridStep;
  if (gu >= 0.0 && gv >= 0.0 && gu < grid_cols_ - 1 && gv < grid_rows_ - 1) {
    const int i = static_cast<int>(gu), j = static_cast<int>(gv);
    const double a = gu - i, b = gv - j;
    const size_t k = static_cast<size_t>(j * grid_cols_ + i);
    const size_t cols = static_cast<size_t>(grid_cols_);
    const Eigen::Vector2d g = (1.0 - b) * ((1.0 - a) * grid_[k] + a * grid_[k + 1]) +
                              b * ((1.0 - a) * grid_[k + cols] + a * grid_[k + cols + 1]);
    x = g.x();
    y = g.y();
  }
}

Eigen::Vector2d CameraModel::newton(double xd, double yd, double x, double y) const {
  return newton_scalar({k1_, k2_, p1_, p2_, k3_}, xd, yd, x, y);
}

Eigen::Vector2d CameraModel::normalise(double u_px, double v_px) const {
  if (!has_distortion_) return {(u_px - cx_) * inv_fx_, (v_px - cy_) * inv_fy_};
  double xd = 0.0, yd = 0.0, x = 0.0, y = 0.0;
  newton_start(u_px, v_px, xd, yd, x, y);
  return newton(xd, yd, x, y);
}

void CameraModel::normalise(std::span<const double> u_px, std::span<const double> v_px,
                            std::span<double> x_out, std::span<double> y_out) const {
  const size_t n = u_px.size();
  if (v_px.size() != n || x_out.size() != n || y_out.size() != n) {
    throw std::invalid_argument("CameraModel::normalise: spans of different sizes");
  }
  if (!has_distortion_) {
    for (size_t i = 0; i < n; ++i) {
      x_out[i] = (u_px[i] - cx_) * inv_fx_;
      y_out[i] = (v_px[i] - cy_) * inv_fy_;
    }
    return;
  }
  const Coeffs c{k1_, k2_, p1_, p2_, k3_};
  Block b;
  for (size_t base = 0; base < n; base += kBlock) {
    const size_t lanes = std::min(kBlock, n - base);
    for (size_t l = 0; l < kBlock; ++l) {
      const size_t i = base + std::min(l, lanes - 1);  // spare lanes repeat a point
      newton_start(u_px[i], v_px[i], b.xd[l], b.yd[l], b.x[l], b.y[l]);
      b.live[l] = l < lanes ? -1 : 0;
    }
    newton_block(c, b);
    for (size_t l = 0; l < lanes; ++l) {
      x_out[base + l] = b.x[l];
      y_out[base + l] = b.y[l];
    }
  }
}

}  // namespace ceilnav::host
