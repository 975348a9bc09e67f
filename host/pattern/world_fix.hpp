// The camera's position and heading in the world from the pattern's pose and
// its placement (the pattern frame of golden/pattern/pattern.hpp).
#pragma once

#include <Eigen/Core>

#include "host/pattern/pattern_pose_types.hpp"

namespace ceilnav::host::pattern {

// A wall pattern's placement: disc centre (x, y, z), facing the horizontal
// direction facing_rad (its +z), its +y the world's up.
struct Placement {
  double x_m = 0, y_m = 0, z_m = 0, facing_rad = 0;
};
struct WorldFix {
  double x_m = 0, y_m = 0, z_m = 0;
  double camera_yaw_rad = 0;  // heading of the optical axis, CCW from +X
  // The camera's axes (columns: x right, y down, z forward) in the world.
  Eigen::Matrix3d world_from_camera = Eigen::Matrix3d::Identity();
};
// The camera position from D, theta, beta; its orientation from the
// direction of the disc centre in the camera (pose.centre_cam) and the
// pattern's +y in the camera, y_cam (for a wall pattern the world's up;
// refine_with_bars measures it: pose.up_cam) paired with the same two
// directions in the pattern frame (TRIAD).
WorldFix world_fix(const PatternPose& pose, const Placement& placement,
                   const Eigen::Vector3d& y_cam);
// Any placement: the pattern frame's axes (columns x, y, z in world
// coordinates) and its origin (the disc centre) in the world, e.g. a
// ceiling station facing down (sim::station_frame).
WorldFix world_fix(const PatternPose& pose, const Eigen::Matrix3d& pattern_axes,
                   const Eigen::Vector3d& pattern_origin, const Eigen::Vector3d& y_cam);

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
