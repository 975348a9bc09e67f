#include "golden/run_scanner_ref.hpp"

#include <algorithm>
#include <stdexcept>

namespace ceilnav::golden {

std::vector<stream::RunRecord> find_runs_ref(const cv::Mat& remap8u, const cv::Mat& mask8u,
                                             const RunScanParams& p, uint32_t* dropped_row_limit) {
  if (remap8u.type() != CV_8UC1 || mask8u.type() != CV_8UC1 || remap8u.size() != mask8u.size()) {
    throw std::invalid_argument("find_runs_ref: need two CV_8UC1 images of one size");
  }
  std::vector<stream::RunRecord> runs;
  uint32_t dropped = 0;
  const int width = remap8u.cols;
  for (int y = 0; y < remap8u.rows; ++y) {
    const uint8_t* g = remap8u.ptr<uint8_t>(y);
    const uint8_t* m = mask8u.ptr<uint8_t>(y);
    auto w = [&](int x) { return std::max(0, int{g[x]} - int{p.background_level}); };
    int kept = 0;
    int x = 0;
    while (x < width) {
      if (m[x] == 0) {
        ++x;
        continue;
      }
      int x_end = x;
      while (x_end + 1 < width && m[x_end + 1] != 0) ++x_end;
      const int x_start = x;
      x = x_end + 1;
      if (x_end - x_start + 1 < int{p.min_run_length}) continue;
      if (kept >= int{p.max_runs_per_row}) {
        ++dropped;
        continue;
      }
      ++kept;
      double sum_w = 0.0;
      double sum_xw = 0.0;
      for (int xi = std::max(0, x_start - 1); xi <= std::min(width - 1, x_end + 1); ++xi) {
        sum_w += w(xi);
        sum_xw += double(xi) * w(xi);
      }
      runs.push_back({static_cast<uint16_t>(y), static_cast<uint16_t>(x_start),
                      static_cast<uint16_t>(x_end), static_cast<uint32_t>(sum_w),
                      static_cast<uint64_t>(sum_xw)});
    }
  }
  if (dropped_row_limit != nullptr) *dropped_row_limit = dropped;
  return runs;
}

}  // namespace ceilnav::golden
