#include "host/pattern/pattern_axes.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ceilnav::host::pattern {

// Pattern frame (x right, y up, z toward the viewer) of the circle pose
// (centre c, normal n toward the camera) given the world vertical in camera
// coordinates: columns x_p, y_p, z_p in camera coordinates.
std::optional<Eigen::Matrix3d> pattern_axes_cam(const Eigen::Vector3d& n,
                                                const Eigen::Vector3d& up) {
  Eigen::Vector3d y = up - up.dot(n) * n;
  if (!(y.norm() > 1e-9)) return std::nullopt;
  y.normalize();
  Eigen::Matrix3d a;
  a.col(0) = y.cross(n);
  a.col(1) = y;
  a.col(2) = n;
  return a;
}

// D, theta, beta of the camera from the circle pose (camera at the origin).
void spherical_from_pose(const Eigen::Vector3d& c, const Eigen::Matrix3d& axes, PatternPose& p) {
  const Eigen::Vector3d cam = axes.transpose() * (-c);  // camera in the pattern frame
  p.d_m = cam.norm();
  p.theta_rad = std::acos(std::clamp(cam.z() / p.d_m, -1.0, 1.0));
  p.beta_rad = std::atan2(cam.x(), cam.y());
}

}  // namespace ceilnav::host::pattern
