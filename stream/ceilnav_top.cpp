#include "stream/ceilnav_top.hpp"

#include <algorithm>
#include <limits>

namespace ceilnav::stream {

namespace {

constexpr uint8_t kOkay = regs::kRespOkay;
constexpr uint8_t kSlvErr = regs::kRespSlvErr;

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

bool error_counters_differ(const FrameErrorCounters& a, const FrameErrorCounters& b) {
  return a.early_eol != b.early_eol || a.late_eol != b.late_eol || a.early_sof != b.early_sof ||
         a.missing_sof != b.missing_sof || a.frames_aborted != b.frames_aborted;
}

}  // namespace

CeilnavTop::CeilnavTop(uint32_t run_fifo_depth, const regs::Config& config)
    : run_fifo_depth_(run_fifo_depth),
      config_(config),
      pipeline_(run_fifo_depth, config.has_class_moments) {
  reset();
}

void CeilnavTop::reset() {
  enable_q_ = false;
  run_sink_regs_q_ = false;
  intr_state_q_ = 0;
  intr_enable_q_ = 0;
  error_cause_q_ = 0;
  cfg_q_ = PipelineConfig{};
  cfg_q_.width = static_cast<uint16_t>(regs::width::kValue.reset);
  cfg_q_.height = static_cast<uint16_t>(regs::height::kValue.reset);
  cfg_q_.background_level = static_cast<uint8_t>(regs::background_level::kValue.reset);
  cfg_q_.min_run_length = static_cast<uint16_t>(regs::min_run_length::kValue.reset);
  cfg_q_.max_runs_per_row = static_cast<uint16_t>(regs::max_runs_per_row::kValue.reset);
  cfg_q_.hist_source_remap = regs::hist_source::kRemap.reset != 0;
  cfg_q_.class_window = {static_cast<uint16_t>(regs::class_win_x::kX0.reset),
                         static_cast<uint16_t>(regs::class_win_x::kX1.reset),
                         static_cast<uint16_t>(regs::class_win_y::kY0.reset),
                         static_cast<uint16_t>(regs::class_win_y::kY1.reset)};
  lut_index_q_ = 0;
  hist_index_q_ = 0;
  gate_open_q_ = false;
  axil_q_ = AxiLiteOut{};
  axil_q_.arready = true;
  rd_stage_q_ = 0;
  rd_addr_q_ = 0;
  rd_data_q_ = 0;
  rd_resp_q_ = kOkay;
  rd_hist_q_ = false;
  cycle_q_ = 0;
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
  eof_edge_q_ = 0;
  eof_to_irq_q_ = 0;
  push_config();
}

void CeilnavTop::push_config() {
  PipelineConfig c = cfg_q_;
  c.lut = lut_bank_[lut_pending_q_ ? lut_active_q_ ^ 1u : lut_active_q_];
  pipeline_.set_config(c);
}

void CeilnavTop::clock(const VideoBeat& s_axis_video, const AxiLiteIn& s_axil,
                       bool m_axis_runs_tready) {
  // ---- Handshakes: inputs against the registered (pre-edge) outputs.
  const bool aw_hs = axil_q_.awready && s_axil.awvalid && s_axil.wvalid;  // wready == awready
  const bool b_hs = axil_q_.bvalid && s_axil.bready;
  const bool ar_hs = axil_q_.arready && s_axil.arvalid;
  const bool r_hs = axil_q_.rvalid && s_axil.rready;
  // The histogram block's read port answers one edge after the read.
  const uint32_t hist_rd_data = pipeline_.hist_rd_data();

  // ---- Read sample stage: the register as it is before this edge.
  bool run_pop = false;
  bool hist_inc = false;
  uint32_t rd_value = 0;
  uint8_t rd_resp = kOkay;
  if (rd_stage_q_ == 1) {
    rd_value = read_register(rd_addr_q_, rd_resp);
    if (rd_resp == kOkay) {
      const uint32_t a = rd_addr_q_ & regs::kAddrMask;
      hist_inc = a == regs::hist_data::kOffset;
      run_pop = a == regs::run_word3::kOffset && run_sink_regs_q_;
    }
  }

  // ---- Datapath edge. The gate passes whole frames only (decided at the SOF beat).
  const bool video_sof = s_axis_video.tvalid && s_axis_video.tuser;
  const bool pass = s_axis_video.tvalid && (s_axis_video.tuser ? enable_q_ : gate_open_q_);
  const VideoBeat video_in = pass ? s_axis_video : VideoBeat{};
  const bool runs_tready = run_sink_regs_q_ ? run_pop : m_axis_runs_tready;

  // Events, from the pipeline's registered outputs. The one-edge-old copies
  // take the pre-edge values here, before the pipeline's edge; in most
  // cycles no counter moved and one comparison settles it.
  const FrameErrorCounters& err = pipeline_.error_counters();
  const bool frame_done = pipeline_.frame_done();
  uint32_t events = 0;
  if (frame_done) events |= kIntrFrameDone;
  if ((frame_done && pipeline_.results().run_stats.runs_dropped_overflow != 0) ||
      pipeline_.run_trailers_lost() != trailers_lost_prev_q_) {
    events |= kIntrRunOverflow;
  }
  bool eof_seen = false;
  bool frame_closed = false;
  uint32_t cause_set = 0;
  if (!(err == err_prev_q_)) {
    if (error_counters_differ(err, err_prev_q_)) events |= kIntrFrameError;
    namespace ec = regs::error_cause;
    cause_set = ec::kEarlyEol.put(err.early_eol != err_prev_q_.early_eol ? 1u : 0u) |
                ec::kLateEol.put(err.late_eol != err_prev_q_.late_eol ? 1u : 0u) |
                ec::kEarlySof.put(err.early_sof != err_prev_q_.early_sof ? 1u : 0u) |
                ec::kMissingSof.put(err.missing_sof != err_prev_q_.missing_sof ? 1u : 0u);
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
    pipeline_.clock(video_in, runs_tready, hist_inc, hist_index_q_);
    if (pass && s_axis_video.tuser && lut_pending_q_) {  // thresh_lut's bank swap
      lut_active_q_ ^= 1u;
      lut_pending_q_ = false;
    }
  }
  soft_reset_hold_q_ = false;

  // ---- Register file, after the edge.
  uint32_t intr_set = events;
  uint32_t intr_clear = 0;
  uint32_t cause_clear = 0;
  bool hist_index_written = false;
  bool soft_reset = false;
  uint8_t bresp = kOkay;
  if (aw_hs) {
    bresp = write_register(s_axil.awaddr, s_axil.wdata, s_axil.wstrb, intr_set, intr_clear,
                           cause_clear, hist_index_written, soft_reset);
  }
  if (hist_inc && !hist_index_written) ++hist_index_q_;

  const bool irq_before = irq();
  intr_state_q_ = (intr_state_q_ & ~intr_clear) | intr_set;  // a set wins over a clear
  error_cause_q_ = (error_cause_q_ & ~cause_clear) | cause_set;
  if (!irq_before && irq()) eof_to_irq_q_ = cycle_q_ - eof_edge_q_;
  if (frame_done) ++frame_count_q_;
  if (eof_seen) eof_edge_q_ = cycle_q_ - 1u;
  if (pass && s_axis_video.tuser && !hold) {
    in_frame_q_ = true;
  } else if (frame_closed) {
    in_frame_q_ = false;
  }
  if (video_sof) gate_open_q_ = enable_q_;
  ++cycle_q_;

  // ---- AXI4-Lite write channel: AW and W are taken together.
  if (aw_hs) {
    axil_q_.awready = axil_q_.wready = false;
    axil_q_.bvalid = true;
    axil_q_.bresp = bresp;
  } else if (!axil_q_.awready && !axil_q_.bvalid && s_axil.awvalid && s_axil.wvalid) {
    axil_q_.awready = axil_q_.wready = true;
  }
  if (b_hs) {
    axil_q_.bvalid = false;
    axil_q_.bresp = kOkay;
  }

  // ---- Read channel: one read in flight.
  if (rd_stage_q_ == 1) {
    rd_data_q_ = rd_value;
    rd_resp_q_ = rd_resp;
    rd_hist_q_ = hist_inc;
    rd_stage_q_ = 2;
  } else if (rd_stage_q_ == 2) {
    axil_q_.rvalid = true;
    axil_q_.rdata = rd_hist_q_ ? regs::hist_data::kCount.put(hist_rd_data) : rd_data_q_;
    axil_q_.rresp = rd_resp_q_;
    rd_stage_q_ = 3;
  }
  if (r_hs) {
    axil_q_.rvalid = false;
    axil_q_.rdata = 0;
    axil_q_.rresp = kOkay;
    axil_q_.arready = true;
    rd_stage_q_ = 0;
  }
  if (ar_hs) {
    axil_q_.arready = false;
    rd_addr_q_ = s_axil.araddr;
    rd_stage_q_ = 1;
  }

  if (soft_reset) {
    reset_datapath();
    soft_reset_hold_q_ = true;
  }
}

uint8_t CeilnavTop::write_register(uint32_t addr, uint32_t data, uint8_t strb, uint32_t& intr_set,
                                   uint32_t& intr_clear, uint32_t& cause_clear,
                                   bool& hist_index_written, bool& soft_reset) {
  const uint32_t a = addr & regs::kAddrMask;
  const regs::Register* reg = (a % 4 == 0) ? regs::find(a) : nullptr;
  if (reg == nullptr || !config_.has(*reg) || strb != 0xF || reg->write_mask() == 0) {
    return kSlvErr;
  }
  namespace r = regs;
  bool config_changed = false;
  switch (a) {
    case r::control::kOffset:
      enable_q_ = r::control::kEnable.get(data) != 0;
      run_sink_regs_q_ = r::control::kRunSink.get(data) != 0;
      soft_reset = r::control::kSoftReset.get(data) != 0;
      break;
    case r::intr_state::kOffset:
      intr_clear = data & reg->w1c_mask;
      break;
    case r::error_cause::kOffset:
      cause_clear = data & reg->w1c_mask;
      break;
    case r::intr_enable::kOffset:
      intr_enable_q_ = data & reg->rw_mask;
      break;
    case r::intr_test::kOffset:
      intr_set |= data & reg->wo_mask;
      break;
    case r::width::kOffset:
      cfg_q_.width = static_cast<uint16_t>(r::width::kValue.get(data));
      config_changed = true;
      break;
    case r::height::kOffset:
      cfg_q_.height = static_cast<uint16_t>(r::height::kValue.get(data));
      config_changed = true;
      break;
    case r::background_level::kOffset:
      cfg_q_.background_level = static_cast<uint8_t>(r::background_level::kValue.get(data));
      config_changed = true;
      break;
    case r::min_run_length::kOffset:
      cfg_q_.min_run_length = static_cast<uint16_t>(r::min_run_length::kValue.get(data));
      config_changed = true;
      break;
    case r::max_runs_per_row::kOffset:
      cfg_q_.max_runs_per_row = static_cast<uint16_t>(r::max_runs_per_row::kValue.get(data));
      config_changed = true;
      break;
    case r::hist_source::kOffset:
      cfg_q_.hist_source_remap = r::hist_source::kRemap.get(data) != 0;
      config_changed = true;
      break;
    case r::class_win_x::kOffset:
      cfg_q_.class_window.x0 = static_cast<uint16_t>(r::class_win_x::kX0.get(data));
      cfg_q_.class_window.x1 = static_cast<uint16_t>(r::class_win_x::kX1.get(data));
      config_changed = true;
      break;
    case r::class_win_y::kOffset:
      cfg_q_.class_window.y0 = static_cast<uint16_t>(r::class_win_y::kY0.get(data));
      cfg_q_.class_window.y1 = static_cast<uint16_t>(r::class_win_y::kY1.get(data));
      config_changed = true;
      break;
    case r::lut_index::kOffset:
      lut_index_q_ = static_cast<uint8_t>(r::lut_index::kValue.get(data));
      break;
    case r::lut_data::kOffset:
      // thresh_lut's write port: the shadow bank, swap pending.
      lut_bank_[lut_active_q_ ^ 1u][lut_index_q_] = lut_entry(
          static_cast<uint8_t>(r::lut_data::kRemap.get(data)), r::lut_data::kMask.get(data) != 0,
          static_cast<uint8_t>(r::lut_data::kClass.get(data)));
      lut_pending_q_ = true;
      ++lut_index_q_;
      config_changed = true;
      break;
    case r::hist_index::kOffset:
      hist_index_q_ = static_cast<uint8_t>(r::hist_index::kValue.get(data));
      hist_index_written = true;
      break;
    default:
      return kSlvErr;  // a writable register this model does not implement
  }
  if (config_changed) push_config();
  return kOkay;
}

uint32_t CeilnavTop::read_register(uint32_t addr, uint8_t& resp) const {
  resp = kOkay;
  const uint32_t a = addr & regs::kAddrMask;
  const regs::Register* reg = (a % 4 == 0) ? regs::find(a) : nullptr;
  if (reg == nullptr || !config_.has(*reg)) {
    resp = kSlvErr;
    return 0;
  }
  namespace r = regs;
  const FrameResults& res = pipeline_.results();
  const FrameErrorCounters& live = pipeline_.error_counters();
  const RunBeat head = pipeline_.m_axis_runs();
  const auto sat32 = [](uint64_t v) {
    return static_cast<uint32_t>(std::min<uint64_t>(v, std::numeric_limits<uint32_t>::max()));
  };
  switch (a) {
    case r::id::kOffset:
      return r::id::kReset;
    case r::version::kOffset:
      return r::version::kReset;
    case r::control::kOffset:
      return r::control::kEnable.put(enable_q_ ? 1u : 0u) |
             r::control::kRunSink.put(run_sink_regs_q_ ? 1u : 0u);
    case r::status::kOffset:
      return r::status::kInFrame.put(in_frame_q_ ? 1u : 0u) |
             r::status::kResultsValid.put(res.valid ? 1u : 0u) |
             r::status::kRunAvail.put(head.tvalid ? 1u : 0u) |
             r::status::kGateOpen.put(gate_open_q_ ? 1u : 0u) |
             r::status::kLutPending.put(lut_pending_q_ ? 1u : 0u);
    case r::intr_state::kOffset:
      return intr_state_q_;
    case r::error_cause::kOffset:
      return error_cause_q_;
    case r::intr_enable::kOffset:
      return intr_enable_q_;
    case r::width::kOffset:
      return r::width::kValue.put(cfg_q_.width);
    case r::height::kOffset:
      return r::height::kValue.put(cfg_q_.height);
    case r::background_level::kOffset:
      return r::background_level::kValue.put(cfg_q_.background_level);
    case r::min_run_length::kOffset:
      return r::min_run_length::kValue.put(cfg_q_.min_run_length);
    case r::max_runs_per_row::kOffset:
      return r::max_runs_per_row::kValue.put(cfg_q_.max_runs_per_row);
    case r::hist_source::kOffset:
      return r::hist_source::kRemap.put(cfg_q_.hist_source_remap ? 1u : 0u);
    case r::class_win_x::kOffset:
      return r::class_win_x::kX0.put(cfg_q_.class_window.x0) |
             r::class_win_x::kX1.put(cfg_q_.class_window.x1);
    case r::class_win_y::kOffset:
      return r::class_win_y::kY0.put(cfg_q_.class_window.y0) |
             r::class_win_y::kY1.put(cfg_q_.class_window.y1);
    case r::lut_index::kOffset:
      return r::lut_index::kValue.put(lut_index_q_);
    case r::hist_index::kOffset:
      return r::hist_index::kValue.put(hist_index_q_);
    case r::hist_data::kOffset:
      return 0;  // read through the histogram block's port (rd_hist_q_)
    case r::run_fifo_level::kOffset:
      return r::run_fifo_level::kValue.put(pipeline_.run_fifo_occupancy() +
                                           (head.tvalid ? 1u : 0u));
    case r::run_fifo_depth::kOffset:
      return r::run_fifo_depth::kValue.put(run_fifo_depth_);
    case r::run_word0::kOffset:
      if (!head.tvalid) return 0;
      return r::run_word0::kValid.put(1u) | r::run_word0::kLast.put(head.tlast ? 1u : 0u) |
             r::run_word0::kRow.put(head.tdata.row);
    case r::run_word1::kOffset:
      if (!head.tvalid) return 0;
      return r::run_word1::kXStart.put(head.tdata.x_start) |
             r::run_word1::kXEnd.put(head.tdata.x_end);
    case r::run_word2::kOffset:
      return head.tvalid ? r::run_word2::kSumW.put(head.tdata.sum_w) : 0u;
    case r::run_word3::kOffset:
      return head.tvalid ? r::run_word3::kSumXw.put(static_cast<uint32_t>(head.tdata.sum_xw)) : 0u;
    case r::res_frame_index::kOffset:
      return res.frame_index;
    case r::frame_count::kOffset:
      return frame_count_q_;
    case r::cycles_per_frame::kOffset:
      return sat32(res.cycles_in_frame);
    case r::eof_to_irq_cycles::kOffset:
      return eof_to_irq_q_;
    case r::runs_emitted::kOffset:
      return res.run_stats.runs_emitted;
    case r::runs_dropped_row_limit::kOffset:
      return res.run_stats.runs_dropped_row_limit;
    case r::runs_dropped_overflow::kOffset:
      return res.run_stats.runs_dropped_overflow;
    case r::run_fifo_high_water::kOffset:
      return res.run_stats.fifo_high_water;
    case r::res_early_eol::kOffset:
      return res.errors.early_eol;
    case r::res_late_eol::kOffset:
      return res.errors.late_eol;
    case r::res_early_sof::kOffset:
      return res.errors.early_sof;
    case r::res_missing_sof::kOffset:
      return res.errors.missing_sof;
    case r::res_frames_ok::kOffset:
      return res.errors.frames_ok;
    case r::res_frames_aborted::kOffset:
      return res.errors.frames_aborted;
    case r::cnt_early_eol::kOffset:
      return live.early_eol;
    case r::cnt_late_eol::kOffset:
      return live.late_eol;
    case r::cnt_early_sof::kOffset:
      return live.early_sof;
    case r::cnt_missing_sof::kOffset:
      return live.missing_sof;
    case r::cnt_frames_ok::kOffset:
      return live.frames_ok;
    case r::cnt_frames_aborted::kOffset:
      return live.frames_aborted;
    case r::run_trailers_lost::kOffset:
      return pipeline_.run_trailers_lost();
    case r::frames_overrun::kOffset:
      return pipeline_.frames_overrun();
    default:
      break;
  }
  const auto moment = [](int i) { return static_cast<size_t>(i); };
  if (const int i = regs::mom_grey_lo::kArray.index(a); i >= 0) {
    return lo(res.moments.grey[moment(i)]);
  }
  if (const int i = regs::mom_grey_hi::kArray.index(a); i >= 0) {
    return hi(res.moments.grey[moment(i)]);
  }
  if (const int i = regs::mom_mask_lo::kArray.index(a); i >= 0) {
    return lo(res.moments.mask[moment(i)]);
  }
  if (const int i = regs::mom_mask_hi::kArray.index(a); i >= 0) {
    return hi(res.moments.mask[moment(i)]);
  }
  // CLASS_MOM_*[i]: class c = i / 6 + 1, moment k = i % 6.
  const auto class_moment = [&res](int i) {
    return res.class_moments
        .cls[static_cast<size_t>(i / kMomentCount)][static_cast<size_t>(i % kMomentCount)];
  };
  if (const int i = regs::class_mom_lo::kArray.index(a); i >= 0) {
    return lo(class_moment(i));
  }
  if (const int i = regs::class_mom_hi::kArray.index(a); i >= 0) {
    return hi(class_moment(i));
  }
  // Write-only registers (INTR_TEST, LUT_DATA) read 0.
  return 0;
}

}  // namespace ceilnav::stream
