// PortProbe's accounting on hand-made edge sequences (no device): the frame
// span from the SOF beat to the last line's tlast, tvalid cycles and bubbles,
// the EOF-to-irq latency, run-stream beats and stalls, AXI4-Lite handshakes,
// and a frame left open across take().
#include <gtest/gtest.h>

#include <cstdint>

#include "apps/port_probe.hpp"

namespace ceilnav::app {
namespace {

// Drives a probe edge by edge.
struct Edges {
  PortProbe probe;
  uint64_t edge = 100;
  drivers::SimOutputs out{};
  explicit Edges(int lines) : probe(lines) {}
  void clock(const drivers::SimInputs& in) { probe.on_edge(edge++, in, out); }
  void idle(int n) {
    for (int i = 0; i < n; ++i) clock({});
  }
  // One pixel; tready as given.
  void pixel(bool sof, bool eol, bool tready = true) {
    drivers::SimInputs in{};
    in.s_axis_video.tvalid = true;
    in.s_axis_video.tuser = sof;
    in.s_axis_video.tlast = eol;
    out.s_axis_video_tready = tready;
    clock(in);
    out.s_axis_video_tready = true;
  }
};

TEST(PortProbe, FrameSpansSofToLastLineEnd) {
  Edges e(2);
  e.idle(3);
  e.pixel(true, false);  // edge 103: SOF
  e.pixel(false, true);  // line 1 ends
  e.idle(2);             // line blanking inside the frame
  e.pixel(false, false);
  e.pixel(false, true);  // edge 108: line 2 ends: EOF
  e.idle(4);
  const PortProbe::Counts c = e.probe.take();
  EXPECT_EQ(c.first_edge, 100u);
  EXPECT_EQ(c.edges, 13u);
  EXPECT_EQ(c.frames_started, 1);
  EXPECT_TRUE(c.sof_seen);
  EXPECT_TRUE(c.eof_seen);
  EXPECT_EQ(c.sof_edge, 103u);
  EXPECT_EQ(c.eof_edge, 108u);
  EXPECT_EQ(c.frame_cycles, 6u);
  EXPECT_EQ(c.tvalid_cycles, 4u);
  EXPECT_EQ(c.accepted_beats, 4u);
  EXPECT_EQ(c.bubbles, 0u);
  EXPECT_FALSE(c.irq_rise_seen);
}

TEST(PortProbe, BeatsHeldWithoutTreadyAreBubbles) {
  Edges e(1);
  e.pixel(true, false, false);  // not taken: no SOF yet
  e.pixel(true, false);         // edge 101: SOF taken
  e.pixel(false, false, false);
  e.pixel(false, false);
  e.pixel(false, true);  // edge 104: EOF
  const PortProbe::Counts c = e.probe.take();
  EXPECT_EQ(c.bubbles, 2u);
  EXPECT_EQ(c.sof_edge, 101u);
  EXPECT_EQ(c.frame_cycles, 4u);
  EXPECT_EQ(c.tvalid_cycles, 4u);
  EXPECT_EQ(c.accepted_beats, 3u);
}

TEST(PortProbe, IrqLatencyCountsFromTheEofEdge) {
  Edges e(1);
  e.pixel(true, false);
  e.pixel(false, true);  // edge 101: EOF
  e.idle(5);             // edges 102..106
  e.out.irq = true;      // the level after edge 106: the rise happened on edge 106
  e.idle(1);             // edge 107
  e.idle(1);             // still high: no second rise
  e.out.irq = false;
  e.idle(1);
  e.out.irq = true;
  e.idle(1);  // a later rise does not move the first
  const PortProbe::Counts c = e.probe.take();
  EXPECT_EQ(c.eof_edge, 101u);
  ASSERT_TRUE(c.irq_rise_seen);
  EXPECT_EQ(c.irq_rise_edge, 106u);
  EXPECT_EQ(c.irq_rise_edge - c.eof_edge, 5u);
}

TEST(PortProbe, IrqHighBeforeTheFrameEndsIsNoRise) {
  Edges e(1);
  e.out.irq = true;
  e.idle(2);
  e.pixel(true, false);
  e.pixel(false, true);
  e.idle(2);
  EXPECT_FALSE(e.probe.take().irq_rise_seen);
}

TEST(PortProbe, RunStreamAndRegisterHandshakes) {
  Edges e(1);
  drivers::SimInputs in{};
  e.out.m_axis_runs.tvalid = true;
  in.m_axis_runs_tready = true;
  e.clock(in);  // a beat
  in.m_axis_runs_tready = false;
  e.clock(in);  // a stall
  e.clock(in);  // another
  e.out.m_axis_runs.tvalid = false;
  e.clock(in);  // tready low, nothing offered
  in = {};
  in.s_axil.arvalid = true;
  e.clock(in);  // no arready: no read
  e.out.s_axil.arready = true;
  e.clock(in);  // a read
  in = {};
  in.s_axil.awvalid = true;
  e.out.s_axil.awready = true;
  e.clock(in);  // address without data: no write
  in.s_axil.wvalid = true;
  e.clock(in);  // a write
  const PortProbe::Counts c = e.probe.take();
  EXPECT_EQ(c.run_beats, 1u);
  EXPECT_EQ(c.run_stall_cycles, 2u);
  EXPECT_EQ(c.run_tready_low_cycles, 3u);
  EXPECT_EQ(c.axil_reads, 1u);
  EXPECT_EQ(c.axil_writes, 1u);
  EXPECT_FALSE(c.sof_seen);
}

TEST(PortProbe, TakeStartsANewWindowAndKeepsAnOpenFrame) {
  Edges e(2);
  e.pixel(true, false);  // edge 100: SOF
  e.pixel(false, true);  // line 1 of 2
  const PortProbe::Counts first = e.probe.take();
  EXPECT_TRUE(first.sof_seen);
  EXPECT_FALSE(first.eof_seen);
  EXPECT_EQ(first.frame_cycles, 2u);
  e.pixel(false, false);
  e.pixel(false, true);  // edge 103: EOF
  const PortProbe::Counts second = e.probe.take();
  EXPECT_EQ(second.first_edge, 102u);
  EXPECT_EQ(second.edges, 2u);
  EXPECT_EQ(second.frames_started, 0);
  EXPECT_EQ(second.sof_edge, 100u);
  EXPECT_TRUE(second.eof_seen);
  EXPECT_EQ(second.eof_edge, 103u);
  EXPECT_EQ(second.frame_cycles, 4u);
  EXPECT_EQ(second.accepted_beats, 4u);
  const PortProbe::Counts third = e.probe.take();  // nothing since
  EXPECT_EQ(third.edges, 0u);
  EXPECT_FALSE(third.sof_seen);
}

}  // namespace
}  // namespace ceilnav::app
