#include "sim/route.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "nav/odometry_step.hpp"

namespace ceilnav::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

struct Seg {
  Eigen::Vector2d a, b;
  double tol;  // half the tape's width
};

std::vector<Seg> segments(const Course& c) {
  std::vector<Seg> out;
  for (const TapePolyline& t : c.tapes) {
    for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
      out.push_back({{t.points[k].x_m, t.points[k].y_m},
                     {t.points[k + 1].x_m, t.points[k + 1].y_m},
                     0.5 * t.width_m});
    }
  }
  return out;
}

double distance_to(const Seg& s, const Eigen::Vector2d& p) {
  const Eigen::Vector2d ab = s.b - s.a;
  const double u = std::clamp((p - s.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (s.a + u * ab - p).norm();
}

// Directions that leave p along tape (segments through p with length beyond
// it), as unit vectors.
std::vector<Eigen::Vector2d> departures(const std::vector<Seg>& segs, const Eigen::Vector2d& p) {
  std::vector<Eigen::Vector2d> out;
  auto add = [&](const Eigen::Vector2d& d) {
    for (const auto& o : out)
      if (o.dot(d) > std::cos(5.0 * kDeg)) return;
    out.push_back(d);
  };
  for (const Seg& s : segs) {
    if (distance_to(s, p) > s.tol) continue;
    if ((s.b - p).norm() > s.tol) add((s.b - p).normalized());
    if ((s.a - p).norm() > s.tol) add((s.a - p).normalized());
  }
  return out;
}

double heading_of(const Eigen::Vector2d& d) {
  return std::atan2(d.y(), d.x());
}

}  // namespace

RoutePlan plan_route(const Course& course) {
  const std::vector<Seg> segs = segments(course);
  const std::vector<Junction> all = junctions(course);
  const Eigen::Vector2d start(course.start.x_m, course.start.y_m);
  const Eigen::Vector2d start_dir(std::cos(course.start.yaw_rad), std::sin(course.start.yaw_rad));

  // The segment the start stands on, taken the way the start faces.
  const Seg* cur = nullptr;
  Eigen::Vector2d dir;
  for (const Seg& s : segs) {
    const Eigen::Vector2d d = (s.b - s.a).normalized();
    const double along = std::abs(d.dot(start_dir));
    if (distance_to(s, start) > 0.5 || along < std::cos(30.0 * kDeg)) continue;
    if (cur == nullptr || distance_to(s, start) < distance_to(*cur, start)) {
      cur = &s;
      dir = d.dot(start_dir) >= 0.0 ? d : Eigen::Vector2d(-d);
    }
  }
  if (cur == nullptr) {
    throw CourseError(fmt::format(
        "{}: the start ({:.3f}, {:.3f}) heading {:.1f} deg is not on a tape (within 0.5 m and "
        "30 deg)",
        course.name, course.start.x_m, course.start.y_m, course.start.yaw_rad / kDeg));
  }
  RoutePlan plan;
  // A waypoint where the path already is (a junction at a bend) is one waypoint.
  auto push = [&plan](const Eigen::Vector2d& w) {
    if (plan.waypoints.empty() || (plan.waypoints.back() - w).norm() > 1e-6)
      plan.waypoints.push_back(w);
  };
  Eigen::Vector2d p = cur->a + (start - cur->a).dot(dir) * dir;  // foot on the line
  plan.waypoints.push_back(p);
  std::size_t next_turn = 0;
  for (int legs = 0;; ++legs) {
    if (legs > 1000) throw CourseError(course.name + ": the route does not end");
    // The far end of the current segment in the direction of travel, and the
    // junctions on the way to it.
    const Eigen::Vector2d end = (cur->b - p).dot(dir) > 0.0 ? cur->b : cur->a;
    double t_best = (end - p).dot(dir);
    Eigen::Vector2d stop = end;
    const Junction* junction = nullptr;
    for (const Junction& j : all) {
      const Eigen::Vector2d q(j.position.x_m, j.position.y_m);
      const double t = (q - p).dot(dir);
      const double off = std::abs((q - p).x() * dir.y() - (q - p).y() * dir.x());
      if (t <= cur->tol || t > t_best + cur->tol || off > cur->tol) continue;
      if (junction == nullptr || t < t_best || std::abs(t - t_best) <= cur->tol) {
        t_best = t;
        stop = q;
        junction = &j;
      }
    }
    // Where the travel can go from there (not back).
    std::vector<Eigen::Vector2d> options;
    for (const auto& d : departures(segs, stop))
      if (d.dot(dir) > std::cos(150.0 * kDeg)) options.push_back(d);
    const bool only_straight = options.size() == 1 && options[0].dot(dir) > std::cos(5.0 * kDeg);
    Eigen::Vector2d next_dir;
    if (options.empty()) {
      push(stop);  // the tape ends
      break;
    }
    if (only_straight) {
      next_dir = options[0];
    } else if (options.size() == 1 && junction == nullptr) {
      next_dir = options[0];  // a bend that is no junction: follow it, no turn taken
      push(stop);
    } else {
      if (next_turn >= course.route.size()) {
        push(stop);  // the route is used up: stop at this junction
        break;
      }
      const Turn turn = course.route[next_turn];
      const double want = turn == Turn::left ? kPi / 2 : turn == Turn::right ? -kPi / 2 : 0.0;
      const Eigen::Vector2d* best = nullptr;
      double best_err = 45.0 * kDeg;
      for (const auto& d : options) {
        const double rel = nav::wrap_angle(heading_of(d) - heading_of(dir));
        const double err = std::abs(nav::wrap_angle(rel - want));
        if (err < best_err) {
          best_err = err;
          best = &d;
        }
      }
      if (best == nullptr) {
        throw CourseError(
            fmt::format("{}: turn {} ({}) of the route does not exist at ({:.3f}, "
                        "{:.3f})",
                        course.name, next_turn + 1, turn_name(turn), stop.x(), stop.y()));
      }
      next_dir = *best;
      RouteJunction rj;
      rj.kind = junction != nullptr ? junction->kind : Junction::Kind::l_turn;
      rj.position = stop;
      rj.turn = turn;
      rj.heading_in_rad = heading_of(dir);
      rj.heading_out_rad = heading_of(next_dir);
      push(stop);
      rj.waypoint = static_cast<int>(plan.waypoints.size()) - 1;
      plan.junctions.push_back(rj);
      ++next_turn;
    }
    // The segment that leaves `stop` along next_dir.
    const Seg* nxt = nullptr;
    for (const Seg& s : segs) {
      if (distance_to(s, stop) > s.tol) continue;
      const Eigen::Vector2d d = (s.b - s.a).normalized();
      if (std::abs(d.dot(next_dir)) < std::cos(5.0 * kDeg)) continue;
      const Eigen::Vector2d far = d.dot(next_dir) > 0.0 ? s.b : s.a;
      if ((far - stop).dot(next_dir) <= s.tol) continue;
      nxt = &s;
      break;
    }
    if (nxt == nullptr) throw CourseError(course.name + ": lost the tape at a junction");
    cur = nxt;
    dir = ((cur->b - cur->a).dot(next_dir) > 0.0 ? (cur->b - cur->a) : (cur->a - cur->b))
              .normalized();
    p = stop;
  }
  for (std::size_t k = 1; k < plan.waypoints.size(); ++k)
    plan.length_m += (plan.waypoints[k] - plan.waypoints[k - 1]).norm();
  return plan;
}

}  // namespace ceilnav::sim
