// Seed 002's guidance in the loop: a robot (robot.hpp) drives down a
// corridor without tape steered by the turn law (eq. 26-28) on what its
// camera sees. Each frame is rendered at the robot's true pose
// (golden::corridor), goes through the device's edge and hough blocks
// (corridor_device.hpp) and the host's CorridorGuide against a model learnt
// from a learning drive; the wheel turn becomes the differential drive's
// yaw rate (host::corridor::yaw_rate) one frame period later (the frame's
// processing). docs/corridor.md, "Closed loop".
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "golden/corridor/corridor.hpp"
#include "golden/corridor/render.hpp"
#include "host/corridor/corridor_guide.hpp"
#include "sim/robot.hpp"

namespace ceilnav::sim {

// The learning drive of seed 002 section 4.1: `frames` camera poses 1 m
// apart along +X from `start` (its y, height, tilt, swing), the pan
// `start.pan_rad` (the vehicle driven along the axis), with the small wander
// of a driver holding a line: 1 cm laterally and 0.5 deg of pan.
std::vector<golden::corridor::Pose> learning_drive(const golden::corridor::Pose& start,
                                                   int frames = 17);

struct CorridorDriveParams {
  double length_m = 50.0;  // along the axis from the start
  double speed_m_s = 0.5;  // commanded forward speed
  double frame_rate_hz = 5.0;
  double odometry_rate_hz = 50.0;
  // The start, relative to the learnt path: lateral offset (left +) and
  // heading (CCW +).
  double start_offset_m = 0.2;
  double start_heading_rad = -0.05;
  // The turn law's convergence length (TurnLawDesign's default): 0.6 m,
  // six frame periods at the default speed and frame rate.
  double convergence_length_m = 0.6;
  RobotParams robot;
  golden::corridor::RenderParams render;  // noise, blur, supersampling
  uint64_t seed = 1;                      // frame noise (and the robot's slip, robot.seed)
};
// Throws std::invalid_argument naming the first bad field.
void validate(const CorridorDriveParams& params);

// One guided frame.
struct CorridorDriveFrame {
  int index = 0;
  double t_s = 0.0;
  golden::corridor::Pose camera;  // true, at the exposure
  double path_y_m = 0.0;          // the learnt path's y (the learning drive's mean camera y)
  host::corridor::GuideStatus status = host::corridor::GuideStatus::not_found;
  double pan_rad = 0.0, delta_phi_rad = 0.0;  // valid unless not_found
  double shift_m = 0.0, shift_sigma_m = 0.0;  // valid when ok
  double turn_rad = 0.0;                      // eq. 26 (0 unless ok)
  double yaw_rate_cmd_rad_s = 0.0;            // applied from t + 1 / frame rate
  int lines = 0, axis_lines = 0;
  uint32_t edges = 0;
};

struct CorridorDriveResult {
  host::corridor::CorridorModel model;
  int learning_frames = 0, learning_frames_with_pan = 0;
  double path_y_m = 0.0;
  std::vector<CorridorDriveFrame> frames;
  // The camera's true lateral distance from the learnt path, every odometry
  // tick (m, left +): RMS and maximum over the whole drive.
  double lateral_rms_m = 0.0, lateral_max_m = 0.0;
  // The same once captured: from 5 m after the start on.
  double held_rms_m = 0.0, held_max_m = 0.0;
  double final_lateral_m = 0.0;
  double distance_m = 0.0;  // along the axis
  double time_s = 0.0;
  bool completed = false;   // reached length_m (false: left the corridor or timed out)
  std::string stop_reason;  // when not completed
};

// The learning drive at `start` (its pan taken as the axis', 0 at the
// default), then the closed loop from start_offset_m / start_heading_rad
// off the learnt path. `camera` gives the intrinsics and image size;
// `start` the camera's height, tilt and swing. on_frame (optional) sees
// every guided frame and its image.
CorridorDriveResult run_corridor_drive(
    const golden::corridor::Corridor& corridor, const host::CameraConfig& camera,
    const golden::corridor::Pose& start, const CorridorDriveParams& params,
    const std::function<void(const CorridorDriveFrame&, const cv::Mat&)>& on_frame = {});

}  // namespace ceilnav::sim
