// ceilnav_top: the device. Pipeline + AXI4-Lite register file (map generated
// from rtl_model/regmap.json), interrupt, cycle counters, video gate and the
// run FIFO register window. Cycle-level model of rtl_model/ceilnav_top.sv.
// Timing and register semantics: docs/blocks/ceilnav_top.md, docs/registers.md.
#pragma once

#include <array>
#include <cstdint>

#include "ceilnav/regs.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/config.hpp"
#include "stream/pipeline.hpp"
#include "stream/results.hpp"

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

  // `config`: the device's build-time configuration (regs::kConfigTape,
  // regs::kConfigFull, ...): the optional blocks it has. A register of an
  // absent block answers SLVERR, as in the RTL built with the same parameters.
  explicit CeilnavTop(uint32_t run_fifo_depth = regs::kRunFifoDepth,
                      const regs::Config& config = regs::kConfigFull);

  // Asynchronous active-low reset (rst_ni) of every register, the register
  // file included. LUT contents (BRAM) are kept; the active bank becomes 0.
  void reset();

  // One rising clock edge. s_axis_video_tready is always 1.
  void clock(const VideoBeat& s_axis_video, const AxiLiteIn& s_axil, bool m_axis_runs_tready);

  // Registered outputs.
  const AxiLiteOut& s_axil_out() const { return axil_q_; }
  // The pipeline's run stream when CONTROL.RUN_SINK = 0; idle otherwise.
  RunBeat m_axis_runs() const { return run_sink_regs_q_ ? RunBeat{} : pipeline_.m_axis_runs(); }
  // Level: |(INTR_STATE & INTR_ENABLE).
  bool irq() const { return (intr_state_q_ & intr_enable_q_) != 0; }

  // Observability (not ports).
  const Pipeline& pipeline() const { return pipeline_; }
  uint32_t cycle() const { return cycle_q_; }  // edges since reset, wrapping
  uint32_t run_fifo_depth() const { return run_fifo_depth_; }
  const regs::Config& config() const { return config_; }

 private:
  // Value and response of a read of `addr`, from the current (pre-edge) state.
  uint32_t read_register(uint32_t addr, uint8_t& resp) const;
  // A write: the register file's part, applied after the edge.
  uint8_t write_register(uint32_t addr, uint32_t data, uint8_t strb, uint32_t& intr_set,
                         uint32_t& intr_clear, uint32_t& cause_clear, bool& hist_index_written,
                         bool& soft_reset);
  // The table the pipeline activates at its next SOF, given the two tracked banks.
  void push_config();
  void reset_datapath();

  uint32_t run_fifo_depth_;
  regs::Config config_;
  Pipeline pipeline_;

  // Register file.
  bool enable_q_ = false;
  bool run_sink_regs_q_ = false;
  uint32_t intr_state_q_ = 0;
  uint32_t intr_enable_q_ = 0;
  uint32_t error_cause_q_ = 0;  // ERROR_CAUSE (w1c)
  PipelineConfig cfg_q_{};      // WIDTH .. HIST_SOURCE (the LUT field unused)
  uint8_t lut_index_q_ = 0;
  uint8_t hist_index_q_ = 0;

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
  uint32_t eof_edge_q_ = 0;  // edge that accepted the last good EOF pixel
  uint32_t eof_to_irq_q_ = 0;

  // AXI4-Lite channels.
  AxiLiteOut axil_q_{};
  uint8_t rd_stage_q_ = 0;  // 0 idle, 1 sample on this edge, 2 respond on this edge, 3 rvalid
  uint32_t rd_addr_q_ = 0;
  uint32_t rd_data_q_ = 0;  // sampled value, waiting one edge for rvalid
  uint8_t rd_resp_q_ = 0;
  bool rd_hist_q_ = false;  // the pending response is the histogram read port's data
};

}  // namespace ceilnav::stream
