// Threshold and background level for the LUT, chosen from the device's
// histogram of the camera grey (what the host does between frames).
#pragma once

#include <cstdint>

#include "stream/config.hpp"
#include "stream/results.hpp"

namespace ceilnav::host {

struct ThresholdOptions {
  double noise_k = 6.0;          // tunable: threshold >= background + noise_k * sigma
  double min_margin_grey = 3.0;  // tunable: ... and >= background + this
  double peak_fraction = 0.15;   // tunable: ... and >= background + this * (peak - background)
  uint32_t peak_min_pixels = 16; // the peak is the highest grey with at least this many pixels at or above it
};

struct ThresholdSettings {
  uint8_t threshold = 255;         // mask = grey >= threshold
  uint8_t background_level = 0;    // run weights w = max(0, grey - background_level)
  double background_grey = 0.0;    // histogram median
  double noise_sigma_grey = 0.0;   // median - 15.87th percentile (Gaussian sigma, robust)
  uint8_t peak_grey = 0;
  bool usable = false;             // a bright population well above the noise exists

  friend bool operator==(const ThresholdSettings&, const ThresholdSettings&) = default;
};

// Background = median (the tape covers far less than half the frame); noise
// sigma from the lower half of the histogram, which the bright tape does not
// touch; threshold the largest of the three bounds in ThresholdOptions.
ThresholdSettings choose_threshold(const stream::HistogramResults& hist,
                                   const ThresholdOptions& opt = {});

// LUT for the settings: identity remap, mask = grey >= threshold.
stream::PipelineConfig apply_threshold(stream::PipelineConfig cfg, const ThresholdSettings& s);

}  // namespace ceilnav::host
