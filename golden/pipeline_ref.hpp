// Golden reference of the whole pipeline for one well-formed frame:
// cv::LUT -> cv::calcHist, cv::moments (grey and mask, and per class mask in
// the class window), the reference run finder.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"

namespace ceilnav::golden {

struct PipelineRef {
  stream::HistogramResults histogram;
  stream::MomentResults moments;
  stream::ClassMomentResults class_moments;
  std::vector<stream::RunRecord> runs;  // in stream order
  uint32_t runs_dropped_row_limit = 0;
};

// grey: CV_8UC1 of cfg.width x cfg.height; cfg is the active configuration.
PipelineRef pipeline_ref(const cv::Mat& grey, const stream::PipelineConfig& cfg);

}  // namespace ceilnav::golden
