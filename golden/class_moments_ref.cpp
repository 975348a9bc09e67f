#include "golden/class_moments_ref.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace ceilnav::golden {

namespace {

uint64_t exact_u64(double v, const char* what) {
  if (!(v >= 0.0) || v >= 9007199254740992.0 || std::floor(v) != v) {
    throw std::runtime_error(std::string("class_moments_ref: not an exact integer: ") + what);
  }
  return static_cast<uint64_t>(v);
}

}  // namespace

stream::ClassMomentResults class_moments_ref(const cv::Mat& cls8u, const stream::ClassWindow& win) {
  if (cls8u.type() != CV_8UC1) {
    throw std::invalid_argument("class_moments_ref: need a CV_8UC1 class image");
  }
  const int x0 = std::min(win.x0 & 0xFFF, cls8u.cols);
  const int x1 = std::min(win.x1 & 0xFFF, cls8u.cols);
  const int y0 = std::min(win.y0 & 0xFFF, cls8u.rows);
  const int y1 = std::min(win.y1 & 0xFFF, cls8u.rows);
  cv::Mat cls2;
  cv::bitwise_and(cls8u, cv::Scalar(3), cls2);
  stream::ClassMomentResults r;
  for (int c = 1; c <= stream::kMomentClasses; ++c) {
    cv::Mat mask = cv::Mat::zeros(cls8u.size(), CV_8UC1);
    if (x1 > x0 && y1 > y0) {
      const cv::Rect roi(x0, y0, x1 - x0, y1 - y0);
      cv::Mat inside = cls2(roi) == c;  // 0 / 255
      inside.copyTo(mask(roi));
    }
    const cv::Moments m = cv::moments(mask, true);
    r.cls[static_cast<size_t>(c - 1)] = {exact_u64(m.m00, "m00"), exact_u64(m.m10, "m10"),
                                         exact_u64(m.m01, "m01"), exact_u64(m.m20, "m20"),
                                         exact_u64(m.m11, "m11"), exact_u64(m.m02, "m02")};
  }
  return r;
}

}  // namespace ceilnav::golden
