// Threshold and background level for the LUT, chosen from the device's
// histogram of the camera grey (what the host does between frames).
#pragma once

#include <cstdint>

#include "common/pipeline_config.hpp"
#include "common/results.hpp"

namespace ceilnav::host {

struct ThresholdOptions {
  double noise_k = 4.5;          // tunable: threshold >= background + noise_k * sigma
  double peak_fraction = 0.15;   // tunable: threshold >= background + this * (peak - background)
  double peak_quantile = 0.999;  // the peak is this quantile of the grey histogram
  double weight_noise_k = 2.0;   // tunable: background_level = background + this * sigma
};

struct ThresholdSettings {
  uint8_t threshold = 255;        // mask = grey >= threshold
  uint8_t background_level = 0;   // run weights w = max(0, grey - background_level)
  double background_grey = 0.0;   // histogram median
  double noise_sigma_grey = 0.0;  // 1.4826 * median |grey - background| (robust Gaussian sigma)
  uint8_t peak_grey = 0;          // peak_quantile of the histogram
  bool usable = false;            // a bright population well above the noise exists

  friend bool operator==(const ThresholdSettings&, const ThresholdSettings&) = default;
};

// Background = median grey (the tape covers far less than half the frame);
// noise sigma = 1.4826 * median absolute deviation (at least 0.5 grey);
// threshold = background + max(noise_k sigma, peak_fraction (peak - background));
// background_level = background + weight_noise_k sigma, so that background
// noise adds little weight to the run sums. Measured in docs/results.md.
ThresholdSettings choose_threshold(const stream::HistogramResults& hist,
                                   const ThresholdOptions& opt = {});

// LUT for the settings: identity remap, mask = grey >= threshold.
stream::PipelineConfig apply_threshold(stream::PipelineConfig cfg, const ThresholdSettings& s);

}  // namespace ceilnav::host
