#include "host/auto_threshold.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ceilnav::host {

namespace {

// Smallest g with cumulative count(<= g) >= q * total.
template <size_t N>
int quantile(const std::array<uint64_t, N>& h, uint64_t total, double q) {
  const double target = q * static_cast<double>(total);
  uint64_t acc = 0;
  for (size_t g = 0; g < N; ++g) {
    acc += h[g];
    if (static_cast<double>(acc) >= target) return static_cast<int>(g);
  }
  return static_cast<int>(N) - 1;
}

}  // namespace

ThresholdSettings choose_threshold(const stream::HistogramResults& hist,
                                   const ThresholdOptions& opt) {
  ThresholdSettings s;
  std::array<uint64_t, 256> h{};
  uint64_t total = 0;
  for (size_t g = 0; g < 256; ++g) {
    h[g] = hist.bins[g];
    total += h[g];
  }
  if (total == 0) return s;

  const int bg = quantile(h, total, 0.5);
  std::array<uint64_t, 256> dev{};  // histogram of |grey - background|
  for (int g = 0; g < 256; ++g)
    dev[static_cast<size_t>(std::abs(g - bg))] += h[static_cast<size_t>(g)];
  const double sigma = std::max(0.5, 1.4826 * quantile(dev, total, 0.5));
  const int peak = quantile(h, total, opt.peak_quantile);

  s.background_grey = bg;
  s.noise_sigma_grey = sigma;
  s.peak_grey = static_cast<uint8_t>(peak);
  const double t = std::ceil(bg + std::max(opt.noise_k * sigma, opt.peak_fraction * (peak - bg)));
  s.usable = t <= static_cast<double>(peak) && t <= 255.0;
  s.threshold = static_cast<uint8_t>(std::clamp(t, 1.0, 255.0));
  s.background_level =
      static_cast<uint8_t>(std::clamp(std::lround(bg + opt.weight_noise_k * sigma), 0L, 255L));
  return s;
}

stream::PipelineConfig apply_threshold(stream::PipelineConfig cfg, const ThresholdSettings& s) {
  cfg.lut = stream::threshold_lut(s.threshold);
  cfg.background_level = s.background_level;
  return cfg;
}

}  // namespace ceilnav::host
