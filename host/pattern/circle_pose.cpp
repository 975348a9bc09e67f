#include "host/pattern/circle_pose.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace ceilnav::host::pattern {

Eigen::Matrix3d conic_from_ellipse(const Ellipse& e) {
  // Uniform ellipse {x : (x - c)^T M (x - c) <= 1} has covariance M^-1 / 4.
  const Eigen::Matrix2d mm = (4.0 * e.cov).inverse();
  const Eigen::Vector2d c(e.cx, e.cy);
  Eigen::Matrix3d q;
  q.topLeftCorner<2, 2>() = mm;
  q.topRightCorner<2, 1>() = -mm * c;
  q.bottomLeftCorner<1, 2>() = (-mm * c).transpose();
  q(2, 2) = c.dot(mm * c) - 1.0;
  return q;
}

std::vector<CirclePose> circle_poses_from_conic(const Eigen::Matrix3d& q_in, double r) {
  std::vector<CirclePose> out;
  if (!q_in.allFinite() || !(r > 0.0)) return out;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (q_in + q_in.transpose()));
  Eigen::Vector3d lam = es.eigenvalues();  // ascending
  Eigen::Matrix3d v = es.eigenvectors();
  // Two eigenvalues of one sign, one of the other: make two positive.
  int positive = 0;
  for (int k = 0; k < 3; ++k) positive += lam[k] > 0.0;
  if (positive == 1) {
    lam = -lam;
    lam = Eigen::Vector3d(lam[2], lam[1], lam[0]);
    v = Eigen::Matrix3d(v.rowwise().reverse());
  } else if (positive != 2) {
    return out;
  }
  // Now lam ascending: lam[0] < 0 < lam[1] <= lam[2]. Name l1 >= l2 > 0 > l3.
  const double l1 = lam[2], l2 = lam[1], l3 = lam[0];
  if (!(l3 < 0.0 && l2 > 0.0)) return out;
  const Eigen::Vector3d e1 = v.col(2), e2 = v.col(1), e3 = v.col(0);
  // In the eigenbasis the cone is l1 x^2 + l2 y^2 + l3 z^2 = 0; Q - l2 I
  // factors into the planes sqrt(l1 - l2) x = +-sqrt(l2 - l3) z, and a plane
  // parallel to one of them cuts the cone in a circle (docs/pattern.md).
  const double g = std::sqrt(std::max(0.0, l1 - l2)), h = std::sqrt(l2 - l3);
  for (int sign : {1, -1}) {
    if (sign == -1 && g == 0.0) break;  // frontal circle: one solution
    const Eigen::Vector3d a(g * sign, 0.0, -h), b(g * sign, 0.0, h);
    // Plane a . X = 1 (eigenbasis): on the cone, l2 |X|^2 = -(a . X)(b . X) =
    // -(b . X): the sphere |X|^2 + (b . X) / l2 = 0, centre s = -b / (2 l2).
    const Eigen::Vector3d s = -b / (2.0 * l2);
    const double an2 = a.squaredNorm();
    const Eigen::Vector3d centre1 = s + ((1.0 - a.dot(s)) / an2) * a;
    const double dist2 = std::pow(1.0 - a.dot(s), 2) / an2;
    const double r1sq = s.squaredNorm() - dist2;
    if (!(r1sq > 0.0)) continue;
    double k = r / std::sqrt(r1sq);  // scale of the plane a . X = k
    Eigen::Vector3d centre = k * centre1;
    const Eigen::Vector3d centre_cam =
        v.col(2) * 0.0 + e1 * centre.x() + e2 * centre.y() + e3 * centre.z();
    Eigen::Vector3d c = centre_cam;
    if (c.z() < 0.0) c = -c;  // the other nappe: the circle in front of the camera
    Eigen::Vector3d n = (e1 * a.x() + e2 * a.y() + e3 * a.z()).normalized();
    if (n.dot(c) > 0.0) n = -n;  // toward the camera
    out.push_back({c, n});
  }
  return out;
}

std::optional<CirclePose> mirror_pose(const PatternPose& p, double radius_m) {
  for (const CirclePose& cp : circle_poses_from_conic(conic_from_ellipse(p.ellipse), radius_m)) {
    if (cp.normal.dot(p.normal_cam) < 1.0 - 1e-12) return cp;
  }
  return std::nullopt;
}

}  // namespace ceilnav::host::pattern
