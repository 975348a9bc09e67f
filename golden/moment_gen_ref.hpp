// Golden reference of moment_gen: cv::moments in double, checked to be exact
// integers. Independent of the stream code.
#pragma once

#include <opencv2/core.hpp>

#include "common/results.hpp"

namespace ceilnav::golden {

// remap8u: CV_8UC1 grey (LUT remap). mask8u: CV_8UC1, 0 = off, nonzero = on
// (0/1 or 0/255). Spatial moments m00 m10 m01 m20 m11 m02 (x = column, y = row)
// of the grey image and of the binary mask. Throws std::runtime_error if a
// moment is not an exact integer in double (it would not be a valid reference).
stream::MomentResults moments_ref(const cv::Mat& remap8u, const cv::Mat& mask8u);

}  // namespace ceilnav::golden
