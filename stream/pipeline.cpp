#include "stream/pipeline.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

namespace ceilnav::stream {

Pipeline::Pipeline(uint32_t run_fifo_depth, bool has_class_moments, bool has_corridor,
                   const HoughShape& hough_shape, uint32_t edge_fifo_depth, bool has_orientation,
                   uint32_t ori_bins)
    : runs_(run_fifo_depth),
      edge_(edge_fifo_depth),
      hough_(hough_shape),
      ori_(ori_bins),
      has_class_moments_(has_class_moments),
      has_corridor_(has_corridor),
      has_orientation_(has_orientation) {
  set_config(shadow_);
  lut_.commit_at_frame_start();
  build_tables();
  reset();
}

void Pipeline::reset() {
  fc_.reset();
  lut_.reset();
  hist_.reset();
  mom_.reset();
  cls_.reset();
  runs_.reset();
  edge_.reset();
  hough_.reset();
  ori_.reset();
  hough_stalls_q_ = 0;
  cfg_fc_ = stage_config(shadow_);
  cfg_lut_ = cfg_fc_;
  cycle_q_ = 0;
  sof_cycle_q_ = 0;
  meta_fc_q_ = {};
  meta_lut_q_ = {};
  hist_accept_q_ = false;
  staged_hist_q_ = {};
  staged_runs_q_ = {};
  staged_meta_q_ = {};
  results_q_ = {};
  frame_done_q_ = false;
}

void Pipeline::set_config(const PipelineConfig& cfg) {
  shadow_ = cfg;
  for (unsigned g = 0; g < 256; ++g) {
    lut_.write(static_cast<uint8_t>(g), cfg.lut[g]);
  }
}

void Pipeline::clock(const VideoBeat& s_axis_video, bool m_axis_runs_tready) {
  clock(s_axis_video, m_axis_runs_tready, false, 0);
}

bool Pipeline::corridor_pending() const {
  if (!has_corridor_) return false;
  const Hough::State s = hough_.state();
  return edge_.pending() || edge_.m_axis_edges().tvalid || edge_.fifo_occupancy() != 0 ||
         s == Hough::State::kVote || s == Hough::State::kSwap;
}

void Pipeline::clock(const VideoBeat& s_axis_video, bool m_axis_runs_tready, bool hist_rd_en,
                     uint8_t hist_rd_bin, bool hough_rd_en, uint32_t hough_rd_index, bool ori_rd_en,
                     uint8_t ori_rd_bin) {
  // Every block samples the pre-edge outputs of the block before it.
  const PixelBeat fc_out = fc_.m_pix();
  const LutBeat lut_out = lut_.m_lut();
  const bool video_sof = s_axis_video.tvalid && s_axis_video.tuser;

  // ---- Stage 3: histogram, moment_gen, class_moments, run_scanner (all
  // sample lut_out). class_moments keeps only the frames that moment_gen
  // takes (eof_keep = moment_gen's eof_accept), so its outputs still hold the
  // frame when moment_gen publishes it; they are read before its edge.
  // A frame the histogram cannot count (no cleared bank at its SOF) is
  // dropped at its EOF by moment_gen (eof_drop); the histogram keeps (will
  // publish) exactly the frames moment_gen takes.
  const uint32_t overruns_before = mom_.overrun_count();
  const ClassMomentResults class_results = cls_.results();
  const bool hist_counts = hist_.counts(lut_out);
  mom_.clock(lut_out, /*eof_drop=*/!hist_counts);
  const bool mom_accept =
      lut_out.pix.valid && lut_out.pix.eof && mom_.overrun_count() == overruns_before;
  hist_.clock(lut_out, cfg_lut_.hist_source_remap, /*keep=*/mom_accept, hist_rd_en, hist_rd_bin);
  if (has_class_moments_) cls_.clock(lut_out, cfg_lut_.class_window, mom_accept);
  runs_.set_active_config(cfg_lut_.runs);
  runs_.clock(lut_out, m_axis_runs_tready);
  // The corridor blocks: edge -> hough, both sampling the other's pre-edge
  // outputs (the edge beat, the hough's tready).
  if (has_corridor_) {
    const EdgeBeat edge_beat = edge_.m_axis_edges();
    const bool hough_tready = hough_.tready();
    if (edge_beat.tvalid && !hough_tready && hough_stalls_q_ != UINT32_MAX) ++hough_stalls_q_;
    hough_.clock(edge_beat, hough_cfg_, hough_rd_en, hough_rd_index);
    edge_.set_config(cfg_lut_.edge);
    edge_.clock(lut_out, hough_tready);
  }
  // The orientation block: the configuration that travelled with the SOF.
  if (has_orientation_) {
    ori_.set_config(cfg_lut_.ori);
    ori_.clock(lut_out, ori_rd_en, ori_rd_bin);
  }
  // Result registers. moment_gen is the last to finish a frame (kCombineCycles
  // after its EOF pixel); the histogram and run stats of the same frame were
  // staged when they finished, and nothing overwrites them before: a frame
  // ending earlier than that is dropped by moment_gen and not staged.
  frame_done_q_ = mom_.done();
  if (mom_.done()) {
    results_q_.frame_index = staged_meta_q_.frame_index;
    results_q_.valid = true;
    results_q_.histogram = staged_hist_q_;
    results_q_.moments = mom_.results();
    if (has_class_moments_) results_q_.class_moments = class_results;
    results_q_.run_stats = staged_runs_q_;
    results_q_.errors = staged_meta_q_.errors;
    results_q_.cycles_in_frame = staged_meta_q_.cycles_in_frame;
  }
  if (hist_.done() && hist_accept_q_) {
    staged_hist_q_ = hist_.results();
  }
  hist_accept_q_ = false;
  if (mom_accept) {
    staged_runs_q_ = runs_.last_frame_stats();
    staged_meta_q_ = meta_lut_q_;
    hist_accept_q_ = true;
  }

  // ---- Stage 2: thresh_lut. The bank swap rides on frame_check's SOF edge.
  lut_.clock(fc_out, video_sof);
  if (fc_out.valid && fc_out.sof) {
    cfg_lut_ = cfg_fc_;
  }
  if (fc_out.valid && fc_out.eof) {
    meta_lut_q_ = meta_fc_q_;
  }

  // ---- Stage 1: frame_check, with the shadow -> active copy at the SOF beat.
  fc_.clock(s_axis_video, shadow_.width, shadow_.height);
  if (video_sof) {
    cfg_fc_ = stage_config(shadow_);
  }
  const PixelBeat& pix = fc_.m_pix();
  if (pix.valid && pix.sof) {
    sof_cycle_q_ = cycle_q_;
  }
  if (pix.valid && pix.eof) {
    meta_fc_q_.frame_index = fc_.counters().frames_ok - 1;
    meta_fc_q_.errors = fc_.counters();
    meta_fc_q_.cycles_in_frame = cycle_q_ - sof_cycle_q_ + 1;
  }
  ++cycle_q_;
}

void Pipeline::build_tables() {
  const auto& table = lut_.active_table();
  for (unsigned g = 0; g < 256; ++g) {
    remap_table_[g] = static_cast<uint8_t>(table[g] & kLutRemapMask);
    mask_table_[g] = (table[g] & kLutMaskBit) != 0 ? 1 : 0;
    class_table_[g] = lut_class(table[g]);
  }
}

FrameResults Pipeline::process_frame(const uint8_t* grey, int width, int height,
                                     size_t stride_bytes, std::vector<RunRecord>* runs_out) {
  if (width != shadow_.width || height != shadow_.height || width < 1 || height < 1) {
    throw std::invalid_argument("Pipeline::process_frame: image size differs from the config");
  }
  if (fc_.state() == FrameCheck::State::kInFrame || fc_.m_pix().valid || lut_.m_lut().pix.valid ||
      mom_.combine_busy() || hist_accept_q_ || runs_.fifo_occupancy() != 0 || corridor_pending() ||
      (has_orientation_ && !ori_.idle())) {
    throw std::logic_error("Pipeline::process_frame: the clocked pipeline is not idle");
  }
  // The SOF: shadow -> active.
  const bool swapped = lut_.commit_pending();
  lut_.commit_at_frame_start();
  if (swapped) {
    build_tables();
  }
  cfg_fc_ = stage_config(shadow_);
  cfg_lut_ = cfg_fc_;
  const bool hist_remap = cfg_lut_.hist_source_remap;

  const auto w = static_cast<uint32_t>(width);
  const bool edges_on = has_corridor_ && cfg_lut_.edge.enable;
  const bool ori_on = has_orientation_ && cfg_lut_.ori.enable;
  if (edges_on || ori_on) remap_frame_.resize(size_t{w} * static_cast<size_t>(height));
  remap_row_.resize(w);
  mask_row_.resize(w);
  class_row_.resize(w);
  ClassMomentResults class_sums;
  std::array<uint32_t, Histogram::kBins> bins{};
  MomentGen::FrameSums sums;
  std::vector<RunRecord> local_runs;
  std::vector<RunRecord>& runs = runs_out != nullptr ? *runs_out : local_runs;
  runs.clear();
  RunStats stats;
  bool run_at_eof = false;
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = grey + static_cast<size_t>(y) * stride_bytes;
    for (uint32_t x = 0; x < w; ++x) {
      remap_row_[x] = remap_table_[row[x]];
      mask_row_[x] = mask_table_[row[x]];
      class_row_[x] = class_table_[row[x]];
    }
    if (edges_on || ori_on) {
      std::copy(remap_row_.begin(), remap_row_.end(),
                remap_frame_.begin() + static_cast<ptrdiff_t>(size_t{w} * static_cast<size_t>(y)));
    }
    const uint8_t* hist_row = hist_remap ? remap_row_.data() : row;
    for (uint32_t x = 0; x < w; ++x) {
      ++bins[hist_row[x]];
    }
    MomentGen::accumulate_row(sums, static_cast<uint32_t>(y), remap_row_.data(), mask_row_.data(),
                              w);
    if (has_class_moments_) {
      ClassMoments::accumulate_row(class_sums, static_cast<uint32_t>(y), class_row_.data(), w,
                                   cfg_lut_.class_window);
    }
    const size_t first_new = runs.size();
    RunScanner::scan_row(cfg_lut_.runs, static_cast<uint16_t>(y), remap_row_.data(),
                         mask_row_.data(), w, runs, stats.runs_dropped_row_limit);
    // A run is pushed on its right-margin pixel, or on its last pixel at the
    // EOL: only a run reaching the end of the last row shares the EOF edge.
    if (y == height - 1 && runs.size() > first_new && runs.back().x_end + 2u >= w) {
      run_at_eof = true;
    }
  }
  stats.runs_emitted = static_cast<uint32_t>(runs.size());
  // The high-water mark is the occupancy after each pixel's edge. With
  // tready = 1 and an empty FIFO at the SOF, the FIFO pops one entry per cycle
  // and takes at most one run per cycle before the EOF edge, so it holds at
  // most 1 entry after any edge before the EOF, where the trailer and
  // possibly a last run are written: the peak is at the EOF edge.
  stats.fifo_high_water = run_at_eof ? 2u : 1u;

  // The corridor: the edge block emits the frame's edge points and its
  // trailer (no FIFO overflow here), the hough block votes them.
  if (edges_on) {
    edge_points_.clear();  // scan_frame appends
    EdgeDetector::scan_frame(cfg_lut_.edge, remap_frame_.data(), w, static_cast<uint32_t>(height),
                             edge_points_);
    edge_words_.clear();
    for (const EdgeRecord& e : edge_points_) edge_words_.push_back(pack_edge_beat(e));
    hough_.process_frame(edge_words_, pack_edge_trailer(edge_points_.size(), 0, 0), hough_cfg_);
  }

  // The orientation block votes the remap stream beside the edge block.
  if (ori_on)
    ori_.publish_frame(cfg_lut_.ori, remap_frame_.data(), w, static_cast<uint32_t>(height));

  fc_.process_frame(shadow_.width, shadow_.height);
  hist_.publish_frame(bins);
  FrameResults r;
  r.frame_index = fc_.counters().frames_ok - 1;
  r.valid = true;
  r.histogram = hist_.results();
  r.moments = MomentGen::finish(sums);
  r.class_moments = class_sums;
  r.run_stats = stats;
  r.errors = fc_.counters();
  r.cycles_in_frame = uint64_t{w} * static_cast<uint64_t>(height);
  results_q_ = r;
  frame_done_q_ = false;
  return r;
}

}  // namespace ceilnav::stream
