#include "golden/orientation_ref.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

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

double major_orientation_deg(const std::vector<double>& h) {
  const int n = static_cast<int>(h.size());
  int best = -1;
  for (int k = 0; k < n; ++k) {
    if (h[static_cast<std::size_t>(k)] > 0.0 &&
        (best < 0 || h[static_cast<std::size_t>(k)] > h[static_cast<std::size_t>(best)]))
      best = k;
  }
  if (best < 0) return std::numeric_limits<double>::quiet_NaN();
  // The centroid of the peak bin and two on each side (circular): the
  // bins' own mean angle, robust to a peak one or two bins wide.
  double sw = 0.0, swk = 0.0;
  for (int d = -2; d <= 2; ++d) {
    const double w = h[static_cast<std::size_t>((best + d + n) % n)];
    sw += w;
    swk += w * d;
  }
  double deg = (best + swk / sw) * 90.0 / n;
  deg = std::fmod(deg, 90.0);
  if (deg < 0.0) deg += 90.0;
  return deg >= 45.0 ? deg - 90.0 : deg;
}

}  // namespace ceilnav::golden
