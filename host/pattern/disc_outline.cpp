#include "host/pattern/disc_outline.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace ceilnav::host::pattern {

std::pair<std::vector<stream::RunRecord>, std::vector<stream::RunRecord>> split_disc_runs(
    std::span<const stream::RunRecord> runs, const ClassMoments& disc) {
  std::pair<std::vector<stream::RunRecord>, std::vector<stream::RunRecord>> out;
  Eigen::Matrix2d shape_inv = Eigen::Matrix2d::Zero();
  double u = 0, v = 0;
  bool have = disc.m00 >= 5;
  if (have) {
    const double n = static_cast<double>(disc.m00);
    u = static_cast<double>(disc.m10) / n;
    v = static_cast<double>(disc.m01) / n;
    Eigen::Matrix2d cov;
    cov << static_cast<double>(disc.m20) / n - u * u + 1.0 / 12.0,
        static_cast<double>(disc.m11) / n - u * v, static_cast<double>(disc.m11) / n - u * v,
        static_cast<double>(disc.m02) / n - v * v + 1.0 / 12.0;
    // The ellipse x^T (4 cov)^-1 x <= 1, enlarged 1.1 x.
    const Eigen::Matrix2d shape = 4.0 * 1.21 * cov;
    have = shape.determinant() > 0.0 && shape(0, 0) > 0.0;
    if (have) shape_inv = shape.inverse();
  }
  for (const auto& r : runs) {
    const Eigen::Vector2d d(0.5 * (r.x_start + r.x_end) - u, static_cast<double>(r.row) - v);
    if (have && d.dot(shape_inv * d) <= 1.0) {
      out.first.push_back(r);
    } else {
      out.second.push_back(r);
    }
  }
  return out;
}

namespace {

// Fewer usable rows: the disc is too flat in the image for row chords (its
// edges shallow over most of the outline); the moments' ellipse is kept.
constexpr std::size_t kMinOutlineRows = 24;
// Rows whose chord needs a larger curvature correction (px) are left out.
constexpr double kMaxChordCorrection = 0.3;

// Integral of round(t) over [a, a + len] (round half up): t^2 / 2 less the
// periodic part (t - round(t))^2 / 2.
double round_integral(double a, double len) {
  auto prim = [](double t) {
    const double f = t - std::floor(t + 0.5);
    return 0.5 * t * t - 0.5 * f * f;
  };
  return prim(a + len) - prim(a);
}

}  // namespace

std::optional<Ellipse> ellipse_from_disc_runs(std::span<const stream::RunRecord> disc_runs,
                                              const ClassMoments& disc, uint32_t k, int width,
                                              double psf_sigma_px, const CameraModel& camera) {
  if (k == 0 || disc.m00 < 5 || disc_runs.size() < 12) return std::nullopt;
  const double n = static_cast<double>(disc.m00);
  const double u0 = static_cast<double>(disc.m10) / n, v0 = static_cast<double>(disc.m01) / n;
  const double c20 = static_cast<double>(disc.m20) / n - u0 * u0 + 1.0 / 12.0;
  const double c11 = static_cast<double>(disc.m11) / n - u0 * v0;
  const double c02 = static_cast<double>(disc.m02) / n - v0 * v0 + 1.0 / 12.0;
  Eigen::Matrix2d shape;  // x^T shape x = 1 on the outline (pixels)
  shape << 4.0 * c20, 4.0 * c11, 4.0 * c11, 4.0 * c02;
  if (!(shape.determinant() > 0.0)) return std::nullopt;
  const Eigen::Matrix2d mm = shape.inverse();
  const double m11 = mm(0, 0), det = mm.determinant();
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(2 * disc_runs.size());
  for (const auto& r : disc_runs) {
    if (r.x_start == 0 || r.x_end + 1 >= width || r.sum_w == 0) continue;
    const double y = static_cast<double>(r.row) - v0;
    // Half-width h(y) = sqrt(m11 - det y^2) / m11 about the chord's midpoint;
    // keep rows whose strip lies 1 px inside the top and bottom.
    const double g_lo = m11 - det * (std::abs(y) + 1.5) * (std::abs(y) + 1.5);
    if (!(g_lo > 0.0)) continue;
    const double g = m11 - det * y * y;
    const double h2 = (-det / std::sqrt(g) - det * det * y * y / (g * std::sqrt(g))) / m11;
    const double len_strip = static_cast<double>(r.sum_w) / k;
    const double s = static_cast<double>(r.sum_xw) / k;
    // Left edge a of [a, a + len] with integral of round(t) = s (monotone in a).
    double a = s / len_strip - 0.5 * len_strip;
    for (int it = 0; it < 20; ++it) {
      const double step = (s - round_integral(a, len_strip)) / len_strip;
      a += step;
      if (std::abs(step) < 1e-9) break;
    }
    // The strip's mean chord, through the lens's blur (Gaussian, psf_sigma_px
    // rows), is the centre line's plus chord'' (1 / 24 + sigma^2 / 2).
    const double bias = 2.0 * h2 * (1.0 / 24.0 + 0.5 * psf_sigma_px * psf_sigma_px);
    if (std::abs(bias) > kMaxChordCorrection) continue;
    const double len = len_strip - bias;
    a -= 0.5 * (len - len_strip);
    pts.push_back(camera.normalise(a, static_cast<double>(r.row)));
    pts.push_back(camera.normalise(a + len, static_cast<double>(r.row)));
  }
  if (pts.size() < 2 * kMinOutlineRows) return std::nullopt;
  // Conic A x^2 + B xy + C y^2 + D x + E y + F = 0 about the points' mean,
  // scaled; smallest singular vector, reweighted by 1 / |grad|^2 (Sampson).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  double scale = 0.0;
  for (const auto& p : pts) scale += (p - mean).norm();
  scale = static_cast<double>(pts.size()) / scale;
  Eigen::VectorXd coef(6);
  std::vector<double> wts(pts.size(), 1.0);
  for (int pass = 0; pass < 4; ++pass) {
    Eigen::MatrixXd a_mat(pts.size(), 6);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector2d q = (pts[i] - mean) * scale;
      a_mat.row(static_cast<Eigen::Index>(i)) << q.x() * q.x(), q.x() * q.y(), q.y() * q.y(), q.x(),
          q.y(), 1.0;
      a_mat.row(static_cast<Eigen::Index>(i)) *= wts[i];
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a_mat, Eigen::ComputeThinV);
    coef = svd.matrixV().col(5);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector2d q = (pts[i] - mean) * scale;
      const double gx = 2.0 * coef(0) * q.x() + coef(1) * q.y() + coef(3);
      const double gy = coef(1) * q.x() + 2.0 * coef(2) * q.y() + coef(4);
      wts[i] = 1.0 / std::max(1e-9, std::sqrt(gx * gx + gy * gy));
    }
  }
  // Back to normalised coordinates: centre and shape matrix.
  Eigen::Matrix2d mq;
  mq << coef(0), 0.5 * coef(1), 0.5 * coef(1), coef(2);
  if (!(mq.determinant() > 0.0)) return std::nullopt;
  const Eigen::Vector2d lin(coef(3), coef(4));
  const Eigen::Vector2d cq = -0.5 * mq.inverse() * lin;
  const double rhs = cq.dot(mq * cq) - coef(5);
  if (!(rhs / mq.trace() > 0.0)) return std::nullopt;
  // (q - cq)^T (mq / rhs) (q - cq) = 1, q = (x - mean) * scale.
  const Eigen::Matrix2d m_norm = mq / rhs * scale * scale;
  const Eigen::Vector2d c = mean + cq / scale;
  return ellipse_from_covariance(c, 0.25 * m_norm.inverse());
}

}  // namespace ceilnav::host::pattern
