#include "sim/robot.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "golden/scene.hpp"

namespace ceilnav::sim {
namespace {

uint64_t mix64(uint64_t z) {  // splitmix64's finaliser
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double unit_interval(uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

double limited(double current, double command, double max_value, double max_rate, double dt) {
  const double target = std::clamp(command, -max_value, max_value);
  return current + std::clamp(target - current, -max_rate * dt, max_rate * dt);
}

void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("RobotParams.") + field + ": " + what);
}

}  // namespace

double RobotParams::nominal_m_per_count() const {
  return 2.0 * std::numbers::pi * wheel_radius_m / encoder_counts_per_rev;
}

void validate(const RobotParams& p) {
  require(p.wheel_base_m > 0.0 && std::isfinite(p.wheel_base_m), "wheel_base_m", "must be > 0");
  require(p.wheel_radius_m > 0.0 && std::isfinite(p.wheel_radius_m), "wheel_radius_m",
          "must be > 0");
  require(p.encoder_counts_per_rev > 0, "encoder_counts_per_rev", "must be > 0");
  require(p.left_scale > 0.0 && std::isfinite(p.left_scale), "left_scale", "must be > 0");
  require(p.right_scale > 0.0 && std::isfinite(p.right_scale), "right_scale", "must be > 0");
  require(p.slip_sigma_sqrt_m >= 0.0 && std::isfinite(p.slip_sigma_sqrt_m), "slip_sigma_sqrt_m",
          "must be >= 0");
  require(p.scrub_sigma_sqrt_rad >= 0.0 && std::isfinite(p.scrub_sigma_sqrt_rad),
          "scrub_sigma_sqrt_rad", "must be >= 0");
  require(p.max_speed_m_s > 0.0, "max_speed_m_s", "must be > 0");
  require(p.max_accel_m_s2 > 0.0, "max_accel_m_s2", "must be > 0");
  require(p.max_yaw_rate_rad_s > 0.0, "max_yaw_rate_rad_s", "must be > 0");
  require(p.max_yaw_accel_rad_s2 > 0.0, "max_yaw_accel_rad_s2", "must be > 0");
}

Robot::Robot(const RobotParams& params, const nav::Pose2& start, double t_s)
    : params_(params), pose_(start), t_s_(t_s), rng_state_(mix64(params.seed ^ 0x5eedULL)) {
  validate(params_);
}

double Robot::normal() {
  // Box-Muller on two counter-based uniforms; u1 in (0, 1].
  rng_state_ = mix64(rng_state_);
  const double u1 = 1.0 - unit_interval(rng_state_);
  rng_state_ = mix64(rng_state_);
  const double u2 = unit_interval(rng_state_);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

nav::OdometryStep Robot::step(double dt_s, double v_cmd_m_s, double omega_cmd_rad_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) throw std::invalid_argument("Robot::step: dt <= 0");
  if (!std::isfinite(v_cmd_m_s) || !std::isfinite(omega_cmd_rad_s)) {
    throw std::invalid_argument("Robot::step: commands must be finite");
  }
  const RobotParams& p = params_;
  v_ = limited(v_, v_cmd_m_s, p.max_speed_m_s, p.max_accel_m_s2, dt_s);
  omega_ = limited(omega_, omega_cmd_rad_s, p.max_yaw_rate_rad_s, p.max_yaw_accel_rad_s2, dt_s);
  const nav::Motion motion{v_ * dt_s, omega_ * dt_s};
  pose_ = nav::advance(pose_, motion);
  t_s_ += dt_s;

  // True ground travel of each wheel; the part not made by turning (slip)
  // is random; the rest turns a wheel of the TRUE radius.
  const double half = 0.5 * p.wheel_base_m * motion.dyaw_rad;
  const double left_travel = motion.distance_m - half;
  const double right_travel = motion.distance_m + half;
  const double left_slip = p.slip_sigma_sqrt_m * std::sqrt(std::abs(left_travel)) * normal();
  const double right_slip = p.slip_sigma_sqrt_m * std::sqrt(std::abs(right_travel)) * normal();
  double left_rolled = left_travel - left_slip, right_rolled = right_travel - right_slip;
  // Scrub: the wheels roll as for a heading change off the true one by w,
  // of variance scrub^2 times the heading change their rolling gives (what
  // the odometry sees, so the filter's noise term is computed from the same).
  if (p.scrub_sigma_sqrt_rad > 0.0 && right_rolled != left_rolled) {
    const double turned = std::abs(right_rolled - left_rolled) / p.wheel_base_m;
    const double w = p.scrub_sigma_sqrt_rad * std::sqrt(turned) * normal();
    left_rolled -= 0.5 * p.wheel_base_m * w;
    right_rolled += 0.5 * p.wheel_base_m * w;
  }
  const double counts_per_m_nominal = 1.0 / p.nominal_m_per_count();
  left_rotation_ += left_rolled / p.left_scale * counts_per_m_nominal;
  right_rotation_ += right_rolled / p.right_scale * counts_per_m_nominal;
  const auto left_now = static_cast<int64_t>(std::floor(left_rotation_));
  const auto right_now = static_cast<int64_t>(std::floor(right_rotation_));
  nav::OdometryStep out{t_s_,
                        static_cast<double>(left_now - left_counts_) * p.nominal_m_per_count(),
                        static_cast<double>(right_now - right_counts_) * p.nominal_m_per_count()};
  left_counts_ = left_now;
  right_counts_ = right_now;
  return out;
}

double CameraWorldPose::heading_rad() const {
  // forward + down: its horizontal part is (cos p + sin p)(cos psi, sin psi)
  // for a pitch p without roll, defined from the horizon to the zenith.
  return std::atan2(world_to_camera(2, 1) + world_to_camera(1, 1),
                    world_to_camera(2, 0) + world_to_camera(1, 0));
}

CameraWorldPose camera_pose(const host::CameraConfig& camera, const CameraMount& mount,
                            const nav::Pose2& robot) {
  const double c = std::cos(robot.yaw_rad), s = std::sin(robot.yaw_rad);
  CameraWorldPose out;
  out.centre = {robot.x_m + c * mount.forward_m - s * mount.left_m,
                robot.y_m + s * mount.forward_m + c * mount.left_m, camera.camera_height_m};
  out.world_to_camera = golden::world_to_camera_rotation(
      robot.yaw_rad + mount.yaw_error_rad, golden::pitch_rad(camera) + mount.pitch_error_rad,
      mount.roll_error_rad);
  return out;
}

}  // namespace ceilnav::sim
