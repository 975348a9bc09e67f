// The corridor renderer: the frame a camera at a Pose sees of a Corridor
// (corridor.hpp), anti-aliased by adaptive supersampling, with motion blur
// (sub-exposures along a moving pose), gain, blur and the golden renderer's
// counter-based noise. docs/renderer.md, "Corridor scenes".
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "common/camera_config.hpp"
#include "golden/corridor/corridor.hpp"
#include "golden/renderer.hpp"

namespace ceilnav::golden::corridor {

struct RenderParams {
  // N: N x N jittered-stratified samples (golden::jittered_offsets) over a
  // pixel whose footprint meets a face border or a feature's border.
  int supersample = 8;
  // false: every pixel gets all N x N samples (reference mode; slow).
  bool adaptive_sampling = true;
  bool apply_distortion = true;
  // Exposure time x gain: grey levels per unit of radiance (albedo x light).
  double gain_grey = 100.0;
  // As golden::RenderParams (finish_render): black level, blur, noise.
  double background_grey = 0.0;
  double blur_sigma_px = 0.5;
  double noise_sigma_grey = 2.0;
  uint64_t noise_seed = 1;
};

struct RenderStats {
  int64_t uniform_pixels = 0;  // footprint on one face in one paint: centre + corner rays
  int64_t edge_pixels = 0;     // N x N samples
  int64_t samples = 0;         // 1 per uniform pixel + N x N per edge pixel
};

// The radiance (albedo x light, or a lamp's radiance) per pixel, CV_64FC1,
// no gain, blur or noise, seen from `view` (camera intrinsics and image size
// from `camera`). Throws std::invalid_argument on bad parameters and
// CorridorError on a bad corridor or a view outside it.
cv::Mat render_radiance(const host::CameraConfig& camera, const Corridor& corridor,
                        const CameraView& view, const RenderParams& params,
                        RenderStats* stats = nullptr);

// An exposure during which the camera moves from `start` to `end` (every
// pose field linearly): the mean of `subexposures` radiances at the poses
// interpolate(start, end, (k + 1/2) / K), as sim::render_drive_float does
// for a drive. The frame's truth is that of the mid-exposure pose.
struct Exposure {
  Pose start, end;
  int subexposures = 1;
};
Pose interpolate(const Pose& a, const Pose& b, double f);
Pose mid_exposure(const Exposure& exposure);

// The frame before quantisation: gain_grey x radiance, then
// golden::finish_render (background, Gaussian blur, noise). CV_64FC1.
cv::Mat render_float(const host::CameraConfig& camera, const Corridor& corridor,
                     const Exposure& exposure, const RenderParams& params,
                     RenderStats* stats = nullptr);
cv::Mat render_float(const host::CameraConfig& camera, const Corridor& corridor, const Pose& pose,
                     const RenderParams& params, RenderStats* stats = nullptr);
// render_float rounded to nearest and saturated: CV_8UC1.
cv::Mat render_frame(const host::CameraConfig& camera, const Corridor& corridor,
                     const Exposure& exposure, const RenderParams& params);
cv::Mat render_frame(const host::CameraConfig& camera, const Corridor& corridor, const Pose& pose,
                     const RenderParams& params);

}  // namespace ceilnav::golden::corridor
