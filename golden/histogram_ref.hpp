// Golden reference of histogram: cv::calcHist with 256 bins over [0, 256).
#pragma once

#include <opencv2/core.hpp>

#include "common/results.hpp"

namespace ceilnav::golden {

// img8u: CV_8UC1 (any size, including empty).
stream::HistogramResults histogram_ref(const cv::Mat& img8u);

}  // namespace ceilnav::golden
