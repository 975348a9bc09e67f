#include "nav/map.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

namespace ceilnav::nav {

TapePrediction predict_tape(const TapeSegment& segment, const Pose2& camera,
                            double measured_yaw_rad) {
  const Eigen::Vector2d dir = segment.b - segment.a;
  const double phi = std::atan2(dir.y(), dir.x());
  const Eigen::Vector2d p(camera.x_m, camera.y_m);
  TapePrediction best;
  double best_miss = 0.0;
  for (int branch = 0; branch < 2; ++branch) {
    const double d = phi + branch * std::numbers::pi;
    const Eigen::Vector2d n(-std::sin(d), std::cos(d));
    TapePrediction t;
    t.branch = branch;
    t.h = {wrap_angle(camera.yaw_rad - d), n.dot(p - segment.a)};
    t.jacobian << 0.0, 0.0, 1.0, n.x(), n.y(), 0.0;
    const double miss = std::abs(wrap_angle(measured_yaw_rad - t.h(0)));
    if (branch == 0 || miss < best_miss) {
      best = t;
      best_miss = miss;
    }
  }
  return best;
}

Eigen::Vector2d tape_innovation(const TapeMeasurement& m, const TapePrediction& p) {
  return {wrap_angle(m.yaw_rad - p.h(0)), m.offset_m - p.h(1)};
}

double distance_to_segment(const Eigen::Vector2d& p, const TapeSegment& s) {
  const Eigen::Vector2d ab = s.b - s.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - s.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (s.a + t * ab)).norm();
}

std::optional<Association> TapeMap::associate(const TapeMeasurement& m, const Pose2& camera,
                                              const Eigen::Matrix3d& camera_cov,
                                              const AssociationOptions& opt) const {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(camera_cov.topLeftCorner<2, 2>(),
                                                           Eigen::EigenvaluesOnly);
  const double reach =
      opt.view_radius_m + opt.gate_sigmas * std::sqrt(std::max(0.0, eig.eigenvalues()(1)));
  const Eigen::Vector2d p(camera.x_m, camera.y_m);
  std::optional<Association> best;
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    if (distance_to_segment(p, segments_[i]) > reach) continue;
    Association a;
    a.segment = static_cast<int>(i);
    a.prediction = predict_tape(segments_[i], camera, m.yaw_rad);
    a.innovation = tape_innovation(m, a.prediction);
    const Eigen::Matrix<double, 2, 3>& h = a.prediction.jacobian;
    a.innovation_covariance = h * camera_cov * h.transpose() + m.covariance;
    a.mahalanobis2 = a.innovation.dot(a.innovation_covariance.ldlt().solve(a.innovation));
    if (!best || a.mahalanobis2 < best->mahalanobis2) best = a;
  }
  return best;
}

std::optional<Eigen::Vector2d> TapeMap::along_direction(const Eigen::Vector2d& point,
                                                        double yaw_rad, double reach_m) const {
  const Eigen::Vector2d heading(std::cos(yaw_rad), std::sin(yaw_rad));
  std::optional<Eigen::Vector2d> best;
  double best_dot = -1.0;
  for (const TapeSegment& s : segments_) {
    if (distance_to_segment(point, s) > reach_m) continue;
    Eigen::Vector2d d = (s.b - s.a).normalized();
    if (d.dot(heading) < 0.0) d = -d;
    if (d.dot(heading) > best_dot) {
      best_dot = d.dot(heading);
      best = d;
    }
  }
  return best;
}

}  // namespace ceilnav::nav
