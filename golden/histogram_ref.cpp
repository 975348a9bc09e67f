#include "golden/histogram_ref.hpp"

#include <cmath>
#include <cstdint>

#include <opencv2/imgproc.hpp>

namespace ceilnav::golden {

stream::HistogramResults histogram_ref(const cv::Mat& img8u) {
  CV_Assert(img8u.type() == CV_8UC1);
  stream::HistogramResults out;
  if (img8u.empty()) {
    return out;
  }
  const int channels[] = {0};
  const int hist_size[] = {256};
  const float range[] = {0.0f, 256.0f};
  const float* ranges[] = {range};
  cv::Mat hist;
  cv::calcHist(&img8u, 1, channels, cv::Mat(), hist, 1, hist_size, ranges);
  for (int b = 0; b < 256; ++b) {
    // calcHist counts in float: exact for counts below 2^24 (a 2048x2048 frame has 2^22).
    out.bins[static_cast<size_t>(b)] = static_cast<uint32_t>(std::lround(hist.at<float>(b)));
  }
  return out;
}

}  // namespace ceilnav::golden
