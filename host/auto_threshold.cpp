#include "host/auto_threshold.hpp"

#include <algorithm>
#include <cmath>

namespace ceilnav::host {

namespace {

// Smallest grey g with cumulative count(<= g) >= q * total.
int percentile(const stream::HistogramResults& hist, uint64_t total, double q) {
  const double target = q * static_cast<double>(total);
  uint64_t cum = 0;
  for (int g = 0; g < 256; ++g) {
    cum += hist.bins[static_cast<size_t>(g)];
    if (static_cast<double>(cum) >= target) return g;
  }
  return 255;
}

}  // namespace

ThresholdSettings choose_threshold(const stream::HistogramResults& hist,
                                   const ThresholdOptions& opt) {
  ThresholdSettings s;
  uint64_t total = 0;
  for (uint32_t b : hist.bins) total += b;
  if (total == 0) return s;

  const int median = percentile(hist, total, 0.5);
  const int lower = percentile(hist, total, 0.158655);  // one sigma below the mean
  s.background_grey = median;
  s.noise_sigma_grey = std::max(0.5, static_cast<double>(median - lower));

  uint64_t above = 0;
  int peak = 0;
  for (int g = 255; g >= 0; --g) {
    above += hist.bins[static_cast<size_t>(g)];
    if (above >= opt.peak_min_pixels) {
      peak = g;
      break;
    }
  }
  s.peak_grey = static_cast<uint8_t>(peak);

  const double t = std::max({static_cast<double>(median) + opt.noise_k * s.noise_sigma_grey,
                             static_cast<double>(median) + opt.min_margin_grey,
                             static_cast<double>(median) + opt.peak_fraction * (peak - median)});
  const double t_ceil = std::ceil(t);
  s.usable = t_ceil <= static_cast<double>(peak) && t_ceil <= 255.0;
  s.threshold = static_cast<uint8_t>(std::clamp(t_ceil, 1.0, 255.0));
  s.background_level = static_cast<uint8_t>(std::clamp(median, 0, 255));
  return s;
}

stream::PipelineConfig apply_threshold(stream::PipelineConfig cfg, const ThresholdSettings& s) {
  cfg.lut = stream::threshold_lut(s.threshold);
  cfg.background_level = s.background_level;
  return cfg;
}

}  // namespace ceilnav::host
