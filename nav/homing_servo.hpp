// Seed 004's visual servoing (section 3.3) for the navigation layer's
// differential-drive robot: two successive steps, each the one-dimensional
// law eta_i = -lambda_i e(t) with an adaptive gain,
//   i)  e = sqrt(X^2 + Y^2): drive until the robot stands where it stood
//       when the site was recorded (the seed: the template at the image
//       centre), the base turned toward the site point (the seed's eta_2,
//       not servoed: here a proportional turn toward the bearing);
//   ii) e = gamma: turn until the robot has the site's heading. The seed
//       turns a turret; a differential drive has none, so the whole robot
//       rotates in place about its wheel-axis midpoint.
// The errors are the robot's (its wheel-axis midpoint and heading), computed
// from the camera's measurement and the camera's place on the robot, so a
// camera ahead of the axis (which the rotation of step ii moves) still ends
// where it was recorded. docs/homing.md, "Servoing".
#pragma once

#include <vector>

#include <Eigen/Core>

#include "nav/measurement.hpp"

namespace ceilnav::nav {

// The adaptive gain of the task-function literature the seed cites
// ([Espiau92]; the seed names the gain adaptive without a law):
//   lambda(e) = (at_zero - at_infinity) exp(-slope_at_zero e /
//               (at_zero - at_infinity)) + at_infinity,
// high near convergence (fast final approach) and lower far away (bounded
// speed): lambda(0) = at_zero, lambda(inf) = at_infinity, d lambda / de (0)
// = -slope_at_zero. at_zero == at_infinity: a constant gain.
struct AdaptiveGain {
  double at_zero = 1.0;        // 1/s
  double at_infinity = 1.0;    // 1/s
  double slope_at_zero = 0.0;  // 1/(s unit of e)
  double operator()(double e) const;
};

struct HomingServoParams {
  // The camera's look point: where its optical axis meets the ceiling,
  // ahead of and left of the wheel-axis midpoint, in the robot's frame (the
  // camera's place on the robot plus the ceiling distance times its tilt:
  // 0.3 deg of tilt at 3 m is 16 mm). The measurement is relative to it;
  // look_offset_from_turns measures it at a site.
  double camera_forward_m = 0.0, camera_left_m = 0.0;
  AdaptiveGain position{1.5, 0.6, 20.0};    // step i: e in metres
  AdaptiveGain orientation{2.0, 1.0, 2.0};  // step ii: e in radians
  double bearing_gain = 2.5;                // 1/s: the base's turn toward the site (eta_2)
  // Step i drives only while the site's bearing (or its reverse: the robot
  // backs up to a site behind it) is within drive_cone_rad, at the speed
  // scaled by cos(bearing).
  double drive_cone_rad = 0.35;
  // Step i is done below position_tolerance_m; step ii below
  // heading_tolerance_rad. A finished step resumes above `hysteresis` x its
  // tolerance.
  double position_tolerance_m = 0.001;
  double heading_tolerance_rad = 0.0015;
  double hysteresis = 2.0;
  // Once step i is done the robot only turns in place, which does not move
  // its wheel-axis midpoint: a position error that grows while it turns is
  // the measurement's (a match pulled a fraction of a pixel by a changed
  // lamp at some turns, the look offset's error), up to slip. Step ii (and
  // done) resume step i only above turn_resume_position_m, not at
  // hysteresis x position_tolerance_m: a bias of 3 mm that came and went
  // with the turn otherwise sent the robot back and forth between the steps
  // until its time ran out.
  double turn_resume_position_m = 0.005;
  // Near the end the errors are a few measurement noises: inside the fine
  // band (position below fine_position_m and turn below fine_turn_rad) the
  // servo decides its steps' ends on an exponential average of the measured
  // errors (its commands stay on each frame's: the average lags; weight
  // fine_smoothing for the newest frame; 1 = none: the scatter of the
  // average is sqrt(a / (2 - a)) = 1/3 of a frame's at 0.2), so that frame
  // noise (0.3 deg of turn on a ceiling of beams) does not keep the robot
  // turning or end a step early. Outside the band it decides on each frame's.
  double fine_position_m = 0.005;
  double fine_turn_rad = 0.0175;
  double fine_smoothing = 0.2;
  double max_speed_m_s = 0.3, max_yaw_rate_rad_s = 0.8;
};
// Throws std::invalid_argument naming the first bad field.
void validate(const HomingServoParams& p);

enum class HomingPhase { position, orientation, done };
const char* to_string(HomingPhase p);

// The robot's pose error toward the site, in the robot's frame: the site's
// wheel-axis midpoint ahead / left of the current one, and the turn to the
// site's heading. With the camera at c on the robot (robot frame), the
// camera's measurement s (site camera - current camera) and the turn g:
//   p = s + c - R(g) c.
struct HomingError {
  double forward_m = 0.0, left_m = 0.0, turn_rad = 0.0;
  double distance_m() const;
};
HomingError robot_error(const HomingMeasurement& m, double camera_forward_m, double camera_left_m);

// The look point's offset c from turns in place at a site: the robot
// records the site, turns in place and measures it again; turned by g
// (the measurement's turn_rad), it sees the site camera at
//   s = (R(g) - I) c
// (the wheel-axis midpoint stays on the site). Least squares over the
// turns; throws std::invalid_argument with fewer than two `ok` turns or
// when they span less than 30 deg (ill-conditioned).
Eigen::Vector2d look_offset_from_turns(const std::vector<HomingMeasurement>& turns);

struct HomingCommand {
  double v_m_s = 0.0, omega_rad_s = 0.0;
  HomingPhase phase = HomingPhase::position;
  HomingError error;
};

class HomingServo {
 public:
  explicit HomingServo(const HomingServoParams& params = {});
  // The command for an `ok` measurement; any other status stops the robot
  // (the phase is kept). cmd.error is the error the servo acted on (the
  // smoothed one inside the fine band).
  HomingCommand update(const HomingMeasurement& m);
  HomingPhase phase() const { return phase_; }
  void reset() {
    phase_ = HomingPhase::position;
    smoothing_ = false;
  }
  const HomingServoParams& params() const { return params_; }

 private:
  HomingServoParams params_;
  HomingPhase phase_ = HomingPhase::position;
  bool smoothing_ = false;
  HomingError smoothed_;
};

}  // namespace ceilnav::nav
