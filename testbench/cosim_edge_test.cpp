// Co-simulation: rtl_model/edge_detect.sv (Verilated, FifoDepth 1024 and 8)
// against stream::EdgeDetector, every output port on every clock, under
// random frames (1x1 up to 640x480 and 2048-wide thin frames), tvalid gaps,
// zero-blanking back-to-back frames, aborts (alone and combined with the next
// SOF), resets mid-frame, stray beats, random configurations (enable, all
// four modes, thresholds 0..4095) on the config port, random m_axis
// back-pressure with long stalls that overflow the FIFO, and a real photo.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <vector>

// First: it includes verilated.h with the warnings that it trips switched off.
#include "testbench/block_bench.hpp"
#include "testbench/lut_stream.hpp"
#include "testbench/ports.hpp"

#include "Vedge_detect.h"
#include "Vedge_detect_d8.h"

#include "stream/beat.hpp"
#include "stream/edge.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::testbench {
namespace {

using stream::EdgeConfig;
using stream::EdgeDetector;
using stream::EdgeMode;
using stream::LutBeat;
using stream::test::LutFrame;

// One clock of stimulus: the s_lut beat, the config port, tready, and an
// optional reset cycle before the edge.
struct Stim {
  LutBeat beat;
  EdgeConfig cfg;
  bool tready = true;
  bool reset_before = false;
};

struct Events {
  std::array<uint64_t, 3> edges{};  // edge beats transferred, per kind
  uint64_t trailers = 0;            // trailer beats transferred
  uint64_t aborted = 0;             // trailers with kEdgeTrailerAborted
  uint64_t overflowed = 0;          // trailers with kEdgeTrailerOverflow
  uint64_t done = 0;                // done pulses
  uint32_t max_occupancy = 0;
  uint64_t trailers_lost = 0;  // across resets
  uint64_t edge_total() const { return edges[0] + edges[1] + edges[2]; }
};

// edge_detect's ports for BlockBench (either FIFO depth); counts what the
// stream reached in `events`.
template <class Top>
struct EdgePorts {
  using Stim = testbench::Stim;

  void drive(Top& d, const Stim& s) {
    drive_s_lut(d, s.beat);
    d.cfg_enable_i = s.cfg.enable;
    d.cfg_mode_i = static_cast<uint8_t>(s.cfg.mode) & 3u;
    d.cfg_threshold_i = s.cfg.threshold & 0xFFFu;
    d.m_axis_edges_tready_i = s.tready;
  }
  // The beat on the output before the edge is transferred if tready.
  void before_edge(Cosim<Top>& /*sim*/, const EdgeDetector& m, const Stim& s) {
    const stream::EdgeBeat before = m.m_axis_edges();
    if (before.tvalid && s.tready) {
      if (before.tlast) {
        const auto flags = static_cast<uint32_t>(before.tdata >> 32);
        ++events.trailers;
        if (flags & stream::kEdgeTrailerAborted) ++events.aborted;
        if (flags & stream::kEdgeTrailerOverflow) ++events.overflowed;
      } else {
        const auto kind = static_cast<size_t>(stream::unpack_edge_beat(before.tdata).kind);
        ++events.edges.at(kind);
      }
    }
  }
  void clock(EdgeDetector& m, const Stim& s) {
    m.set_config(s.cfg);
    m.clock(s.beat, s.tready);
  }
  bool compare(Cosim<Top>& sim, const EdgeDetector& m) {
    auto& d = sim.dut();
    const stream::EdgeBeat out = m.m_axis_edges();
    bool ok = sim.check("m_axis_edges_tvalid_o", d.m_axis_edges_tvalid_o, out.tvalid);
    ok = sim.check("m_axis_edges_tlast_o", d.m_axis_edges_tlast_o, out.tlast) && ok;
    ok = sim.check("m_axis_edges_tdata_o", d.m_axis_edges_tdata_o, out.tdata) && ok;
    const stream::EdgeStats& st = m.last_frame_stats();
    ok = sim.check("done_o", d.done_o, m.done()) && ok;
    ok = sim.check("pending_o", d.pending_o, m.pending()) && ok;
    ok = sim.check("edges_emitted_o", d.edges_emitted_o, st.edges_emitted) && ok;
    ok = sim.check("edges_dropped_o", d.edges_dropped_o, st.edges_dropped) && ok;
    ok = sim.check("fifo_occupancy_o", d.fifo_occupancy_o, m.fifo_occupancy()) && ok;
    ok = sim.check("trailers_lost_o", d.trailers_lost_o, m.trailers_lost()) && ok;
    if (m.done()) ++events.done;
    if (m.trailers_lost() > lost_seen) events.trailers_lost += m.trailers_lost() - lost_seen;
    lost_seen = m.trailers_lost();
    events.max_occupancy = std::max(events.max_occupancy, m.fifo_occupancy());
    return ok;
  }

  Events events;
  uint32_t lost_seen = 0;
};

template <class Top>
using EdgeBench = BlockBench<Top, EdgeDetector, EdgePorts<Top>>;

// Random legal LutBeat streams with a random config port and tready.
class StimGen : public FifoStreamGen<StimGen, Stim, EdgeConfig> {
 public:
  StimGen(uint64_t seed, uint32_t max_stall_cycles)
      : FifoStreamGen(seed, LutStreamShape{.thin_frames = true}, max_stall_cycles) {
    cfg_ = random_config();
  }

  EdgeConfig random_config() {
    EdgeConfig c;
    c.enable = rng_.chance(0.93);
    const int64_t m = rng_.uniform(0, 99);
    c.mode = m < 32   ? EdgeMode::kHorizontal
             : m < 64 ? EdgeMode::kVertical
             : m < 97 ? EdgeMode::kSobel
                      : EdgeMode::kReserved;
    static constexpr uint16_t kT[] = {0, 1, 8, 20, 40, 100, 254, 255, 1000, 2039, 2040, 4095};
    c.threshold = rng_.chance(0.5)             ? kT[rng_.uniform(0, 11)]
                  : c.mode == EdgeMode::kSobel ? rng_.uniform_as<uint16_t>(0, 400)
                                               : rng_.uniform_as<uint16_t>(0, 60);
    return c;
  }

  // Uniform noise: nearly every pixel is an edge at a low threshold.
  LutFrame noise_frame(uint16_t w, uint16_t h) {
    LutFrame f{w, h, {}, std::vector<uint8_t>(size_t{w} * h), std::vector<uint8_t>(size_t{w} * h)};
    for (auto& p : f.remap) p = rng_.byte();
    return f;
  }

  // A dense frame while the consumer stalls: fills a FIFO of 1024 entries,
  // so edges are dropped and trailers get lost.
  void append_burst(std::vector<Stim>& out) {
    const auto mode = static_cast<EdgeMode>(rng_.uniform(0, 2));
    cfg_ = {true, mode, rng_.uniform_as<uint16_t>(0, 10)};
    stall_ = true;
    append_frame(
        out, noise_frame(rng_.uniform_as<uint16_t>(40, 120), rng_.uniform_as<uint16_t>(10, 30)));
    stall_ = rng_.chance(0.5);  // sometimes the next frame's trailer is lost too
    append_frame(out,
                 noise_frame(rng_.uniform_as<uint16_t>(1, 20), rng_.uniform_as<uint16_t>(1, 4)));
    stall_ = false;
  }

  // Tiny frames (1..4 x 1..4) back to back, many aborted by the next SOF: an
  // edge can then write an aborted-frame trailer and a 1x1 frame's trailer.
  std::vector<Stim> tiny_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      append_frame(out,
                   noise_frame(rng_.uniform_as<uint16_t>(1, 4), rng_.uniform_as<uint16_t>(1, 4)));
    }
    finish(out);
    return out;
  }
};

void print_events(const char* name, uint64_t cycles, const Events& e) {
  std::printf(
      "%s: %llu cycles compared; edges %llu horizontal, %llu vertical, %llu Sobel; %llu trailers "
      "(%llu aborted, %llu overflow), %llu done, max occupancy %u, %llu trailers lost\n",
      name, static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(e.edges[0]),
      static_cast<unsigned long long>(e.edges[1]), static_cast<unsigned long long>(e.edges[2]),
      static_cast<unsigned long long>(e.trailers), static_cast<unsigned long long>(e.aborted),
      static_cast<unsigned long long>(e.overflowed), static_cast<unsigned long long>(e.done),
      e.max_occupancy, static_cast<unsigned long long>(e.trailers_lost));
}

// Runs `stim` on the RTL with FIFO depth `depth` (Top) and the model of the
// same depth; prints and returns what the stream reached.
template <class Top>
Events run_bench(const char* name, uint64_t seed, uint32_t depth, const std::vector<Stim>& stim) {
  EdgeBench<Top> bench(name, seed, depth);
  EXPECT_TRUE(bench.run(stim));
  print_events(name, bench.cycles(), bench.ports().events);
  return bench.ports().events;
}

TEST(CosimEdge, RandomFramesDepth1024) {
  const uint64_t seed = cosim_seed(0xED6E0001);
  StimGen gen(seed, 6000);
  const auto stim = gen.random_stream(cosim_count(1500000), 0.03);
  const Events e = run_bench<Vedge_detect>("edge_d1024", seed, 1024, stim);
  for (uint64_t n : e.edges) EXPECT_GT(n, 10000u);
  EXPECT_GT(e.aborted, 50u);
  EXPECT_GT(e.done, 200u);
  EXPECT_EQ(e.max_occupancy, 1024u);
  EXPECT_GT(e.overflowed, 5u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimEdge, RandomFramesDepth8BackPressure) {
  const uint64_t seed = cosim_seed(0xED6E0002);
  StimGen gen(seed, 400);
  const auto stim = gen.random_stream(cosim_count(800000), 0.01);
  const Events e = run_bench<Vedge_detect_d8>("edge_d8", seed, 8, stim);
  EXPECT_GT(e.edge_total(), 10000u);
  EXPECT_EQ(e.max_occupancy, 8u);
  EXPECT_GT(e.overflowed, 50u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimEdge, TinyFramesDepth8) {
  const uint64_t seed = cosim_seed(0xED6E0003);
  StimGen gen(seed, 200);
  const auto stim = gen.tiny_stream(cosim_count(200000));
  const Events e = run_bench<Vedge_detect_d8>("edge_tiny_d8", seed, 8, stim);
  EXPECT_GT(e.aborted, 1000u);
  EXPECT_GT(e.edges[2], 100u);
  EXPECT_GT(e.trailers_lost, 0u);
}

// A real photo (building.jpg from opencv-doc) in each mode, back to back
// under random back-pressure.
TEST(CosimEdge, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0xED6E0004);
  const auto img = stream::test::load_photo("building.jpg");
  ASSERT_TRUE(img) << "opencv-doc sample data missing";
  StimGen gen(seed, 3000);
  std::array<stream::LutEntry, 256> lut{};
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = stream::lut_entry(static_cast<uint8_t>(g), false);
  }
  const LutFrame f = lut_frame(*img, lut);
  std::vector<Stim> stim;
  for (EdgeMode mode : {EdgeMode::kHorizontal, EdgeMode::kVertical, EdgeMode::kSobel}) {
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), mode == EdgeMode::kVertical ? 0.2 : 0.0);
    const EdgeConfig cfg{true, mode, static_cast<uint16_t>(mode == EdgeMode::kSobel ? 150 : 20)};
    for (const auto& b : beats) {
      Stim s = gen.make(b);
      s.cfg = cfg;
      stim.push_back(s);
    }
  }
  gen.finish(stim);
  const Events e = run_bench<Vedge_detect>("edge_photo", seed, 1024, stim);
  EXPECT_EQ(e.done, 3u);
  for (uint64_t n : e.edges) EXPECT_GT(n, 1000u);
}

}  // namespace
}  // namespace ceilnav::testbench
