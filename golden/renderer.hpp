// Scene renderer: the frame a camera with a known pose sees of retroreflective
// tape on the ceiling under an on-axis flash. Used by every accuracy test and by
// `ceilnav demo`. Geometry, radiometry, sampling and error bounds are derived in
// docs/renderer.md.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "common/camera_config.hpp"
#include "golden/scene.hpp"

namespace ceilnav::golden {

struct RenderParams {
  int supersample = 8;         // N: N x N jittered-stratified samples over a pixel near a tape edge
  double blur_sigma_px = 0.5;  // Gaussian blur on the float image; 0 = none
  double noise_sigma_grey = 2.0;
  uint64_t noise_seed = 1;
  double background_grey = 16.0;
  // grey = background + tape_gain * reflectance / r^2, r = camera-to-point range
  // in m: retroreflective return of an on-axis flash.
  double tape_gain = 800.0;
  bool apply_distortion = true;
  // false: every pixel gets all N x N samples (reference mode for tests; slow).
  bool adaptive_sampling = true;
};

// How the adaptive sampler treated the pixels of one frame.
struct RenderStats {
  int64_t background_pixels = 0;  // footprint misses every tape (or the ceiling): no samples
  int64_t interior_pixels = 0;    // footprint inside a tape: 2 x 2 midpoint samples
  int64_t edge_pixels = 0;        // footprint crosses an edge: N x N jittered samples
  int64_t samples = 0;            // ray-ceiling evaluations in total
};

// The ray through a pixel centre in normalised undistorted coordinates (x, y)
// and its Jacobian d(x, y)/d(u, v): a sub-sample at offset (a, b) px from the
// centre has the ray (x + j00 a + j01 b, y + j10 a + j11 b) (local affine
// approximation, error bounded by affine_undistortion_error_px). valid = false
// where the distortion model folds over.
struct PixelRay {
  double x, y;
  double j00, j01, j10, j11;
  bool valid;
};

// The rays of every pixel centre, row-major (cached per camera; shared with the
// tape renderer). distorted = false: the pinhole rays K^-1 (u, v, 1).
std::shared_ptr<const std::vector<PixelRay>> pixel_rays(const host::CameraConfig& camera,
                                                        bool distorted);
// The same for a renderer whose scene has its own heights (the corridor, the
// structured ceilings): only the camera's lens and image size count, its
// camera and ceiling heights (which pixel_rays checks) are not looked at.
std::shared_ptr<const std::vector<PixelRay>> lens_pixel_rays(const host::CameraConfig& camera,
                                                             bool distorted);

// The n x n jittered-stratified sub-pixel offsets (a[k], b[k] in [-0.5, 0.5))
// that the tape renderer uses for pixel `pixel_index` (row-major index): a
// fixed function of the index, so frames are reproducible. a, b hold n*n.
void jittered_offsets(std::size_t pixel_index, int n, double* a, double* b);

// What render_float does after the radiance: adds params.background_grey, the
// Gaussian blur and the counter-based Gaussian noise, in place (CV_64FC1).
void finish_render(cv::Mat& image, const RenderParams& params);

// Normalised undistorted coordinates (x, y) = (X/Z, Y/Z) of the ray through a
// distorted pixel position: the inverse of OpenCV's distortion model, by Newton
// iteration to ~1e-15. nullopt where the model is not invertible (fold-over).
std::optional<Eigen::Vector2d> undistort_pixel(const host::CameraConfig& camera,
                                               const Eigen::Vector2d& pixel);

// Largest error, in (undistorted) pixels, of the renderer's per-pixel affine
// approximation of the undistortion over the pixel footprint, measured at every
// pixel corner of the image (where the quadratic remainder is largest). 0 for a
// camera without distortion.
double affine_undistortion_error_px(const host::CameraConfig& camera);

// The frame before quantisation: CV_64FC1, image_height x image_width;
// background + tape radiance, blurred, plus noise. Throws std::invalid_argument
// on bad parameters or when the ceiling is not above the camera.
cv::Mat render_float(const host::CameraConfig& camera, const CeilingScene& scene,
                     const CameraPose& pose, const RenderParams& params,
                     RenderStats* stats = nullptr);

// A camera in any orientation: its centre in the world and the world ->
// camera rotation (rows: the camera's x right, y down, z forward axes in world
// coordinates; X_cam = R (X_world - centre)). For a robot's camera with mount
// errors in yaw, pitch and roll, or at another height than the CameraConfig's
// (the config's intrinsics and ceiling_height_m still apply).
struct CameraView {
  Eigen::Vector3d centre;
  Eigen::Matrix3d world_to_camera;
};
// The view of a CameraPose: camera_centre and world_to_camera_rotation(yaw,
// pitch of the config).
CameraView camera_view(const host::CameraConfig& camera, const CameraPose& pose);

// The tape radiance alone (CV_64FC1, no background, blur or noise) seen from
// `view`: render_float(camera, scene, pose) is exactly (bit for bit)
// finish_render(render_radiance(camera, scene, camera_view(camera, pose))).
// For sums of several views (motion blur) finished once. Throws
// std::invalid_argument as render_float, and for a non-finite view.
cv::Mat render_radiance(const host::CameraConfig& camera, const CeilingScene& scene,
                        const CameraView& view, const RenderParams& params,
                        RenderStats* stats = nullptr);

// The camera's 8-bit frame: render_float rounded to nearest and saturated,
// CV_8UC1, image_height x image_width.
cv::Mat render_frame(const host::CameraConfig& camera, const CeilingScene& scene,
                     const CameraPose& pose, const RenderParams& params);

}  // namespace ceilnav::golden
