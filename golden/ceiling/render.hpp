// The frame a camera looking up sees of a structured ceiling (ceiling.hpp):
// each pixel's footprint on the ceiling plane, integrated exactly where it
// lies on one paint (the light is linear in X, Y: its value at the centre is
// the footprint's mean) and by N x N jittered-stratified samples where it
// meets a paint border; then gain, blur and the golden renderer's
// counter-based noise (golden::finish_render). docs/renderer.md,
// "Structured ceilings".
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>

#include "common/camera_config.hpp"
#include "golden/ceiling/ceiling.hpp"
#include "golden/renderer.hpp"

namespace ceilnav::golden::ceiling {

struct RenderParams {
  int supersample = 4;            // N of the N x N samples at paint borders (1 .. 16)
  bool adaptive_sampling = true;  // false: N x N everywhere (reference)
  bool apply_distortion = true;
  double gain_grey = 90.0;  // grey levels per unit of radiance (exposure x gain)
  double background_grey = 0.0;
  double blur_sigma_px = 0.5;
  double noise_sigma_grey = 2.0;
  uint64_t noise_seed = 1;
};

// The camera of a pose: centre (x, y, height) and the world -> camera
// rotation R = Rx(pitch_error) Ry(roll_error) R0, R0 =
// golden::world_to_camera_rotation(yaw, 90 deg): the optical axis up, the
// image's v axis (down the image) along the heading, u to the robot's
// right; a positive pitch error tilts the axis toward the heading, a
// positive roll error toward the left.
CameraView view_of(const Pose& pose);

// Where the ceiling point (x, y) appears (pixels, with the lens distortion
// when `distorted`); nullopt behind the camera.
std::optional<Eigen::Vector2d> project(const host::CameraConfig& camera, const Ceiling& ceiling,
                                       const Pose& pose, double x_m, double y_m,
                                       bool distorted = true);

// The radiance per pixel (CV_64FC1), no gain, blur or noise. Throws
// CeilingError for a bad ceiling or lighting, std::invalid_argument for bad
// parameters or a camera not below the ceiling.
cv::Mat render_radiance(const host::CameraConfig& camera, const Ceiling& ceiling,
                        const Lighting& lighting, const Pose& pose, const RenderParams& params);
// gain x radiance, background, blur, noise; rounded and saturated: CV_8UC1.
cv::Mat render_frame(const host::CameraConfig& camera, const Ceiling& ceiling,
                     const Lighting& lighting, const Pose& pose, const RenderParams& params);

}  // namespace ceilnav::golden::ceiling
