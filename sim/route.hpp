// The path a route takes through a course: from the start pose along the
// tape it stands on, at each junction met (sim::junctions: tees, crossings,
// L-turns) the next turn of Course::route, until the route is used up and the
// next junction or the tape's end is reached. The waypoints are the start's
// foot on the tape, every junction and bend passed, and the end: the legs of
// nav::PathFollower (docs/navigation.md, "Routes").
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "sim/course.hpp"

namespace ceilnav::sim {

struct RouteJunction {
  Junction::Kind kind = Junction::Kind::tee;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  Turn turn = Turn::straight;
  double heading_in_rad = 0.0, heading_out_rad = 0.0;
  int waypoint = 0;  // index of its waypoint in RoutePlan::waypoints
};

struct RoutePlan {
  std::vector<Eigen::Vector2d> waypoints;
  std::vector<RouteJunction> junctions;  // the junctions the route decides at, in order
  double length_m = 0.0;
};

// Throws CourseError when the start is not on a tape (farther than 0.5 m or
// heading more than 30 deg off it), when a turn of the route does not exist
// at its junction, or when the path does not end (more than 1000 legs).
RoutePlan plan_route(const Course& course);

}  // namespace ceilnav::sim
