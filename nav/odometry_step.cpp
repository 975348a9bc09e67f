#include "nav/odometry_step.hpp"

#include <cmath>
#include <numbers>

namespace ceilnav::nav {

Motion motion_of(const OdometryStep& step, double wheel_base_m) {
  return {0.5 * (step.left_m + step.right_m), (step.right_m - step.left_m) / wheel_base_m};
}

Pose2 advance(const Pose2& pose, const Motion& motion) {
  const double half = 0.5 * motion.dyaw_rad;
  // sinc(h) = sin(h)/h; its series is exact to double precision below 1e-4.
  const double sinc = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
  const double chord = motion.distance_m * sinc;
  const double heading = pose.yaw_rad + half;
  return {pose.x_m + chord * std::cos(heading), pose.y_m + chord * std::sin(heading),
          wrap_angle(pose.yaw_rad + motion.dyaw_rad)};
}

double wrap_angle(double a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  a = std::fmod(a + std::numbers::pi, two_pi);
  if (a < 0.0) a += two_pi;
  return a - std::numbers::pi;
}

}  // namespace ceilnav::nav
