#include "host/pattern/bar_refinement.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "host/pattern/circle_pose.hpp"
#include "host/pattern/pattern_axes.hpp"

namespace ceilnav::host::pattern {

namespace {

constexpr double kPi = std::numbers::pi;

// The image of the pattern's disc for a pose (centre t, axes a of the pattern
// in the camera) as fit_disc_coverage's parameters (centre, S = 4 cov):
// the unit circle's conic diag(1, 1, -1) through H = [R a1, R a2, t].
std::optional<Eigen::Matrix<double, 5, 1>> disc_image_params(const Eigen::Matrix3d& a,
                                                             const Eigen::Vector3d& t, double r) {
  Eigen::Matrix3d h;
  h.col(0) = r * a.col(0);
  h.col(1) = r * a.col(1);
  h.col(2) = t;
  const Eigen::Matrix3d hi = h.inverse();
  const Eigen::Matrix3d q = hi.transpose() * Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal() * hi;
  const Eigen::Matrix2d m = q.topLeftCorner<2, 2>();
  if (!(std::abs(m.determinant()) > 0.0) || !q.allFinite()) return std::nullopt;
  const Eigen::Vector2d x0 = -m.inverse() * q.topRightCorner<2, 1>();
  const Eigen::Matrix2d s = (x0.dot(m * x0) - q(2, 2)) * m.inverse();
  Eigen::Matrix<double, 5, 1> e;
  e << x0.x(), x0.y(), s(0, 0), s(0, 1), s(1, 1);
  return e;
}

// The least-squares problem of refine_with_bars: each usable bar centroid's
// distance to the image of its bar's edges (rows about their bar's mean, each
// bar's mean with a common error) and the disc prior (its fitted image with
// the fit's covariance, or the conic's centre and normal), over the pattern's
// rotation, translation and a common shift along the pattern's x.
class BarPoseFit {
 public:
  BarPoseFit(const PatternPose& conic, std::span<const BarEdge> edges, const CameraModel& camera,
             const PoseOptions& o)
      : edges_(edges), o_(o), c0_(conic.centre_cam), n0_(conic.normal_cam) {
    const double f = std::sqrt(camera.fx() * camera.fy());
    // Per row, a bar's ink centroid scatters by about 0.15 px; every row of one
    // bar shares the same pixel phase, so the bar's mean carries a common error
    // of about 0.03 px that its rows do not average away (docs/pattern.md).
    sigma_row_ = 0.15 / f;  // normalised units
    sigma_bar_ = 0.03 / f;
    // The disc: with the coverage fit's covariance the prior is the disc's own
    // image (5 constraints on the pose, weighted by what the fit measured);
    // without it, the conic's centre (0.3 % of D in each coordinate) and normal
    // (1 deg).
    sigma_slide_ = 0.003 * conic.centre_cam.norm();
    sigma_normal_ = 1.0 * kPi / 180.0;
    const Eigen::Matrix<double, 5, 5>& pc = conic.ellipse.param_cov;
    e_meas_ << conic.ellipse.cx, conic.ellipse.cy, 4.0 * conic.ellipse.cov(0, 0),
        4.0 * conic.ellipse.cov(0, 1), 4.0 * conic.ellipse.cov(1, 1);
    disc_llt_.compute(pc);
    disc_prior_ = (pc.array() != 0.0).any() && disc_llt_.info() == Eigen::Success;
    // Bars narrower than 2 px are left out: their gaps are about as narrow, so
    // the run's one-pixel margin takes in the neighbours' ink and biases the
    // centroid (measured: up to 0.6 % in D at 3 m, 67.5 deg).
    bar_of_.assign(edges.size(), -1);
    std::map<double, int> bar_index;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (edges[i].width * f < 2.0) continue;
      bar_of_[i] =
          bar_index.try_emplace(edges[i].x0_m, static_cast<int>(bar_index.size())).first->second;
      ++used_;
    }
    n_bars_ = bar_index.size();
    const std::size_t n_prior = disc_prior_ ? 5 : 6;
    n_res_ = edges.size() + n_bars_ + n_prior + 1;
    weight_.assign(edges.size(), 1.0);
  }

  // Edges of bars wide enough to use.
  std::size_t used() const { return used_; }
  // Whether the disc prior is the coverage fit's image (else centre and normal).
  bool disc_prior() const { return disc_prior_; }

  // Gauss-Newton from the start pose (a, t); the robust cost at the end
  // (Huber at 3 sigma on the rows, squares elsewhere) to compare starts.
  // False when a step or the result is not finite or the disc is behind.
  bool solve(Eigen::Matrix3d& a, Eigen::Vector3d& t, double& cost) {
    double bias = 0.0;  // metres: a common shift along x (pattern printing offset)
    std::fill(weight_.begin(), weight_.end(), 1.0);
    Eigen::VectorXd r0, r1;
    for (int iteration = 0; iteration < 12; ++iteration) {
      residuals(a, t, bias, r0);
      // Robust: down-weight rows beyond 3 sigma of their bar's mean (once per iteration).
      for (std::size_t i = 0; i < edges_.size(); ++i) {
        if (bar_of_[i] < 0) continue;
        const double ri = std::abs(r0(static_cast<Eigen::Index>(i))) / weight_[i];
        weight_[i] = ri > 3.0 ? 3.0 / ri : 1.0;
      }
      residuals(a, t, bias, r0);
      Eigen::MatrixXd jac(static_cast<Eigen::Index>(n_res_), 7);
      const double steps[7] = {1e-6, 1e-6, 1e-6, 1e-6 * t.norm(), 1e-6 * t.norm(), 1e-6 * t.norm(),
                               1e-6};
      for (int j = 0; j < 7; ++j) {
        Eigen::Matrix<double, 7, 1> d = Eigen::Matrix<double, 7, 1>::Zero();
        d(j) = steps[j];
        Eigen::Matrix3d a2;
        Eigen::Vector3d t2;
        double b2 = 0.0;
        apply(a, t, bias, d, a2, t2, b2);
        residuals(a2, t2, b2, r1);
        jac.col(j) = (r1 - r0) / steps[j];
      }
      Eigen::Matrix<double, 7, 7> h = jac.transpose() * jac;
      h.diagonal() *= 1.0 + 1e-9;
      const Eigen::Matrix<double, 7, 1> g = jac.transpose() * r0;
      const Eigen::Matrix<double, 7, 1> delta = -h.ldlt().solve(g);
      if (!delta.allFinite()) return false;
      apply(a, t, bias, delta, a, t, bias);
      if (delta.head<3>().norm() < 1e-10 && delta.segment<3>(3).norm() < 1e-10 * t.norm()) break;
    }
    if (!a.allFinite() || !t.allFinite() || !(t.z() > 0.0)) return false;
    std::fill(weight_.begin(), weight_.end(), 1.0);
    residuals(a, t, bias, r0);
    cost = 0.0;
    for (Eigen::Index i = 0; i < r0.size(); ++i) {
      const double z = std::abs(r0(i));
      cost += i < static_cast<Eigen::Index>(edges_.size()) && z > 3.0 ? 6.0 * z - 9.0 : z * z;
    }
    return true;
  }

 private:
  // Residuals (scaled by their sigmas) of the pattern axes aa, centre tt and
  // shift bb along the pattern's x.
  void residuals(const Eigen::Matrix3d& aa, const Eigen::Vector3d& tt, double bb,
                 Eigen::VectorXd& r) const {
    r.setZero(static_cast<Eigen::Index>(n_res_));
    const Eigen::Vector3d a1 = aa.col(0), a2 = aa.col(1), a3 = aa.col(2);
    std::vector<double> dist(edges_.size(), 0.0), sum(n_bars_, 0.0), wsum(n_bars_, 0.0);
    for (std::size_t i = 0; i < edges_.size(); ++i) {
      if (bar_of_[i] < 0) continue;
      const BarEdge& e = edges_[i];
      // The ink centroid along the row is the midpoint of the bar's two
      // projected edges (not the projection of its centre line): the mean
      // of the signed distances to the two edge lines vanishes there.
      double d = 0.0;
      for (const double xe : {e.x0_m, e.x1_m}) {
        const Eigen::Vector3d l = (tt + (xe + bb) * a1).cross(a2);
        const double norm = std::sqrt(l.x() * l.x() + l.y() * l.y());
        d += norm > 0.0 ? 0.5 * (l.x() * e.x + l.y() * e.y + l.z()) / norm : 0.0;
      }
      dist[i] = d;
      const auto b = static_cast<std::size_t>(bar_of_[i]);
      sum[b] += weight_[i] * d;
      wsum[b] += weight_[i];
    }
    // Each row about its bar's mean; each bar's mean against its own sigma.
    for (std::size_t i = 0; i < edges_.size(); ++i) {
      if (bar_of_[i] < 0) continue;
      const auto b = static_cast<std::size_t>(bar_of_[i]);
      r(static_cast<Eigen::Index>(i)) = weight_[i] * (dist[i] - sum[b] / wsum[b]) / sigma_row_;
    }
    auto k = static_cast<Eigen::Index>(edges_.size());
    for (std::size_t b = 0; b < n_bars_; ++b, ++k) {
      if (wsum[b] > 0.0) {
        r(k) = sum[b] / wsum[b] /
               std::sqrt(sigma_bar_ * sigma_bar_ + sigma_row_ * sigma_row_ / wsum[b]);
      }
    }
    if (disc_prior_) {
      const auto e = disc_image_params(aa, tt, o_.radius_m);
      r.segment<5>(k) = e ? Eigen::Matrix<double, 5, 1>(disc_llt_.matrixL().solve(*e - e_meas_))
                          : Eigen::Matrix<double, 5, 1>::Constant(1e6);
    } else {
      r.segment<3>(k) = (tt - c0_) / sigma_slide_;
      r.segment<3>(k + 3) = (a3 - n0_) / sigma_normal_;
    }
    r(static_cast<Eigen::Index>(n_res_) - 1) =
        bb / 1e-4;  // a shift along x is a translation along a1: pinned
  }

  // The pose after the step d (rotation vector, translation, shift).
  static void apply(const Eigen::Matrix3d& aa, const Eigen::Vector3d& tt, double bb,
                    const Eigen::Matrix<double, 7, 1>& d, Eigen::Matrix3d& a2, Eigen::Vector3d& t2,
                    double& b2) {
    const Eigen::Vector3d w = d.head<3>();
    const double angle = w.norm();
    a2 = angle > 0.0 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, w / angle) * aa) : aa;
    t2 = tt + d.segment<3>(3);
    b2 = bb + d(6);
  }

  std::span<const BarEdge> edges_;
  const PoseOptions& o_;
  Eigen::Vector3d c0_, n0_;
  double sigma_row_ = 0, sigma_bar_ = 0, sigma_slide_ = 0, sigma_normal_ = 0;
  Eigen::Matrix<double, 5, 1> e_meas_;
  Eigen::LLT<Eigen::Matrix<double, 5, 5>> disc_llt_;
  bool disc_prior_ = false;
  std::vector<int> bar_of_;  // bar number of each edge, -1: not used
  std::size_t used_ = 0, n_bars_ = 0, n_res_ = 0;
  std::vector<double> weight_;  // robust weights of the rows
};

}  // namespace

PatternPose refine_with_bars(const PatternPose& conic, std::span<const BarEdge> edges,
                             const CameraModel& camera, const PoseOptions& o) {
  if ((conic.status != PatternStatus::ok && conic.status != PatternStatus::ambiguous) ||
      edges.size() < 48) {
    return conic;
  }
  const auto axes0 = pattern_axes_cam(conic.normal_cam, o.up_cam);
  if (!axes0) return conic;
  BarPoseFit fit(conic, edges, camera, o);
  if (fit.used() < 48) return conic;
  const Eigen::Vector3d c0 = conic.centre_cam, n0 = conic.normal_cam;
  // Starts: the conic's pose and, with the disc's own prior, the other circle
  // pose of the same ellipse (the seed's two-way ambiguity, eq. 14): the
  // bars' perspective tells them apart where no side wall shows.
  struct Start {
    Eigen::Matrix3d a;
    Eigen::Vector3d t;
    Eigen::Vector3d n0;
  };
  std::vector<Start> starts{{*axes0, c0, n0}};
  if (fit.disc_prior()) {
    if (const auto cp = mirror_pose(conic, o.radius_m)) {
      const auto ax = pattern_axes_cam(cp->normal, o.up_cam);
      if (ax) starts.push_back({*ax, cp->centre, cp->normal});
    }
  }
  double best_cost = std::numeric_limits<double>::infinity(), other_cost = best_cost;
  std::optional<std::pair<Eigen::Matrix3d, Eigen::Vector3d>> best;
  for (Start& st : starts) {
    double cost = 0.0;
    if (!fit.solve(st.a, st.t, cost)) continue;
    // A fit that wandered far from its start is not trusted.
    if (std::abs(st.t.norm() / c0.norm() - 1.0) > 0.05 ||
        st.a.col(2).dot(st.n0) < std::cos(5.0 * kPi / 180.0)) {
      continue;
    }
    if (cost < best_cost) {
      other_cost = best_cost;
      best_cost = cost;
      best = {st.a, st.t};
    } else {
      other_cost = std::min(other_cost, cost);
    }
  }
  if (!best) return conic;
  PatternPose p = conic;
  p.centre_cam = best->second;
  p.normal_cam = best->first.col(2);
  p.up_cam = best->first.col(1);
  spherical_from_pose(best->second, best->first, p);
  // Resolved by the bars when the other start fits worse by > 5 sigma.
  if (starts.size() == 2 && other_cost - best_cost > 25.0 && !p.beta_resolved) {
    p.beta_resolved = true;
    p.status = PatternStatus::ok;
  }
  return p;
}

}  // namespace ceilnav::host::pattern
