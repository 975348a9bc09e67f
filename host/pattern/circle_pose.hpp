// The exact pose of a circle from its image conic: the two circle poses of
// the cone through the disc's ellipse (the seed's two-way ambiguity) and the
// other one of a given pose (docs/pattern.md).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "host/pattern/ellipse_from_moments.hpp"
#include "host/pattern/pattern_pose_types.hpp"

namespace ceilnav::host::pattern {

// The two poses (centre, unit normal toward the camera) of a circle of radius
// r whose image is the conic q (3x3 symmetric, [x y 1] q [x y 1]^T = 0 in
// normalised coordinates). Empty when q is not a real ellipse.
struct CirclePose {
  Eigen::Vector3d centre, normal;
};
std::vector<CirclePose> circle_poses_from_conic(const Eigen::Matrix3d& q, double r);
Eigen::Matrix3d conic_from_ellipse(const Ellipse& e);
// The other circle pose of a pose's disc ellipse (the seed's two-way
// ambiguity, eq. 14): the one of circle_poses_from_conic whose normal is not
// the pose's; empty when the ellipse has only one.
std::optional<CirclePose> mirror_pose(const PatternPose& p, double radius_m);

}  // namespace ceilnav::host::pattern
