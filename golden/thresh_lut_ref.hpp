// Golden reference of thresh_lut: cv::LUT with 8-bit tables.
#pragma once

#include <array>

#include <opencv2/core.hpp>

#include "common/pipeline_config.hpp"

namespace ceilnav::golden {

// grey: CV_8UC1. remap = LUT bits 7:0, mask = LUT bit 8 as 0/1, both CV_8UC1.
void lut_ref(const cv::Mat& grey, const std::array<stream::LutEntry, 256>& lut, cv::Mat& remap,
             cv::Mat& mask);

// grey: CV_8UC1. The pixel class, LUT bits 10:9 (stream::PixelClass), CV_8UC1.
cv::Mat lut_class_ref(const cv::Mat& grey, const std::array<stream::LutEntry, 256>& lut);

}  // namespace ceilnav::golden
