// `ceilnav profile`, the measurement at the ports: a SimObserver counting
// handshakes over a window of edges. See docs/profile.md.
#pragma once

#include <cstdint>

#include "drivers/sim_bus.hpp"

namespace ceilnav::app {

// Counts at the device ports over a window of edges (one frame's host cycle:
// configure, stream, interrupt, readout). Handshakes are taken as AXI defines
// them: inputs on an edge against the registered outputs before it.
class PortProbe : public drivers::SimObserver {
 public:
  struct Counts {
    // The frame: from the edge accepting the SOF beat (tvalid && tready &&
    // tuser) to the one accepting the lines_per_frame-th tlast, inclusive.
    bool sof_seen = false, eof_seen = false;
    int frames_started = 0;  // SOF beats accepted in the window (1 expected)
    uint64_t sof_edge = 0, eof_edge = 0;
    uint64_t frame_cycles = 0;    // edges in [sof_edge, eof_edge]
    uint64_t tvalid_cycles = 0;   // of those, edges with s_axis_video_tvalid
    uint64_t accepted_beats = 0;  // of those, edges with tvalid && tready
    uint64_t bubbles = 0;         // whole window: edges with tvalid && !tready
    // irq: first 0 -> 1 after the EOF edge; latency = rise edge - eof_edge
    // (the register EOF_TO_IRQ_CYCLES counts the same way).
    bool irq_rise_seen = false;
    uint64_t irq_rise_edge = 0;
    uint64_t run_beats = 0;         // m_axis_runs tvalid && tready (trailers included)
    uint64_t run_stall_cycles = 0;  // m_axis_runs tvalid && !tready
    uint64_t run_tready_low_cycles = 0;
    uint64_t axil_reads = 0;   // AR handshakes
    uint64_t axil_writes = 0;  // AW (= W) handshakes
    uint64_t first_edge = 0, edges = 0;
  };

  explicit PortProbe(int lines_per_frame) : lines_per_frame_(lines_per_frame) {}
  void on_edge(uint64_t edge, const drivers::SimInputs& in,
               const drivers::SimOutputs& out) override;
  // The counts since the previous take(); starts a new window.
  Counts take();

 private:
  int lines_per_frame_;
  Counts c_{};
  bool in_frame_ = false;
  int lines_ = 0;
  bool irq_prev_ = false;
  bool started_ = false;
};

}  // namespace ceilnav::app
