// The simulated robot: a differential drive whose true pose moves exactly as
// the (limited) commands say, and whose wheel encoders report that motion
// through scale errors, random slip and count quantisation; and the camera
// mounted on it. Model and parameters: docs/navigation.md, "Robot".
#pragma once

#include <Eigen/Core>
#include <Eigen/Dense>
#include <cstdint>

#include "common/camera_config.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::sim {

struct RobotParams {
  double wheel_base_m = 0.40;         // b: distance between the wheels' contact points
  double wheel_radius_m = 0.075;      // nominal radius (what the odometry assumes)
  int encoder_counts_per_rev = 4096;  // counts per wheel revolution
  // True radius / nominal radius of each wheel (1 = no scale error).
  double left_scale = 1.0, right_scale = 1.0;
  // Random slip: the ground travel a wheel makes without turning, independent
  // increments of variance slip_sigma^2 per metre of that wheel's travel, so
  // over L metres its standard deviation is slip_sigma * sqrt(L)
  // (unit m / sqrt(m)). 0 = no slip.
  double slip_sigma_sqrt_m = 0.004;
  // Tyre scrub in turns: the heading change the wheels report differs from the
  // true one by independent increments of variance scrub_sigma^2 per radian
  // the wheels' rolling turns (unit rad / sqrt(rad)); the filter's
  // yaw_var_per_rad. 0 = none (the default: see docs/navigation.md, "Robot",
  // on the slip's phantom turning at 100 Hz).
  double scrub_sigma_sqrt_rad = 0.0;
  // Limits, applied in this order to each command: |v| <= max_speed, then
  // |dv/dt| <= max_accel; |omega| <= max_yaw_rate, then |domega/dt| <=
  // max_yaw_accel.
  double max_speed_m_s = 1.0;
  double max_accel_m_s2 = 1.0;
  double max_yaw_rate_rad_s = 1.5;
  double max_yaw_accel_rad_s2 = 3.0;
  uint64_t seed = 1;  // the slip's random stream

  double nominal_m_per_count() const;
};

// Throws std::invalid_argument naming the first bad field.
void validate(const RobotParams& params);

class Robot {
 public:
  explicit Robot(const RobotParams& params, const nav::Pose2& start = {}, double t_s = 0.0);

  // One odometry tick of length dt: limits the commands (speed, then
  // acceleration from the current velocity), holds the resulting v and omega
  // over the tick, moves the true pose along that arc exactly (nav::advance)
  // and returns what the encoders report: each wheel's accumulated counts
  // (floor of its true rotation in counts since the start, so a fraction of a
  // count is carried to the next tick, never lost) times the NOMINAL metres
  // per count, stamped with the time at the end of the tick.
  nav::OdometryStep step(double dt_s, double v_cmd_m_s, double omega_cmd_rad_s);

  const nav::Pose2& pose() const { return pose_; }  // true pose
  double time_s() const { return t_s_; }
  double speed_m_s() const { return v_; }           // after the limits
  double yaw_rate_rad_s() const { return omega_; }  // after the limits
  const RobotParams& params() const { return params_; }
  // Total encoder counts of each wheel since the start.
  int64_t left_counts() const { return left_counts_; }
  int64_t right_counts() const { return right_counts_; }

 private:
  double normal();

  RobotParams params_;
  nav::Pose2 pose_;
  double t_s_ = 0.0, v_ = 0.0, omega_ = 0.0;
  // True rotation of each wheel since the start, in counts (real).
  double left_rotation_ = 0.0, right_rotation_ = 0.0;
  int64_t left_counts_ = 0, right_counts_ = 0;
  uint64_t rng_state_;
};

// The camera on the robot: its centre `forward_m` ahead of and `left_m` to
// the left of the wheel-axis midpoint, at the CameraConfig's camera height,
// looking along the robot's heading pitched up by the CameraConfig's pitch,
// with small mounting errors: yaw (about the world vertical, CCW positive),
// pitch (added to the configured pitch) and roll (about the optical axis;
// positive turns the camera's x axis toward its y axis, so the image content
// turns counter-clockwise).
struct CameraMount {
  double forward_m = 0.0, left_m = 0.0;
  double yaw_error_rad = 0.0, pitch_error_rad = 0.0, roll_error_rad = 0.0;
};

// A camera anywhere: its centre in the world and the world -> camera
// rotation (rows: the camera's x right, y down, z forward axes in world
// coordinates; X_cam = R (X_world - centre)).
struct CameraWorldPose {
  Eigen::Vector3d centre;
  Eigen::Matrix3d world_to_camera;
  // Heading the camera looks along (CCW from +X): the horizontal direction
  // of its forward + down axes, defined for any pitch from 0 to 90 deg.
  double heading_rad() const;
};

// R = M(roll) * world_to_camera_rotation(yaw + yaw error, pitch + pitch
// error), M(roll) = [c s 0; -s c 0; 0 0 1]: with zero errors exactly
// golden::world_to_camera_rotation of the robot's yaw and the pitch.
CameraWorldPose camera_pose(const host::CameraConfig& camera, const CameraMount& mount,
                            const nav::Pose2& robot);

}  // namespace ceilnav::sim
