#include "golden/edge_ref.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace ceilnav::golden {

namespace {

using stream::EdgeKind;
using stream::EdgeRecord;

// |cur - prev| and cur > prev of two equally sized views, as edge records at
// (x0 + c, y0 + r) where the magnitude exceeds t.
void difference_edges(const cv::Mat& cur, const cv::Mat& prev, int x0, int y0, uint16_t t,
                      EdgeKind kind, std::vector<EdgeRecord>& out) {
  cv::Mat mag;
  cv::Mat rises;
  cv::absdiff(cur, prev, mag);
  cv::compare(cur, prev, rises, cv::CMP_GT);
  for (int r = 0; r < mag.rows; ++r) {
    const auto* m = mag.ptr<uint8_t>(r);
    const auto* up = rises.ptr<uint8_t>(r);
    for (int c = 0; c < mag.cols; ++c) {
      if (m[c] > t) {
        out.push_back(
            {static_cast<uint16_t>(x0 + c), static_cast<uint16_t>(y0 + r), m[c], up[c] != 0, kind});
      }
    }
  }
}

}  // namespace

std::vector<EdgeRecord> find_edges_ref(const cv::Mat& remap8u, const EdgeParams& p) {
  if (remap8u.type() != CV_8UC1) {
    throw std::invalid_argument("find_edges_ref: need a CV_8UC1 image");
  }
  std::vector<EdgeRecord> edges;
  const int w = remap8u.cols;
  const int h = remap8u.rows;
  switch (p.mode) {
    case stream::EdgeMode::kHorizontal:
      if (w >= 2) {
        difference_edges(remap8u.colRange(1, w), remap8u.colRange(0, w - 1), 1, 0, p.threshold,
                         EdgeKind::kHorizontal, edges);
      }
      break;
    case stream::EdgeMode::kVertical:
      if (h >= 2) {
        difference_edges(remap8u.rowRange(1, h), remap8u.rowRange(0, h - 1), 0, 1, p.threshold,
                         EdgeKind::kVertical, edges);
      }
      break;
    case stream::EdgeMode::kSobel: {
      if (w < 3 || h < 3) break;
      cv::Mat gx;
      cv::Mat gy;
      // The border rule does not matter: only interior centres are used.
      cv::Sobel(remap8u, gx, CV_16S, 1, 0, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
      cv::Sobel(remap8u, gy, CV_16S, 0, 1, 3, 1.0, 0.0, cv::BORDER_REPLICATE);
      for (int y = 1; y < h - 1; ++y) {
        const auto* rx = gx.ptr<int16_t>(y);
        const auto* ry = gy.ptr<int16_t>(y);
        for (int x = 1; x < w - 1; ++x) {
          const int mag = std::min(4095, std::abs(int{rx[x]}) + std::abs(int{ry[x]}));
          if (mag > int{p.threshold}) {
            edges.push_back({static_cast<uint16_t>(x), static_cast<uint16_t>(y),
                             static_cast<uint16_t>(mag), rx[x] > 0, EdgeKind::kSobel});
          }
        }
      }
      break;
    }
    case stream::EdgeMode::kReserved:
      break;
  }
  return edges;
}

}  // namespace ceilnav::golden
