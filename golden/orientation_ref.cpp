#include "golden/orientation_ref.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "fixedpoint/orientation.hpp"

namespace ceilnav::golden {

std::vector<double> orientation_histogram_ref(const cv::Mat& grey, const OrientationParams& p) {
  if (grey.type() != CV_8UC1 || grey.cols < 3 || grey.rows < 3) {
    throw std::invalid_argument(
        "orientation_histogram_ref: the image must be 8-bit grey, >= 3 x 3");
  }
  if (p.bins < 1 || p.bins > 4096 || !std::isfinite(p.min_magnitude) || p.min_magnitude < 0.0) {
    throw std::invalid_argument("orientation_histogram_ref: bins 1 .. 4096, min_magnitude >= 0");
  }
  cv::Mat gx, gy, mag, ang;
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3);
  cv::cartToPolar(gx, gy, mag, ang, true);
  std::vector<double> h(static_cast<std::size_t>(p.bins), 0.0);
  const double per_bin = 90.0 / p.bins;
  for (int y = 1; y + 1 < grey.rows; ++y) {
    const float* m = mag.ptr<float>(y);
    const float* a = ang.ptr<float>(y);
    for (int x = 1; x + 1 < grey.cols; ++x) {
      if (!(m[x] > p.min_magnitude)) continue;
      // Bin k is centred on k x 90 / bins degrees (rounded to the nearest).
      const double folded = std::fmod(static_cast<double>(a[x]), 90.0);
      const int k = static_cast<int>(std::lround(folded / per_bin)) % p.bins;
      h[static_cast<std::size_t>(k)] += m[x];
    }
  }
  return h;
}

std::vector<uint32_t> orientation_histogram_fixed(const cv::Mat& grey,
                                                  const OrientationFixedParams& p) {
  namespace fo = fp::orientation;
  if (grey.type() != CV_8UC1 || grey.cols < 3 || grey.rows < 3) {
    throw std::invalid_argument(
        "orientation_histogram_fixed: the image must be 8-bit grey, >= 3 x 3");
  }
  if (p.bins < 1 || p.bins > fo::kMaxBins || p.threshold < 0 ||
      p.threshold >= (1 << fo::kThresholdBits)) {
    throw std::invalid_argument("orientation_histogram_fixed: bins 1 .. 256, threshold 0 .. 4095");
  }
  cv::Mat gx, gy;
  cv::Sobel(grey, gx, CV_16S, 1, 0, 3);
  cv::Sobel(grey, gy, CV_16S, 0, 1, 3);
  std::vector<uint32_t> h(static_cast<std::size_t>(p.bins), 0u);
  for (int y = 1; y + 1 < grey.rows; ++y) {
    const int16_t* gxr = gx.ptr<int16_t>(y);
    const int16_t* gyr = gy.ptr<int16_t>(y);
    for (int x = 1; x + 1 < grey.cols; ++x) {
      const fo::Vote v = fo::vote(gxr[x], gyr[x], static_cast<uint32_t>(p.threshold),
                                  static_cast<uint32_t>(p.bins));
      if (!v.valid) continue;
      uint32_t& b = h[v.bin];
      b = fo::add_saturating(b, v.weight);
    }
  }
  return h;
}

}  // namespace ceilnav::golden
