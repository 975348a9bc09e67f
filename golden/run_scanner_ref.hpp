// Golden reference of run_scanner: a plain per-row loop over the mask with an
// unbounded output (no FIFO). Independent of the stream code.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/run_record.hpp"

namespace ceilnav::golden {

struct RunScanParams {
  uint8_t background_level;
  uint16_t min_run_length;
  uint16_t max_runs_per_row;
};

// remap8u, mask8u: CV_8UC1 of one size; mask nonzero = 1. Runs of mask = 1 on
// each row, top to bottom and left to right, with sum_w and sum_xw over the run
// plus one margin pixel each side clipped to the row (see common/run_record.hpp),
// w = max(0, remap - background_level). Runs shorter than min_run_length are
// skipped; after max_runs_per_row runs on a row the rest are counted in
// *dropped_row_limit (if given) and not returned.
std::vector<stream::RunRecord> find_runs_ref(const cv::Mat& remap8u, const cv::Mat& mask8u,
                                             const RunScanParams& p,
                                             uint32_t* dropped_row_limit = nullptr);

}  // namespace ceilnav::golden
