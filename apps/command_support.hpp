// What the tape commands (demo, run, render, accuracy) share: backend
// selection, output files, angle and error arithmetic, random poses.
#pragma once

#include <filesystem>
#include <random>
#include <string>

#include <opencv2/core.hpp>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "common/camera_config.hpp"
#include "golden/scene.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {

// a wrapped into [-pi, pi] (std::remainder by 2 pi).
double wrap_angle(double a);

// Root mean square and greatest magnitude of the errors added.
struct Rms {
  double sum2 = 0.0, max_abs = 0.0;
  int n = 0;
  void add(double e) {
    sum2 += e * e;
    max_abs = std::max(max_abs, std::abs(e));
    ++n;
  }
  double rms() const { return n > 0 ? std::sqrt(sum2 / n) : 0.0; }
};

// `relative` in the output folder's staging area. Encoded in memory, then
// written with every error checked (a full disk or a file size limit is an
// error, not a truncated PNG).
void write_png(const OutputFolder& folder, const std::filesystem::path& relative,
               const cv::Mat& img);

// scene.yaml, read back: cv::FileStorage does not report every write error.
void write_scene(const OutputFolder& folder, const host::CameraConfig& camera);

// frame_0000.png, frame_0001.png, ...
std::string frame_name(int i);

// --overlay-every N: whether the frame at `index` (0, 1, ... in processing
// order) gets its own overlay, overlays/<frame name>.png. Every N-th frame
// from frame 0 (0, N, 2N, ...); N = 0: none (the command's single overlay, if
// it has one, is unchanged). Throws std::runtime_error for N < 0.
bool overlay_due(int every, size_t index);
// Throws std::runtime_error unless N >= 0 (before any output is written).
void check_overlay_every(int every);
// The overlay of frame file `frame_file` (frame_0003.png, or a recorded
// frame's name): its stem with .png, e.g. frame_0003.png. Relative to the
// overlays/ folder.
std::filesystem::path overlay_file_name(const std::string& frame_file);

// A camera pose drawn uniformly from the accuracy ranges: pitch in
// [pitch_min, pitch_max] deg, yaw in [-yaw_max, yaw_max] deg, lateral offset in
// [-offset_max, offset_max] m, x in [0, 10) m, noise and blur in [0, max).
struct SampledPose {
  golden::CameraPose pose;
  double pitch_deg, noise, blur;
};
SampledPose sample_pose(std::mt19937_64& rng, double pitch_min, double pitch_max, double yaw_max,
                        double offset_max, double noise_max, double blur_max);

}  // namespace ceilnav::app
