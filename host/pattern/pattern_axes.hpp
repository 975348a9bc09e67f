// The pattern frame of a circle pose and the camera's spherical position in
// it: shared by the conic method, the plane bar-code reader and the
// refinement with the bars (not part of the front header pattern_pose.hpp).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "host/pattern/pattern_pose_types.hpp"

namespace ceilnav::host::pattern {

// Pattern frame (x right, y up, z toward the viewer) of the circle pose
// (centre c, normal n toward the camera) given the world vertical in camera
// coordinates: columns x_p, y_p, z_p in camera coordinates; empty when the
// vertical is along the normal.
std::optional<Eigen::Matrix3d> pattern_axes_cam(const Eigen::Vector3d& n,
                                                const Eigen::Vector3d& up);

// D, theta, beta of the camera from the circle pose (camera at the origin):
// fills p.d_m, p.theta_rad, p.beta_rad.
void spherical_from_pose(const Eigen::Vector3d& c, const Eigen::Matrix3d& axes, PatternPose& p);

}  // namespace ceilnav::host::pattern
