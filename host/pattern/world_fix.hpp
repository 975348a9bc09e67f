// The camera's position and heading in the world from the pattern's pose and
// its placement (the pattern frame of golden/pattern/pattern.hpp).
#pragma once

#include <Eigen/Core>

#include "host/pattern/pattern_pose_types.hpp"

namespace ceilnav::host::pattern {

// Camera position and heading in the world from a pose and the pattern's
// placement (the pattern frame of golden/pattern/pattern.hpp).
struct Placement {
  double x_m = 0, y_m = 0, z_m = 0, facing_rad = 0;
};
struct WorldFix {
  double x_m = 0, y_m = 0, z_m = 0;
  double camera_yaw_rad = 0;  // heading of the optical axis, CCW from +X
};
// The camera position from D, theta, beta; its yaw from the direction of the
// disc centre in the camera (pose.centre_cam) and up_cam.
WorldFix world_fix(const PatternPose& pose, const Placement& placement,
                   const Eigen::Vector3d& up_cam);

// The camera's swing sigma (seed 003 eq. 70, beta' = beta + sigma): its roll
// about the optical axis away from the pose where its x axis is horizontal,
// positive clockwise in the image (golden::pattern::look_at's convention),
// from the world's up in camera coordinates (x right, y down, z forward):
// sigma = atan2(-up_x, -up_y). Exact at any tilt; it is the angle a vertical
// line through the principal point makes with the image's vertical (the
// seed's "angle that a vertical line in the world makes with the vertical in
// the image"). NaN when up is along the optical axis.
double swing_from_up(const Eigen::Vector3d& up_cam);

}  // namespace ceilnav::host::pattern
