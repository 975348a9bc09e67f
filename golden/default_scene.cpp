#include "golden/default_scene.hpp"

#include <cmath>
#include <numbers>

namespace ceilnav::golden {

host::CameraConfig default_camera() {
  host::CameraConfig c;
  c.image_width = 640;
  c.image_height = 480;
  c.camera_matrix = {520.0, 0.0, 321.7, 0.0, 518.5, 238.2, 0.0, 0.0, 1.0};
  c.distortion_coefficients = {-0.08, 0.015, 0.0004, -0.0003, 0.0};  // mild barrel
  c.camera_pitch_deg = 45.0;
  c.camera_height_m = 0.5;
  c.ceiling_height_m = 2.8;
  c.tape_width_m = 0.05;
  return c;
}

CeilingScene default_corridor(const host::CameraConfig& camera) {
  CorridorOptions o;
  o.second_tape = false;
  return corridor_scene(camera.tape_width_m, o);
}

RenderParams default_render_params() {
  RenderParams p;
  p.supersample = 8;
  p.blur_sigma_px = 0.7;
  p.noise_sigma_grey = 3.0;
  p.noise_seed = 2026;
  p.background_grey = 18.0;
  p.tape_gain = 1200.0;
  return p;
}

std::vector<DrivePose> default_drive(int frames, double step_m) {
  std::vector<DrivePose> drive;
  drive.reserve(static_cast<size_t>(frames));
  double prev_x = 0.0, prev_y = 0.0;
  for (int i = 0; i < frames; ++i) {
    const double x = step_m * i;
    const double phase = 2.0 * std::numbers::pi * x / 14.0;
    DrivePose d;
    d.pose.x_m = x;
    d.pose.y_m = 0.3 * std::sin(phase);
    // Heading follows the weave (the path's tangent) plus a slow sway.
    d.pose.yaw_rad = std::atan(0.3 * 2.0 * std::numbers::pi / 14.0 * std::cos(phase)) +
                     0.05 * std::sin(0.7 * phase);
    d.odometry_m = i == 0 ? 0.0 : std::hypot(x - prev_x, d.pose.y_m - prev_y);
    prev_x = x;
    prev_y = d.pose.y_m;
    drive.push_back(d);
  }
  return drive;
}

}  // namespace ceilnav::golden
