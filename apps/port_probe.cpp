// PortProbe: frame, irq, run-stream and AXI4-Lite accounting at the device
// ports, edge by edge.
#include "apps/port_probe.hpp"

namespace ceilnav::app {

void PortProbe::on_edge(uint64_t edge, const drivers::SimInputs& in,
                        const drivers::SimOutputs& out) {
  if (!started_) {
    started_ = true;
    irq_prev_ = out.irq;
    c_.first_edge = edge;
  }
  ++c_.edges;
  const stream::VideoBeat& v = in.s_axis_video;
  const bool accept = v.tvalid && out.s_axis_video_tready;
  if (v.tvalid && !out.s_axis_video_tready) ++c_.bubbles;
  if (accept && v.tuser) {
    ++c_.frames_started;
    c_.sof_seen = true;
    c_.eof_seen = false;
    c_.irq_rise_seen = false;
    c_.sof_edge = edge;
    c_.frame_cycles = c_.tvalid_cycles = c_.accepted_beats = 0;
    in_frame_ = true;
    lines_ = 0;
  }
  if (in_frame_) {
    ++c_.frame_cycles;
    if (v.tvalid) ++c_.tvalid_cycles;
    if (accept) ++c_.accepted_beats;
    if (accept && v.tlast && ++lines_ == lines_per_frame_) {
      in_frame_ = false;
      c_.eof_seen = true;
      c_.eof_edge = edge;
    }
  }
  // out.irq is the level after edge - 1: a rise seen here happened on edge - 1.
  if (out.irq && !irq_prev_ && c_.eof_seen && !c_.irq_rise_seen && edge - 1 >= c_.eof_edge) {
    c_.irq_rise_seen = true;
    c_.irq_rise_edge = edge - 1;
  }
  irq_prev_ = out.irq;

  if (out.m_axis_runs.tvalid) {
    if (in.m_axis_runs_tready) {
      ++c_.run_beats;
    } else {
      ++c_.run_stall_cycles;
    }
  }
  if (!in.m_axis_runs_tready) ++c_.run_tready_low_cycles;
  if (in.s_axil.arvalid && out.s_axil.arready) ++c_.axil_reads;
  if (in.s_axil.awvalid && in.s_axil.wvalid && out.s_axil.awready) ++c_.axil_writes;
}

PortProbe::Counts PortProbe::take() {
  Counts done = c_;
  c_ = Counts{};
  started_ = false;
  // A frame still open keeps its counts into the next window (it should not happen).
  if (in_frame_) {
    c_.sof_seen = true;
    c_.sof_edge = done.sof_edge;
    c_.frame_cycles = done.frame_cycles;
    c_.tvalid_cycles = done.tvalid_cycles;
    c_.accepted_beats = done.accepted_beats;
  }
  return done;
}

}  // namespace ceilnav::app
