// `ceilnav pattern` and `ceilnav pattern-accuracy`: seed 003's standard pattern
// (docs/pattern.md).
#pragma once

#include <cstdint>
#include <string>

namespace ceilnav::app {

struct PatternOptions {
  std::string out_dir;     // CSV + overlay PNG (+ rendered frames for the built-in scene)
  std::string frames_dir;  // recorded frames instead of the built-in scene
  std::string scene_file;  // camera YAML (with --frames)
  std::string database;    // pattern database YAML (with --frames; built-in scene: written)
  double noise_sigma = 3.0;
  uint64_t seed = 1;
  std::string backend = "fast";  // fast | model | rtl (see drivers::DeviceOptions)
  bool quiet = false;
  // N > 0: also overlays/<frame name>.png of every N-th frame (frame 0
  // included); 0: only overlay.png of the last frame.
  int overlay_every = 0;
};
int run_pattern(const PatternOptions& o);

struct PatternAccuracyOptions {
  int width = 640, height = 480;
  double noise_sigma = 3.0;
  double blur_sigma = 0.5;
  // The camera's blur and noise as the host believes them (its calibration);
  // negative: the rendered values (a perfect calibration).
  double calib_blur_sigma = -1.0;
  double calib_noise_sigma = -1.0;
  bool distortion = true;
  int supersample = 4;  // renderer's N x N samples per edge pixel
  int betas = 2;        // co-azimuth samples per (D, theta) besides the seed's +-90 deg
  uint64_t seed = 1;
  std::string backend = "fast";  // fast | model | rtl
  std::string csv;               // per-frame errors, optional
  std::string plot;              // PNG of the error curves, optional
  bool require = false;          // exit 1 unless the bars hold (docs/pattern.md)
  bool swing_height = false;     // the swing and height error analysis instead (eq. 57-70)
  // The camera's actual photometry, rendered but not told to the host (it
  // calibrates from each frame unless self_calibrate is off).
  // (golden::pattern::CameraPhotometry).
  double gain = 1.0, offset_grey = 0.0, vignetting = 0.0;
  bool self_calibrate = true;
  bool photometric_sweep = false;  // the table of docs/pattern.md instead of one study
};
int run_pattern_accuracy(const PatternAccuracyOptions& o);

}  // namespace ceilnav::app
