#include "golden/pipeline_ref.hpp"

#include "golden/class_moments_ref.hpp"
#include "golden/histogram_ref.hpp"
#include "golden/moment_gen_ref.hpp"
#include "golden/run_scanner_ref.hpp"
#include "golden/thresh_lut_ref.hpp"

namespace ceilnav::golden {

PipelineRef pipeline_ref(const cv::Mat& grey, const stream::PipelineConfig& cfg) {
  CV_Assert(grey.type() == CV_8UC1 && grey.cols == cfg.width && grey.rows == cfg.height);
  cv::Mat remap;
  cv::Mat mask;
  lut_ref(grey, cfg.lut, remap, mask);
  PipelineRef out;
  out.histogram = histogram_ref(cfg.hist_source_remap ? remap : grey);
  out.moments = moments_ref(remap, mask);
  out.class_moments = class_moments_ref(lut_class_ref(grey, cfg.lut), cfg.class_window);
  const RunScanParams params{cfg.background_level, cfg.min_run_length, cfg.max_runs_per_row};
  out.runs = find_runs_ref(remap, mask, params, &out.runs_dropped_row_limit);
  return out;
}

}  // namespace ceilnav::golden
