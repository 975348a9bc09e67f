#include "golden/thresh_lut_ref.hpp"

#include <opencv2/core.hpp>

namespace ceilnav::golden {

void lut_ref(const cv::Mat& grey, const std::array<stream::LutEntry, 256>& lut, cv::Mat& remap,
             cv::Mat& mask) {
  CV_Assert(grey.type() == CV_8UC1);
  cv::Mat remap_table(1, 256, CV_8UC1);
  cv::Mat mask_table(1, 256, CV_8UC1);
  for (int g = 0; g < 256; ++g) {
    const stream::LutEntry e = lut[static_cast<size_t>(g)];
    remap_table.at<uchar>(g) = static_cast<uchar>(e & stream::kLutRemapMask);
    mask_table.at<uchar>(g) = (e & stream::kLutMaskBit) != 0 ? 1 : 0;
  }
  cv::LUT(grey, remap_table, remap);
  cv::LUT(grey, mask_table, mask);
}

cv::Mat lut_class_ref(const cv::Mat& grey, const std::array<stream::LutEntry, 256>& lut) {
  CV_Assert(grey.type() == CV_8UC1);
  cv::Mat class_table(1, 256, CV_8UC1);
  for (int g = 0; g < 256; ++g) {
    const stream::LutEntry e = lut[static_cast<size_t>(g)];
    class_table.at<uchar>(g) = stream::lut_class(e);
  }
  cv::Mat cls;
  cv::LUT(grey, class_table, cls);
  return cls;
}

}  // namespace ceilnav::golden
