#include "nav/homing_servo.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "nav/odometry_step.hpp"

namespace ceilnav::nav {

double AdaptiveGain::operator()(double e) const {
  const double span = at_zero - at_infinity;
  if (span == 0.0) return at_zero;
  return span * std::exp(-slope_at_zero * std::abs(e) / span) + at_infinity;
}

void validate(const HomingServoParams& p) {
  const auto need = [](bool ok, const char* field, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("homing servo: ") + field + " " + what);
  };
  need(std::isfinite(p.camera_forward_m) && std::isfinite(p.camera_left_m), "camera offset",
       "must be finite");
  for (const auto& [g, name] :
       {std::pair{p.position, "position gain"}, {p.orientation, "orientation gain"}}) {
    need(std::isfinite(g.at_zero) && g.at_zero > 0.0, name, "at_zero must be > 0");
    need(std::isfinite(g.at_infinity) && g.at_infinity > 0.0, name, "at_infinity must be > 0");
    need(std::isfinite(g.slope_at_zero) && g.slope_at_zero >= 0.0, name,
         "slope_at_zero must be >= 0");
  }
  need(std::isfinite(p.bearing_gain) && p.bearing_gain > 0.0, "bearing_gain", "must be > 0");
  need(p.drive_cone_rad > 0.0 && p.drive_cone_rad < std::numbers::pi / 2, "drive_cone_rad",
       "must be in (0, pi/2)");
  need(std::isfinite(p.position_tolerance_m) && p.position_tolerance_m > 0.0,
       "position_tolerance_m", "must be > 0");
  need(std::isfinite(p.heading_tolerance_rad) && p.heading_tolerance_rad > 0.0,
       "heading_tolerance_rad", "must be > 0");
  need(std::isfinite(p.hysteresis) && p.hysteresis >= 1.0, "hysteresis", "must be >= 1");
  need(std::isfinite(p.fine_position_m) && p.fine_position_m >= 0.0 &&
           std::isfinite(p.fine_turn_rad) && p.fine_turn_rad >= 0.0,
       "fine band", "must be finite and >= 0");
  need(p.fine_smoothing > 0.0 && p.fine_smoothing <= 1.0, "fine_smoothing", "must be in (0, 1]");
  need(std::isfinite(p.turn_resume_position_m) &&
           p.turn_resume_position_m >= p.hysteresis * p.position_tolerance_m,
       "turn_resume_position_m", "must be >= hysteresis x position_tolerance_m");
  need(std::isfinite(p.max_speed_m_s) && p.max_speed_m_s > 0.0, "max_speed_m_s", "must be > 0");
  need(std::isfinite(p.max_yaw_rate_rad_s) && p.max_yaw_rate_rad_s > 0.0, "max_yaw_rate_rad_s",
       "must be > 0");
}

const char* to_string(HomingPhase p) {
  switch (p) {
    case HomingPhase::position:
      return "position";
    case HomingPhase::orientation:
      return "orientation";
    case HomingPhase::done:
      return "done";
  }
  return "?";
}

double HomingError::distance_m() const {
  return std::hypot(forward_m, left_m);
}

HomingError robot_error(const HomingMeasurement& m, double camera_forward_m, double camera_left_m) {
  // Robot frame now: camera at c, site camera at s + c. At the site the
  // robot's heading is g from now, so its camera sat at R(g) c from its
  // wheel-axis midpoint: that midpoint is at s + c - R(g) c.
  const double c = std::cos(m.turn_rad), s = std::sin(m.turn_rad);
  HomingError e;
  e.forward_m = m.forward_m + camera_forward_m - (c * camera_forward_m - s * camera_left_m);
  e.left_m = m.left_m + camera_left_m - (s * camera_forward_m + c * camera_left_m);
  e.turn_rad = wrap_angle(m.turn_rad);
  return e;
}

Eigen::Vector2d look_offset_from_turns(const std::vector<HomingMeasurement>& turns) {
  Eigen::Matrix2d ata = Eigen::Matrix2d::Zero();
  Eigen::Vector2d atb = Eigen::Vector2d::Zero();
  int used = 0;
  double widest = 0.0;
  for (const HomingMeasurement& m : turns) {
    if (m.status != MeasurementStatus::ok) continue;
    const double c = std::cos(m.turn_rad), s = std::sin(m.turn_rad);
    Eigen::Matrix2d a;
    a << c - 1.0, -s, s, c - 1.0;
    ata += a.transpose() * a;
    atb += a.transpose() * Eigen::Vector2d(m.forward_m, m.left_m);
    widest = std::max(widest, std::abs(wrap_angle(m.turn_rad)));
    ++used;
  }
  if (used < 2 || widest < std::numbers::pi / 6) {
    throw std::invalid_argument(
        "look offset: needs two or more ok turns, one of them 30 deg or more");
  }
  return ata.ldlt().solve(atb);
}

HomingServo::HomingServo(const HomingServoParams& params) : params_(params) {
  validate(params_);
}

HomingCommand HomingServo::update(const HomingMeasurement& m) {
  HomingCommand cmd;
  cmd.phase = phase_;
  if (m.status != MeasurementStatus::ok) return cmd;
  const HomingServoParams& p = params_;
  const HomingError raw = robot_error(m, p.camera_forward_m, p.camera_left_m);
  if (raw.distance_m() < p.fine_position_m && std::abs(raw.turn_rad) < p.fine_turn_rad) {
    if (!smoothing_) {
      smoothed_ = raw;
      smoothing_ = true;
    } else {
      const double a = p.fine_smoothing;
      smoothed_.forward_m += a * (raw.forward_m - smoothed_.forward_m);
      smoothed_.left_m += a * (raw.left_m - smoothed_.left_m);
      smoothed_.turn_rad += a * (raw.turn_rad - smoothed_.turn_rad);
    }
    cmd.error = smoothed_;
  } else {
    smoothing_ = false;
    cmd.error = raw;
  }
  const double e = cmd.error.distance_m();
  const double g = cmd.error.turn_rad;

  // Phase changes: a step is done at its tolerance and resumed above
  // hysteresis x it (so a measurement's noise does not toggle them); step i
  // after the turn in place began only above turn_resume_position_m.
  const double resume_p = p.turn_resume_position_m;
  const double resume_h = p.hysteresis * p.heading_tolerance_rad;
  switch (phase_) {
    case HomingPhase::position:
      if (e <= p.position_tolerance_m) phase_ = HomingPhase::orientation;
      break;
    case HomingPhase::orientation:
      if (e > resume_p) {
        phase_ = HomingPhase::position;
      } else if (std::abs(g) <= p.heading_tolerance_rad) {
        phase_ = HomingPhase::done;
      }
      break;
    case HomingPhase::done:
      if (e > resume_p) {
        phase_ = HomingPhase::position;
      } else if (std::abs(g) > resume_h) {
        phase_ = HomingPhase::orientation;
      }
      break;
  }
  if (phase_ == HomingPhase::orientation && std::abs(g) <= p.heading_tolerance_rad) {
    phase_ = HomingPhase::done;
  }
  cmd.phase = phase_;

  // The commands act on this frame's error (the smoothed one lags: acting
  // on it overshoots); only the phase decisions above use the smoothed one.
  if (phase_ == HomingPhase::position) {
    // eta_2: the base toward the site point (or away from it, backing up,
    // when the site is behind); eta_1 = -lambda_1(e) e along the heading,
    // scaled by cos(bearing) and only inside the drive cone.
    const double bearing = std::atan2(raw.left_m, raw.forward_m);
    const bool reverse = std::abs(bearing) > std::numbers::pi / 2;
    const double facing = reverse ? wrap_angle(bearing - std::numbers::pi) : bearing;
    cmd.omega_rad_s =
        std::clamp(p.bearing_gain * facing, -p.max_yaw_rate_rad_s, p.max_yaw_rate_rad_s);
    if (std::abs(facing) < p.drive_cone_rad) {
      const double d = raw.distance_m();
      const double v = p.position(d) * d * std::cos(facing);
      cmd.v_m_s = (reverse ? -1.0 : 1.0) * std::min(v, p.max_speed_m_s);
    }
  } else if (phase_ == HomingPhase::orientation) {
    // eta_3 = -lambda_3(gamma) gamma: the rotation in place.
    const double t = raw.turn_rad;
    cmd.omega_rad_s = std::clamp(p.orientation(t) * t, -p.max_yaw_rate_rad_s, p.max_yaw_rate_rad_s);
  }
  return cmd;
}

}  // namespace ceilnav::nav
