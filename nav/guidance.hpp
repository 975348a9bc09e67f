// Guidance: the steering laws that keep the robot on a tape line, and the
// path follower that drives a route of straight legs joined at junctions
// (T-branches, L-turns), slows down when vision is lost and stops when it
// stays lost. The laws are derived in docs/navigation.md ("Guidance").
//
// Line frame: the leg runs from a to b; the robot's lateral error e is the
// signed distance of its wheel-axis midpoint from the line (positive: left
// of it, as the tape offset of BRIEF section 5) and its heading error psi is
// its yaw minus the leg's direction. Over the travelled distance s,
//   de/ds = sin psi,  dpsi/ds = kappa = omega / v.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/odometry_step.hpp"

namespace ceilnav::nav {

struct LineError {
  double lateral_m = 0.0;    // e: positive left of the line
  double heading_rad = 0.0;  // psi: yaw - line direction, wrapped to [-pi, pi)
  double along_m = 0.0;      // distance of the projection from a along a -> b
  double length_m = 0.0;     // |b - a|
};
LineError line_error(const Pose2& robot, const Eigen::Vector2d& a, const Eigen::Vector2d& b);

enum class SteeringLaw {
  // Exact: kappa = -(2 zeta sin psi / L + e / L^2) / cos psi makes
  // e'' + (2 zeta / L) e' + e / L^2 = 0 in distance, whatever the heading.
  feedback_linearised,
  // Its linearisation about the line: kappa = -(2 zeta psi / L + e / L^2).
  linear,
  // Pure pursuit of the point on the line `lookahead_m` from the robot:
  // kappa = 2 sin(alpha) / lookahead, alpha the bearing of that point. About
  // the line it is the linear law with L = lookahead / sqrt 2, zeta = 1 / sqrt 2.
  pure_pursuit,
};

struct SteeringOptions {
  SteeringLaw law = SteeringLaw::feedback_linearised;
  double convergence_length_m = 0.4;  // L: the distance scale of the lateral error's decay
  double damping = 1.0;               // zeta: 1 = critically damped, no overshoot
  double lookahead_m = 0.6;           // pure pursuit only
  double max_curvature_per_m = 5.0;   // |kappa| limit (the robot's, and safety)
};

// The curvature command kappa (1/m, positive: turn left) for a line error.
double steering_curvature(const LineError& e, const SteeringOptions& o);

struct FollowerOptions {
  SteeringOptions steering;
  double cruise_speed_mps = 0.5;
  double max_accel_mps2 = 0.5;         // speed ramps and the stop before a pivot
  double pivot_rate_radps = 1.0;       // turning on the spot at a junction
  double pivot_tolerance_rad = 0.002;  // heading error at which a pivot ends
  double pivot_gain_per_s = 4.0;       // omega = gain * heading error near the end of a pivot
  // Turns smaller than this are driven through by the steering law without
  // stopping (a gently bent tape); larger ones are junctions: stop, pivot.
  double pivot_min_turn_rad = 0.35;
  // Vision lost: after blind_slow_m of travel without a fix the speed drops
  // to blind_speed_mps; after blind_stop_m the robot stops (mode lost).
  double blind_slow_m = 0.3;
  double blind_speed_mps = 0.2;
  double blind_stop_m = 2.0;
};

enum class FollowerMode { follow, pivot, lost, finished };
const char* to_string(FollowerMode m);

struct Command {
  double v_mps = 0.0;
  double omega_radps = 0.0;
  FollowerMode mode = FollowerMode::follow;
  int leg = 0;  // index of the leg being driven (waypoints[leg] -> waypoints[leg + 1])
  LineError error;
};

// Drives a polyline of waypoints (the route through the course's junctions,
// each leg a straight piece of tape). Legs joined by a turn of at least
// pivot_min_turn_rad end with a stop on the junction and a pivot on the spot
// onto the next leg; smaller turns are steered through.
class PathFollower {
 public:
  PathFollower(std::vector<Eigen::Vector2d> waypoints, const FollowerOptions& options = {});

  // One control step of dt seconds from the estimated pose and the speed
  // commanded last; blind_m: distance travelled since the last vision fix.
  Command update(const Pose2& estimate, double dt, double blind_m);

  FollowerMode mode() const { return mode_; }
  int leg() const { return leg_; }
  const std::vector<Eigen::Vector2d>& waypoints() const { return waypoints_; }

 private:
  bool pivots_at_end(int leg) const;
  std::vector<Eigen::Vector2d> waypoints_;
  FollowerOptions options_;
  FollowerMode mode_ = FollowerMode::follow;
  int leg_ = 0;
  double speed_ = 0.0;
};

}  // namespace ceilnav::nav
