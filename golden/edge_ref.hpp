// Golden reference of the edge detector (seed 002 eq. 17): OpenCV image
// operations (cv::absdiff of shifted images, cv::Sobel), no stream code, no
// FIFO. Integer results: equal to stream::EdgeDetector::scan_frame.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/edge_record.hpp"

namespace ceilnav::golden {

struct EdgeParams {
  stream::EdgeMode mode = stream::EdgeMode::kHorizontal;
  uint16_t threshold = 0;  // an edge point has magnitude > threshold
};

// remap8u: CV_8UC1 (the LUT remap image). The edge points in raster order of
// (y, x), one per qualifying pixel:
//   horizontal: x >= 1, |p(x,y) - p(x-1,y)| > t, polarity p(x,y) > p(x-1,y)
//   vertical:   y >= 1, |p(x,y) - p(x,y-1)| > t, polarity p(x,y) > p(x,y-1)
//   Sobel:      interior centres 1 <= x <= W-2, 1 <= y <= H-2 (no border rule
//               needed), cv::Sobel 3x3 gx, gy; magnitude |gx| + |gy|
//               (<= 2040, saturated to 4095 for form), polarity gx > 0
//   reserved:   none.
std::vector<stream::EdgeRecord> find_edges_ref(const cv::Mat& remap8u, const EdgeParams& p);

}  // namespace ceilnav::golden
