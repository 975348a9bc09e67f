// ceilnav_top: the device. Pipeline + the generated register block
// (stream::RegBlock, from rtl_model/regmap.json: decode, storage, interrupt)
// + the hardware side of the registers (events, cycle counters, video gate,
// LUT write port, run FIFO register window). Cycle-level model of
// rtl_model/ceilnav_top.sv.
// Timing and register semantics: docs/blocks/ceilnav_top.md, docs/registers.md.
#pragma once

#include <array>
#include <cstdint>

#include "ceilnav/regblock.hpp"
#include "ceilnav/regs.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/pipeline.hpp"

namespace ceilnav::stream {

class CeilnavTop {
 public:
  // AR handshake on edge e -> the register is sampled on edge e+1 (its read
  // side effect happens there) -> rvalid rises on edge e+kReadLatencyCycles.
  static constexpr int kReadLatencyCycles = 2;
  // EOF pixel accepted on edge t -> INTR_STATE.FRAME_DONE set on edge t+11.
  static constexpr int kEofToIntrCycles = Pipeline::kEofToFrameDoneCycles + 1;

  // INTR_STATE / INTR_ENABLE / INTR_TEST bits.
  static constexpr uint32_t kIntrFrameDone = regs::intr_state::kFrameDone.mask();
  static constexpr uint32_t kIntrRunOverflow = regs::intr_state::kRunOverflow.mask();
  static constexpr uint32_t kIntrFrameError = regs::intr_state::kFrameError.mask();
  static constexpr uint32_t kIntrHoughDone = regs::intr_state::kHoughDone.mask();

  // `config`: the device's build-time configuration (regs::kConfigTape,
  // regs::kConfigFull, ...): the optional blocks it has. A register of an
  // absent block answers SLVERR, as in the RTL built with the same parameters.
  // hough_shape: the hough block's compile-time shape (the RTL top's
  // HoughLanes, HoughThetaStep, HoughRhoBits, HoughAccBits; HOUGH_SHAPE).
  // ori_bins: the orientation block's bins (the RTL top's OriBins;
  // ORI_STATUS.NUM_BINS), used in configurations with the block.
  explicit CeilnavTop(uint32_t run_fifo_depth = regs::kRunFifoDepth,
                      const regs::Config& config = regs::kConfigFull,
                      const HoughShape& hough_shape = HoughShape{},
                      uint32_t ori_bins = Orientation::kDefaultBins);

  // Synchronous active-low reset (rst_ni) of every register, the register
  // file included. LUT contents (BRAM) are kept; the active bank becomes 0.
  void reset();

  // One rising clock edge. s_axis_video_tready is always 1.
  void clock(const VideoBeat& s_axis_video, const AxiLiteIn& s_axil, bool m_axis_runs_tready);

  // Registered outputs.
  const AxiLiteOut& s_axil_out() const { return regs_.out(); }
  // The pipeline's run stream when CONTROL.RUN_SINK = 0; idle otherwise.
  RunBeat m_axis_runs() const { return run_sink() ? RunBeat{} : pipeline_.m_axis_runs(); }
  // Level: |(INTR_STATE & INTR_ENABLE).
  bool irq() const { return regs_.irq(); }

  // Observability (not ports).
  const Pipeline& pipeline() const { return pipeline_; }
  uint32_t cycle() const { return cycle_q_; }  // edges since reset, wrapping
  uint32_t run_fifo_depth() const { return run_fifo_depth_; }
  const regs::Config& config() const { return regs_.config(); }

 private:
  bool run_sink() const { return regs_.reg2hw().control.run_sink != 0; }
  // What the registers read (the ro inputs of the register block), from the
  // state before the edge.
  void fill_read_inputs();
  // The pipeline's configuration from the register block's stored fields.
  PipelineConfig pipeline_config() const;
  // The table the pipeline activates at its next SOF, given the two tracked banks.
  void push_config();
  void reset_datapath();

  uint32_t run_fifo_depth_;
  Pipeline pipeline_;
  RegBlock regs_;
  Hw2Reg hw_{};  // inputs of the register block on this edge

  // The threshold LUT as the hardware holds it: two BRAM banks, the active
  // bank select and the pending-swap flag of thresh_lut, mirrored here because
  // Pipeline::set_config writes a whole table.
  std::array<std::array<LutEntry, 256>, 2> lut_bank_{};
  unsigned lut_active_q_ = 0;
  bool lut_pending_q_ = false;

  // Video gate and status.
  bool gate_open_q_ = false;
  bool in_frame_q_ = false;
  bool soft_reset_hold_q_ = false;  // datapath held in reset on this edge

  // Event detection: copies of the pipeline's counters one edge old.
  FrameErrorCounters err_prev_q_{};
  uint32_t trailers_lost_prev_q_ = 0;

  // Counters.
  uint32_t cycle_q_ = 0;
  uint32_t frame_count_q_ = 0;
  uint32_t hough_frame_count_q_ = 0;
  uint32_t eof_age_q_ = 0;  // EOF_TO_IRQ_CYCLES if irq rose on the next edge
  uint32_t eof_to_irq_q_ = 0;

  // Result store read port (MOM_* and the published frame meta): the word
  // read and RESULTS_VALID on the read edge.
  uint32_t store_rd_q_ = 0;
  bool store_rd_valid_q_ = false;
};

}  // namespace ceilnav::stream
