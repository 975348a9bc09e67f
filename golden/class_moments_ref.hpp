// Golden reference of class_moments: cv::moments (binaryImage) of each class
// mask restricted to the window. Independent of the stream code.
#pragma once

#include <opencv2/core.hpp>

#include "common/pipeline_config.hpp"
#include "common/results.hpp"

namespace ceilnav::golden {

// cls8u: CV_8UC1 image of pixel classes (0..3; higher bits are ignored, as
// the 2-bit LUT field cannot hold them). For each class c = 1..3: the mask
// (cls == c) with every pixel outside [x0, x1) x [y0, y1) set to 0, given to
// cv::moments(mask, true) on the full image, so x and y are frame
// coordinates. Window bounds use their low 12 bits (the register width).
// Throws std::runtime_error if a moment is not an exact integer in double.
stream::ClassMomentResults class_moments_ref(const cv::Mat& cls8u, const stream::ClassWindow& win);

}  // namespace ceilnav::golden
