#include "host/pattern/world_fix.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace ceilnav::host::pattern {

WorldFix world_fix(const PatternPose& pose, const Eigen::Matrix3d& pattern_axes,
                   const Eigen::Vector3d& pattern_origin, const Eigen::Vector3d& y_cam) {
  WorldFix f;
  const double st = std::sin(pose.theta_rad);
  const Eigen::Vector3d cam_pat =
      pose.d_m * Eigen::Vector3d(st * std::sin(pose.beta_rad), st * std::cos(pose.beta_rad),
                                 std::cos(pose.theta_rad));
  const Eigen::Vector3d w = pattern_origin + pattern_axes * cam_pat;
  f.x_m = w.x();
  f.y_m = w.y();
  f.z_m = w.z();
  // TRIAD: (direction to the disc, the pattern's +y) in the camera <->
  // (-cam_pat, y_p) in the pattern frame gives the camera's rotation; its
  // forward axis in the world gives the yaw.
  auto triad = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    Eigen::Matrix3d t;
    t.col(0) = a.normalized();
    t.col(1) = a.cross(b).normalized();
    t.col(2) = t.col(0).cross(t.col(1));
    return t;
  };
  const Eigen::Matrix3d tc = triad(pose.centre_cam, y_cam);
  const Eigen::Matrix3d tp = triad(-cam_pat, Eigen::Vector3d::UnitY());
  f.world_from_camera = pattern_axes * (tp * tc.transpose());
  const Eigen::Vector3d fwd = f.world_from_camera.col(2);
  f.camera_yaw_rad = std::atan2(fwd.y(), fwd.x());
  if (!std::isfinite(f.camera_yaw_rad)) f.camera_yaw_rad = 0.0;
  return f;
}

WorldFix world_fix(const PatternPose& pose, const Placement& placement,
                   const Eigen::Vector3d& y_cam) {
  const Eigen::Vector3d z(std::cos(placement.facing_rad), std::sin(placement.facing_rad), 0.0);
  const Eigen::Vector3d y(0.0, 0.0, 1.0);
  Eigen::Matrix3d axes;
  axes.col(0) = y.cross(z);
  axes.col(1) = y;
  axes.col(2) = z;
  return world_fix(pose, axes, Eigen::Vector3d(placement.x_m, placement.y_m, placement.z_m), y_cam);
}

double swing_from_up(const Eigen::Vector3d& up_cam) {
  if (!up_cam.allFinite() || !(std::hypot(up_cam.x(), up_cam.y()) > 1e-12)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return std::atan2(-up_cam.x(), -up_cam.y());
}

}  // namespace ceilnav::host::pattern
