// Test helpers of the corridor model, lateral shift and turn law tests: the
// renderer's truth lines of the ceiling (lamp edges, seams, wall-ceiling
// junctions) at a pose, as ImageLines with Hough-like noise.
#pragma once

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "common/camera_config.hpp"
#include "golden/corridor/corridor.hpp"
#include "host/corridor/corridor_model.hpp"

namespace ceilnav::host::corridor::testing {

constexpr double kDeg = std::numbers::pi / 180.0;

// 640 x 480, f = 500 px, tilt 35 deg, camera 1.0 m high under a 2.8 m
// ceiling: the default corridor scene (examples/corridor/default.yaml).
inline CameraConfig corridor_camera() {
  CameraConfig c;
  c.camera_pitch_deg = 35.0;
  c.camera_height_m = 1.0;
  c.ceiling_height_m = 2.8;
  return c;
}

// Its mount: tilt 35 deg, the given swing.
inline CameraMount corridor_mount(double swing_rad = 0.0) {
  return {35.0 * kDeg, swing_rad, 0.0};
}

inline golden::corridor::Pose pose_at(double y_m, double pan_rad, double x_m = 2.0) {
  golden::corridor::Pose p;
  p.x_m = x_m;
  p.y_m = y_m;
  p.height_m = 1.0;
  p.pan_rad = pan_rad;
  p.tilt_rad = 35.0 * kDeg;
  return p;
}

struct TruthLine {
  ImageLine line;
  double y_m;  // the scene line's Y
};

// The visible ceiling lines along the axis (lamp edges, seams, junctions) at
// `pose`, with Gaussian noise on theta and rho; strength = the visible
// length in pixels.
inline std::vector<TruthLine> ceiling_lines(const CameraConfig& camera,
                                            const golden::corridor::Corridor& corridor,
                                            const golden::corridor::Pose& pose,
                                            double sigma_theta_rad, double sigma_rho_px,
                                            std::mt19937_64& rng) {
  using golden::corridor::LineKind;
  const golden::corridor::FrameTruth truth = golden::corridor::truth_for(camera, corridor, pose);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<TruthLine> out;
  for (const golden::corridor::ImageLine& t : truth.lines) {
    const LineKind k = t.line.kind;
    if (k != LineKind::lamp_edge && k != LineKind::seam && k != LineKind::junction) continue;
    if (!t.defined || !t.visible) continue;
    const double length = (t.to_px - t.from_px).norm();
    if (length < 40.0) continue;  // a Hough would not find a stub
    const double theta = t.theta_rad + sigma_theta_rad * n01(rng);
    const double rho = t.rho_px + sigma_rho_px * n01(rng);
    out.push_back({line_from_homogeneous({std::cos(theta), std::sin(theta), -rho}, length),
                   t.line.point.y()});
  }
  return out;
}

inline std::vector<ImageLine> lines_of(const std::vector<TruthLine>& truth) {
  std::vector<ImageLine> out;
  for (const TruthLine& t : truth) out.push_back(t.line);
  return out;
}

}  // namespace ceilnav::host::corridor::testing
