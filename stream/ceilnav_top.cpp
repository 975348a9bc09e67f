#include "stream/ceilnav_top.hpp"

#include <algorithm>
#include <array>
#include <limits>

namespace ceilnav::stream {

namespace {

static_assert(regs::mom_grey_lo::kCount == kMomentCount &&
              regs::mom_mask_hi::kCount == kMomentCount);
static_assert(regs::class_mom_lo::kCount == kMomentClasses * kMomentCount &&
              regs::class_mom_hi::kCount == kMomentClasses * kMomentCount);

uint32_t lo(uint64_t v) {
  return static_cast<uint32_t>(v);
}
uint32_t hi(uint64_t v) {
  return static_cast<uint32_t>(v >> 32);
}

uint32_t sat32(uint64_t v) {
  return static_cast<uint32_t>(std::min<uint64_t>(v, std::numeric_limits<uint32_t>::max()));
}

// Word `index` of the result store's meta port: RES_FRAME_INDEX,
// CYCLES_PER_FRAME, RUNS_EMITTED .. RUN_FIFO_HIGH_WATER, RES_EARLY_EOL ..
// RES_FRAMES_ABORTED (register order).
uint32_t meta_word(const FrameResults& res, uint32_t index) {
  const FrameErrorCounters& e = res.errors;
  const RunStats& r = res.run_stats;
  const std::array<uint32_t, 12> words = {res.frame_index,
                                          sat32(res.cycles_in_frame),
                                          r.runs_emitted,
                                          r.runs_dropped_row_limit,
                                          r.runs_dropped_overflow,
                                          r.fifo_high_water,
                                          e.early_eol,
                                          e.late_eol,
                                          e.early_sof,
                                          e.missing_sof,
                                          e.frames_ok,
                                          e.frames_aborted};
  return index < words.size() ? words[index] : 0u;
}

bool error_counters_differ(const FrameErrorCounters& a, const FrameErrorCounters& b) {
  return a.early_eol != b.early_eol || a.late_eol != b.late_eol || a.early_sof != b.early_sof ||
         a.missing_sof != b.missing_sof || a.frames_aborted != b.frames_aborted;
}

}  // namespace

CeilnavTop::CeilnavTop(uint32_t run_fifo_depth, const regs::Config& config,
                       const HoughShape& hough_shape, uint32_t ori_bins)
    : run_fifo_depth_(run_fifo_depth),
      pipeline_(run_fifo_depth, config.has_class_moments, config.has_corridor, hough_shape,
                regs::kEdgeFifoDepth, config.has_orientation, ori_bins),
      regs_(config) {
  reset();
}

void CeilnavTop::reset() {
  regs_.reset();
  hw_ = Hw2Reg{};
  gate_open_q_ = false;
  cycle_q_ = 0;
  store_rd_q_ = 0;  // the RTL leaves it undefined: it is read masked by store_rd_valid_q_
  store_rd_valid_q_ = false;
  reset_datapath();
  soft_reset_hold_q_ = false;
}

void CeilnavTop::reset_datapath() {
  pipeline_.reset();
  lut_active_q_ = 0;
  lut_pending_q_ = false;
  in_frame_q_ = false;
  err_prev_q_ = {};
  trailers_lost_prev_q_ = 0;
  frame_count_q_ = 0;
  hough_frame_count_q_ = 0;
  eof_age_q_ = 0;
  eof_to_irq_q_ = 0;
  push_config();
}

PipelineConfig CeilnavTop::pipeline_config() const {
  const Reg2Hw& r = regs_.reg2hw();
  PipelineConfig c;
  c.width = static_cast<uint16_t>(r.width.value);
  c.height = static_cast<uint16_t>(r.height.value);
  c.background_level = static_cast<uint8_t>(r.background_level.value);
  c.min_run_length = static_cast<uint16_t>(r.min_run_length.value);
  c.max_runs_per_row = static_cast<uint16_t>(r.max_runs_per_row.value);
  c.hist_source_remap = r.hist_source.remap != 0;
  c.class_window = {
      static_cast<uint16_t>(r.class_win_x.x0), static_cast<uint16_t>(r.class_win_x.x1),
      static_cast<uint16_t>(r.class_win_y.y0), static_cast<uint16_t>(r.class_win_y.y1)};
  return c;
}

void CeilnavTop::push_config() {
  PipelineConfig c = pipeline_config();
  c.lut = lut_bank_[lut_pending_q_ ? lut_active_q_ ^ 1u : lut_active_q_];
  pipeline_.set_config(c);
  const Reg2Hw& r = regs_.reg2hw();
  EdgeConfig e;
  e.enable = r.edge_control.enable != 0;
  e.mode = static_cast<EdgeMode>(r.edge_control.mode);
  e.threshold = static_cast<uint16_t>(r.edge_control.threshold);
  HoughConfig h;
  h.enable = r.hough_control.enable != 0;
  h.unit_weight = r.hough_control.unit_weight != 0;
  h.weight_shift = static_cast<uint8_t>(r.hough_control.weight_shift);
  h.rho_shift = static_cast<uint8_t>(r.hough_control.rho_shift);
  h.theta_first = static_cast<uint8_t>(r.hough_control.theta_first);
  h.theta_count = static_cast<uint8_t>(r.hough_control.theta_count);
  h.width = static_cast<uint16_t>(r.hough_geometry.width);
  pipeline_.set_corridor_config(e, h);
  OrientationConfig o;
  o.enable = r.ori_control.enable != 0;
  o.threshold = static_cast<uint16_t>(r.ori_control.threshold);
  pipeline_.set_orientation_config(o);
}

void CeilnavTop::fill_read_inputs() {
  const FrameResults& res = pipeline_.results();
  const FrameErrorCounters& live = pipeline_.error_counters();
  const RunBeat head = pipeline_.m_axis_runs();
  Hw2Reg& h = hw_;
  h.status = {in_frame_q_ ? 1u : 0u,    res.valid ? 1u : 0u,
              head.tvalid ? 1u : 0u,    gate_open_q_ ? 1u : 0u,
              lut_pending_q_ ? 1u : 0u, pipeline_.corridor_pending() ? 1u : 0u};
  h.run_fifo_level.value = pipeline_.run_fifo_occupancy() + (head.tvalid ? 1u : 0u);
  h.run_fifo_depth.value = run_fifo_depth_;
  h.features.class_moments = regs_.config().has_class_moments;
  h.features.corridor = regs_.config().has_corridor;
  h.features.orientation = regs_.config().has_orientation;
  // The run window: the head entry of the run FIFO, 0 if none.
  const RunRecord run = head.tvalid ? head.tdata : RunRecord{};
  h.run_word0 = {head.tvalid ? 1u : 0u, head.tvalid && head.tlast ? 1u : 0u, run.row};
  h.run_word1 = {run.x_start, run.x_end};
  h.run_word2.sum_w = run.sum_w;
  h.run_word3.sum_xw = static_cast<uint32_t>(run.sum_xw);
  h.frame_count.value = frame_count_q_;
  h.eof_to_irq_cycles.value = eof_to_irq_q_;
  h.cnt_early_eol.value = live.early_eol;
  h.cnt_late_eol.value = live.late_eol;
  h.cnt_early_sof.value = live.early_sof;
  h.cnt_missing_sof.value = live.missing_sof;
  h.cnt_frames_ok.value = live.frames_ok;
  h.cnt_frames_aborted.value = live.frames_aborted;
  h.run_trailers_lost.value = pipeline_.run_trailers_lost();
  h.frames_overrun.value = pipeline_.frames_overrun();
  // The corridor blocks (all 0 without them: the registers answer SLVERR).
  if (pipeline_.has_corridor()) {
    const EdgeDetector& edge = pipeline_.edge();
    const Hough& hough = pipeline_.hough();
    const HoughCounters& hc = hough.counters();
    const HoughShape& shape = hough.shape();
    h.edge_count.value = edge.last_frame_stats().edges_emitted;
    h.edge_dropped.value = edge.last_frame_stats().edges_dropped;
    h.edge_fifo_level.value = edge.fifo_occupancy() + (edge.m_axis_edges().tvalid ? 1u : 0u);
    h.edge_trailers_lost.value = edge.trailers_lost();
    h.hough_status = {hough.results_valid() ? 1u : 0u, static_cast<uint32_t>(hough.state())};
    h.hough_edges.value = hc.edges;
    h.hough_bad_edges.value = hc.bad_edges;
    h.hough_votes.value = hc.votes;
    h.hough_dropped.value = hc.dropped;
    h.hough_saturated.value = hc.saturated;
    h.hough_trailer_edges.value = hc.trailer_edges;
    h.hough_trailer_flags.value = hc.trailer_flags;
    h.hough_shape = {static_cast<uint32_t>(shape.lanes), static_cast<uint32_t>(shape.theta_step),
                     static_cast<uint32_t>(shape.rho_bits), static_cast<uint32_t>(shape.acc_bits)};
    h.hough_frame_count.value = hough_frame_count_q_;
    h.hough_stalls.value = pipeline_.hough_stalls();
  }
  // The orientation block (all 0 without it: the registers answer SLVERR).
  if (pipeline_.has_orientation()) {
    const Orientation& ori = pipeline_.orientation();
    h.ori_status = {ori.results_valid() ? 1u : 0u, ori.clearing() ? 1u : 0u, ori.bins()};
    h.ori_frames.value = ori.frames();
    h.ori_skipped.value = ori.frames_skipped();
    h.ori_votes.value = ori.frame_votes();
  }
  // CLASS_MOM_*[i] (class c = i / 6 + 1, moment k = i % 6): 64-bit moments in two words.
  for (size_t i = 0; i < kMomentClasses * kMomentCount; ++i) {
    const uint64_t v = res.class_moments.cls[i / kMomentCount][i % kMomentCount];
    h.class_mom_lo.value[i] = lo(v);
    h.class_mom_hi.value[i] = hi(v);
  }
}

void CeilnavTop::clock(const VideoBeat& s_axis_video, const AxiLiteIn& s_axil,
                       bool m_axis_runs_tready) {
  // ---- Register block, first half: this edge's write and read strobes. The
  // result store holds reads of MOM_* while moment_gen writes the words.
  hw_.moments.ready = !pipeline_.mom_wr().valid;
  hw_.moments.data = hw_.meta.data = store_rd_valid_q_ ? store_rd_q_ : 0u;
  regs_.begin_edge(s_axil, hw_);
  const Reg2Hw& r = regs_.reg2hw();
  // Inputs of the register block: the state before this edge.
  if (regs_.read_sampling()) fill_read_inputs();
  // Result store read port: the word as the store holds it before the edge,
  // i.e. the published set (reads of the moments wait while they are written).
  if (r.moments.re || r.meta.re) {
    const FrameResults& res = pipeline_.results();
    store_rd_q_ = r.moments.re
                      ? MomentGen::moment_word(res.moments, static_cast<int>(r.moments.index))
                      : meta_word(res, r.meta.index);
    store_rd_valid_q_ = res.valid;
  }
  // The histogram and hough blocks' read ports answer one edge after the read.
  hw_.hist_data.count = pipeline_.hist_rd_data();
  hw_.hough_data.count = pipeline_.hough_rd_data();
  hw_.ori_data.count = pipeline_.ori_rd_data();
  const bool run_pop = r.run_word3.re && run_sink();
  const bool runs_tready = run_sink() ? run_pop : m_axis_runs_tready;
  const bool soft_reset = r.control.we && r.control.soft_reset != 0;

  // ---- Datapath edge. The gate passes whole frames only (decided at the SOF
  // beat with CONTROL.ENABLE as it is before the edge).
  const bool video_sof = s_axis_video.tvalid && s_axis_video.tuser;
  const bool enable = r.control.enable != 0;
  const bool pass = s_axis_video.tvalid && (s_axis_video.tuser ? enable : gate_open_q_);
  const VideoBeat video_in = pass ? s_axis_video : VideoBeat{};

  // Events, from the pipeline's registered outputs. The one-edge-old copies
  // take the pre-edge values here, before the pipeline's edge; in most
  // cycles no counter moved and one comparison settles it.
  const FrameErrorCounters& err = pipeline_.error_counters();
  const bool frame_done = pipeline_.frame_done();
  hw_.intr_state.frame_done = frame_done ? 1u : 0u;
  hw_.intr_state.run_overflow =
      (frame_done && pipeline_.results().run_stats.runs_dropped_overflow != 0) ||
              pipeline_.run_trailers_lost() != trailers_lost_prev_q_
          ? 1u
          : 0u;
  const bool hough_done = pipeline_.hough_done();
  hw_.intr_state.hough_done = hough_done ? 1u : 0u;
  hw_.intr_state.frame_error = 0;
  hw_.error_cause = {};
  bool eof_seen = false;
  bool frame_closed = false;
  if (!(err == err_prev_q_)) {
    hw_.intr_state.frame_error = error_counters_differ(err, err_prev_q_) ? 1u : 0u;
    hw_.error_cause = {err.early_eol != err_prev_q_.early_eol ? 1u : 0u,
                       err.late_eol != err_prev_q_.late_eol ? 1u : 0u,
                       err.early_sof != err_prev_q_.early_sof ? 1u : 0u,
                       err.missing_sof != err_prev_q_.missing_sof ? 1u : 0u};
    eof_seen = err.frames_ok != err_prev_q_.frames_ok;
    // An early SOF aborts a frame and opens the next one on the same beat; an
    // EOL error always leaves frame_check discarding (the frame aborted, or
    // its SOF pixel rejected before it opened).
    frame_closed = eof_seen ||
                   (err.frames_aborted != err_prev_q_.frames_aborted &&
                    err.early_sof == err_prev_q_.early_sof) ||
                   err.early_eol != err_prev_q_.early_eol || err.late_eol != err_prev_q_.late_eol;
    err_prev_q_ = err;
  }
  trailers_lost_prev_q_ = pipeline_.run_trailers_lost();

  const bool hold = soft_reset_hold_q_;
  if (hold) {
    // ThreshLut::reset() clears the pending swap that reset_datapath() set up:
    // hand the pipeline the table of the now-active bank 0 again.
    pipeline_.reset();
    push_config();
  } else {
    pipeline_.clock(video_in, runs_tready, r.hist_data.re, static_cast<uint8_t>(r.hist_index.value),
                    r.hough_data.re, r.hough_index.value, r.ori_data.re,
                    static_cast<uint8_t>(r.ori_index.value));
    if (pass && s_axis_video.tuser && lut_pending_q_) {  // thresh_lut's bank swap
      lut_active_q_ ^= 1u;
      lut_pending_q_ = false;
    }
  }
  soft_reset_hold_q_ = false;

  // LUT write port: entry LUT_INDEX (before the write) of the shadow bank, swap pending.
  if (r.lut_data.we) {
    lut_bank_[lut_active_q_ ^ 1u][r.lut_index.value] =
        lut_entry(static_cast<uint8_t>(r.lut_data.remap), r.lut_data.mask != 0,
                  static_cast<uint8_t>(r.lut_data.class_));
    lut_pending_q_ = true;
  }

  // ---- Register block, the edge.
  const int written = regs_.written_word();
  regs_.commit(s_axil, hw_);
  if (written >= 0) push_config();  // a configuration field or the LUT may have changed

  if (regs_.irq_rise()) eof_to_irq_q_ = eof_age_q_;
  if (frame_done) ++frame_count_q_;
  if (hough_done) ++hough_frame_count_q_;
  // Edges from the one that accepted the last good EOF pixel (eof_seen is one
  // edge later), or from the last reset.
  eof_age_q_ = eof_seen ? 2u : eof_age_q_ + 1u;
  if (pass && s_axis_video.tuser && !hold) {
    in_frame_q_ = true;
  } else if (frame_closed) {
    in_frame_q_ = false;
  }
  if (video_sof) gate_open_q_ = enable;
  ++cycle_q_;

  if (soft_reset) {
    reset_datapath();
    soft_reset_hold_q_ = true;
  }
}

}  // namespace ceilnav::stream
