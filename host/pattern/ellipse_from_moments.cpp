#include "host/pattern/ellipse_from_moments.hpp"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <numbers>

namespace ceilnav::host::pattern {

namespace {

constexpr double kPi = std::numbers::pi;

// Centroid and covariance (pixels) -> normalised: the centroid through the
// model, the covariance through the Jacobian of the undistortion there
// (central differences, 1 px).
bool to_normalised(const CameraModel& camera, double u, double v, const Eigen::Matrix2d& cov_px,
                   Eigen::Vector2d& c, Eigen::Matrix2d& cov) {
  c = camera.normalise(u, v);
  Eigen::Matrix2d jac;
  jac.col(0) = 0.5 * (camera.normalise(u + 1.0, v) - camera.normalise(u - 1.0, v));
  jac.col(1) = 0.5 * (camera.normalise(u, v + 1.0) - camera.normalise(u, v - 1.0));
  cov = jac * cov_px * jac.transpose();
  return cov.allFinite() && c.allFinite();
}

// Area, centroid and central second moments (pixels) of the region bounded by
// the lens-distorted image of the ellipse (c, cov) given in normalised
// coordinates: a 720-gon through the model, moments by Green's theorem.
bool distorted_region_moments(const CameraModel& camera, const Eigen::Vector2d& c,
                              const Eigen::Matrix2d& cov, double& u, double& v,
                              Eigen::Matrix2d& cov_px) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  if (!(es.eigenvalues()(0) > 0.0)) return false;
  const Eigen::Vector2d ax0 = 2.0 * std::sqrt(es.eigenvalues()(0)) * es.eigenvectors().col(0);
  const Eigen::Vector2d ax1 = 2.0 * std::sqrt(es.eigenvalues()(1)) * es.eigenvectors().col(1);
  constexpr int kVertices = 720;
  std::array<Eigen::Vector2d, kVertices> p;
  for (int k = 0; k < kVertices; ++k) {
    const double t = 2.0 * kPi * k / kVertices;
    p[static_cast<std::size_t>(k)] =
        camera.distort_to_pixel(c + std::cos(t) * ax1 + std::sin(t) * ax0);
    if (!p[static_cast<std::size_t>(k)].allFinite()) return false;
  }
  // Moments about the first vertex's neighbourhood (the mean) for precision.
  Eigen::Vector2d o = Eigen::Vector2d::Zero();
  for (const auto& q : p) o += q;
  o /= kVertices;
  double a = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (int k = 0; k < kVertices; ++k) {
    const Eigen::Vector2d p0 = p[static_cast<std::size_t>(k)] - o;
    const Eigen::Vector2d p1 = p[static_cast<std::size_t>((k + 1) % kVertices)] - o;
    const double cr = p0.x() * p1.y() - p1.x() * p0.y();
    a += cr;
    sx += cr * (p0.x() + p1.x());
    sy += cr * (p0.y() + p1.y());
    sxx += cr * (p0.x() * p0.x() + p0.x() * p1.x() + p1.x() * p1.x());
    syy += cr * (p0.y() * p0.y() + p0.y() * p1.y() + p1.y() * p1.y());
    sxy += cr * (p0.x() * p1.y() + 2.0 * p0.x() * p0.y() + 2.0 * p1.x() * p1.y() + p1.x() * p0.y());
  }
  a *= 0.5;
  if (!(std::abs(a) > 0.0)) return false;
  const double mx = sx / (6.0 * a), my = sy / (6.0 * a);
  cov_px(0, 0) = sxx / (12.0 * a) - mx * mx;
  cov_px(1, 1) = syy / (12.0 * a) - my * my;
  cov_px(0, 1) = cov_px(1, 0) = sxy / (24.0 * a) - mx * my;
  u = mx + o.x();
  v = my + o.y();
  return cov_px.allFinite();
}

}  // namespace

// Eq. 17-18: b, a = 2 sqrt(eigenvalues) (the seed's form divided by mu00 / 2);
// psi is the minor axis (eigenvector of the smaller eigenvalue) from image up
// toward +x, in [0, pi).
std::optional<Ellipse> ellipse_from_covariance(const Eigen::Vector2d& c,
                                               const Eigen::Matrix2d& cov) {
  const double tr = cov(0, 0) + cov(1, 1);
  const double disc = std::hypot(cov(0, 0) - cov(1, 1), 2.0 * cov(0, 1));
  const double l1 = 0.5 * (tr + disc), l2 = 0.5 * (tr - disc);
  if (!(l2 > 0.0)) return std::nullopt;
  Ellipse e;
  e.cx = c.x();
  e.cy = c.y();
  e.b = 2.0 * std::sqrt(l1);
  e.a = 2.0 * std::sqrt(l2);
  e.cov = cov;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  const Eigen::Vector2d minor = es.eigenvectors().col(0);
  e.psi = std::fmod(std::atan2(minor.x(), -minor.y()) + 2.0 * kPi, kPi);
  return e;
}

std::optional<Ellipse> ellipse_from_moments(const ClassMoments& m, const CameraModel& camera) {
  if (m.m00 < 5) return std::nullopt;
  const double n = static_cast<double>(m.m00);
  const double u = static_cast<double>(m.m10) / n, v = static_cast<double>(m.m01) / n;
  // Eq. 30-32 (divided by mu00): central second moments in pixels^2, plus
  // Sheppard's 1/12 px^2: the moments of pixel centres are those of the
  // region less the spread of one pixel (docs/pattern.md).
  const double c20 = static_cast<double>(m.m20) / n - u * u + 1.0 / 12.0;
  const double c11 = static_cast<double>(m.m11) / n - u * v;
  const double c02 = static_cast<double>(m.m02) / n - v * v + 1.0 / 12.0;
  Eigen::Matrix2d cov_px;
  cov_px << c20, c11, c11, c02;
  Eigen::Vector2d c;
  Eigen::Matrix2d cov;
  if (!to_normalised(camera, u, v, cov_px, c, cov)) return std::nullopt;
  if (camera.has_distortion()) {
    // The disc's image is an ellipse in undistorted coordinates, not in
    // pixels: refine (c, cov) until the distorted image of that ellipse has
    // the measured pixel moments (fixed point; the affine map above is the
    // first step).
    const Eigen::Vector2d c_meas = c;
    const Eigen::Matrix2d cov_meas = cov;
    for (int iteration = 0; iteration < 6; ++iteration) {
      double pu = 0, pv = 0;
      Eigen::Matrix2d pcov;
      Eigen::Vector2d pc;
      Eigen::Matrix2d pcn;
      if (!distorted_region_moments(camera, c, cov, pu, pv, pcov)) break;
      if (!to_normalised(camera, pu, pv, pcov, pc, pcn)) break;
      c += c_meas - pc;
      cov += cov_meas - pcn;
      if ((c_meas - pc).norm() < 1e-12 && (cov_meas - pcn).norm() < 1e-14) break;
    }
  }
  return ellipse_from_covariance(c, cov);
}

}  // namespace ceilnav::host::pattern
