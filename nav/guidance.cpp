#include "nav/guidance.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ceilnav::nav {

LineError line_error(const Pose2& robot, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  LineError e;
  e.length_m = ab.norm();
  if (!(e.length_m > 0.0)) throw std::invalid_argument("line_error: a leg of zero length");
  const Eigen::Vector2d d = ab / e.length_m;
  const Eigen::Vector2d n(-d.y(), d.x());  // left of the direction of travel
  const Eigen::Vector2d r = Eigen::Vector2d(robot.x_m, robot.y_m) - a;
  e.lateral_m = r.dot(n);
  e.along_m = r.dot(d);
  e.heading_rad = wrap_angle(robot.yaw_rad - std::atan2(d.y(), d.x()));
  return e;
}

double steering_curvature(const LineError& e, const SteeringOptions& o) {
  const double L = o.convergence_length_m, z = o.damping, kmax = o.max_curvature_per_m;
  double k = 0.0;
  switch (o.law) {
    case SteeringLaw::feedback_linearised: {
      const double c = std::cos(e.heading_rad);
      // Beyond +-78 deg the law's 1 / cos psi blows up; turn back at the limit.
      if (c < 0.2) {
        k = e.heading_rad > 0.0 ? -kmax : kmax;
      } else {
        k = -(2.0 * z * std::sin(e.heading_rad) / L + e.lateral_m / (L * L)) / c;
      }
      break;
    }
    case SteeringLaw::linear:
      k = -(2.0 * z * e.heading_rad / L + e.lateral_m / (L * L));
      break;
    case SteeringLaw::pure_pursuit: {
      const double ld = o.lookahead_m;
      const double ahead = std::sqrt(std::max(ld * ld - e.lateral_m * e.lateral_m, 0.0));
      const double bearing = std::atan2(-e.lateral_m, ahead);  // of the goal, in the line frame
      k = 2.0 * std::sin(wrap_angle(bearing - e.heading_rad)) / ld;
      break;
    }
  }
  return std::clamp(k, -kmax, kmax);
}

const char* to_string(FollowerMode m) {
  switch (m) {
    case FollowerMode::follow:
      return "follow";
    case FollowerMode::pivot:
      return "pivot";
    case FollowerMode::lost:
      return "lost";
    case FollowerMode::finished:
      return "finished";
  }
  return "unknown";
}

PathFollower::PathFollower(std::vector<Eigen::Vector2d> waypoints, const FollowerOptions& options)
    : waypoints_(std::move(waypoints)), options_(options) {
  if (waypoints_.size() < 2) throw std::invalid_argument("PathFollower: fewer than 2 waypoints");
  for (std::size_t i = 1; i < waypoints_.size(); ++i) {
    if (!((waypoints_[i] - waypoints_[i - 1]).norm() > 1e-6))
      throw std::invalid_argument("PathFollower: two equal waypoints in a row");
  }
}

bool PathFollower::pivots_at_end(int leg) const {
  const auto i = static_cast<std::size_t>(leg);
  if (i + 2 >= waypoints_.size()) return false;
  const Eigen::Vector2d d0 = waypoints_[i + 1] - waypoints_[i];
  const Eigen::Vector2d d1 = waypoints_[i + 2] - waypoints_[i + 1];
  const double turn = std::atan2(d0.x() * d1.y() - d0.y() * d1.x(), d0.dot(d1));
  return std::abs(turn) >= options_.pivot_min_turn_rad;
}

Command PathFollower::update(const Pose2& estimate, double dt, double blind_m) {
  const FollowerOptions& o = options_;
  Command c;
  auto error_on = [&](int leg) {
    const auto i = static_cast<std::size_t>(leg);
    return line_error(estimate, waypoints_[i], waypoints_[i + 1]);
  };
  const int last_leg = static_cast<int>(waypoints_.size()) - 2;
  if (mode_ == FollowerMode::lost && blind_m < o.blind_stop_m) mode_ = FollowerMode::follow;
  if (mode_ == FollowerMode::follow && blind_m >= o.blind_stop_m) mode_ = FollowerMode::lost;

  if (mode_ == FollowerMode::pivot) {
    c.error = error_on(leg_);
    const double psi = c.error.heading_rad;
    if (std::abs(psi) <= o.pivot_tolerance_rad) {
      mode_ = FollowerMode::follow;
    } else {
      c.omega_radps =
          std::clamp(-o.pivot_gain_per_s * psi, -o.pivot_rate_radps, o.pivot_rate_radps);
    }
  }
  if (mode_ == FollowerMode::follow) {
    // Legs whose end is passed without a pivot hand over to the next one.
    c.error = error_on(leg_);
    while (leg_ < last_leg && !pivots_at_end(leg_) && c.error.along_m >= c.error.length_m) {
      ++leg_;
      c.error = error_on(leg_);
    }
    const double remaining = c.error.length_m - c.error.along_m;
    const bool stop_at_end = leg_ == last_leg || pivots_at_end(leg_);
    if (stop_at_end && remaining <= std::max(1e-3, speed_ * dt)) {
      speed_ = 0.0;
      if (leg_ == last_leg) {
        mode_ = FollowerMode::finished;
      } else {
        ++leg_;
        mode_ = FollowerMode::pivot;
        c.error = error_on(leg_);
        c.omega_radps = std::clamp(-o.pivot_gain_per_s * c.error.heading_rad, -o.pivot_rate_radps,
                                   o.pivot_rate_radps);
      }
    } else {
      double target = o.cruise_speed_mps;
      if (blind_m >= o.blind_slow_m) target = std::min(target, o.blind_speed_mps);
      if (stop_at_end) {
        // Constant deceleration to the junction, with a creep speed so the
        // last millimetres are covered in finite time.
        constexpr double kCreep = 0.02;
        target = std::min(target, std::max(kCreep, std::sqrt(2.0 * o.max_accel_mps2 * remaining)));
      }
      const double dv = o.max_accel_mps2 * dt;
      speed_ = std::clamp(target, speed_ - dv, speed_ + dv);
      if (stop_at_end) speed_ = std::min(speed_, remaining / dt);
      c.v_mps = speed_;
      c.omega_radps = steering_curvature(c.error, o.steering) * speed_;
    }
  }
  if (mode_ == FollowerMode::lost || mode_ == FollowerMode::finished) {
    speed_ = 0.0;
    c.v_mps = c.omega_radps = 0.0;
    c.error = error_on(leg_);
  }
  c.mode = mode_;
  c.leg = leg_;
  return c;
}

}  // namespace ceilnav::nav
