// Wheel odometry of a differential-drive robot as the navigation layer sees
// it: the travel of each wheel between two odometry ticks, and the planar
// pose it moves. Frames: world X forward along the course's first tape, Y
// left, yaw counter-clockwise from X (BRIEF section 5); the robot's origin is
// the midpoint of its wheel axis.
#pragma once

namespace ceilnav::nav {

struct Pose2 {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
};

// Wheel travel measured since the previous step (encoder counts times the
// nominal metres per count), stamped with the time of the tick.
struct OdometryStep {
  double t_s = 0.0;
  double left_m = 0.0;
  double right_m = 0.0;
};

// Distance travelled by the axis midpoint and heading change of one step,
// for a wheel base (distance between the wheels' contact points) b:
//   ds = (r + l) / 2,  dpsi = (r - l) / b.
struct Motion {
  double distance_m = 0.0;
  double dyaw_rad = 0.0;
};
Motion motion_of(const OdometryStep& step, double wheel_base_m);

// The pose after moving `distance_m` along a circular arc that turns the
// heading by `dyaw_rad` (exact for constant curvature over the step):
//   x' = x + ds sinc(dpsi/2) cos(psi + dpsi/2), y' likewise with sin.
Pose2 advance(const Pose2& pose, const Motion& motion);

// Wrap an angle to [-pi, pi).
double wrap_angle(double a);

}  // namespace ceilnav::nav
