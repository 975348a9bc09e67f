// Co-simulation: rtl_model/hough.sv against stream::Hough, every output port
// on every clock, in two parameter sets (Vhough: Lanes 4, ThetaStep 4,
// RhoBits 6, AccBits 16, the iCE40 configuration; Vhough_big: Lanes 8,
// ThetaStep 1, RhoBits 9, AccBits 12): random edge lists and
// edges of real lines, random tvalid gaps, random configurations per frame
// (theta sub-ranges, 1..3 thetas so that one edge is one cycle and repeated
// points hit the same cell on consecutive edges: the read-modify-write
// forwarding), frames back to back (double buffer), host reads racing the
// next frame's voting, disabled frames, bad coordinates, resets. Besides
// RTL == C++, the cells read through the RTL port are checked against the
// golden accumulator.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "golden/hough_ref.hpp"
#include "stream/hough.hpp"
#include "testbench/block_bench.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "Vhough.h"
#include "Vhough_big.h"
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::testbench {
namespace {

using golden::EdgePoint;
using stream::EdgeBeat;
using stream::Hough;
using stream::HoughConfig;
using stream::HoughShape;

const HoughShape kSmall{4, 4, 6, 16};
const HoughShape kBig{8, 1, 9, 12};

struct HoughCycle {
  EdgeBeat in;
  HoughConfig cfg;
  bool rd_en = false;
  uint32_t rd_index = 0;
  bool reset_before = false;
};

template <class Top>
struct HoughPorts {
  using Stim = HoughCycle;
  uint64_t transfers = 0;
  uint64_t dones = 0;
  uint64_t frames_dropping = 0;    // published frames with dropped votes
  uint64_t frames_saturating = 0;  // published frames with clipped cells

  void drive(Top& d, const HoughCycle& c) {
    d.s_axis_edges_tvalid_i = c.in.tvalid;
    d.s_axis_edges_tdata_i = c.in.tdata;
    d.s_axis_edges_tlast_i = c.in.tlast;
    d.cfg_enable_i = c.cfg.enable;
    d.cfg_unit_weight_i = c.cfg.unit_weight;
    d.cfg_weight_shift_i = c.cfg.weight_shift;
    d.cfg_rho_shift_i = c.cfg.rho_shift;
    d.cfg_theta_first_i = c.cfg.theta_first;
    d.cfg_theta_count_i = c.cfg.theta_count;
    d.cfg_width_i = c.cfg.width;
    d.rd_en_i = c.rd_en;
    d.rd_index_i = static_cast<std::remove_reference_t<decltype(d.rd_index_i)>>(c.rd_index);
  }
  void before_edge(Cosim<Top>& /*sim*/, const Hough& m, const HoughCycle& c) {
    transfers += (c.in.tvalid && m.tready()) ? 1u : 0u;
  }
  void clock(Hough& m, const HoughCycle& c) { m.clock(c.in, c.cfg, c.rd_en, c.rd_index); }
  bool compare(Cosim<Top>& sim, const Hough& m) {
    const Top& d = sim.dut();
    const stream::HoughCounters& k = m.counters();
    bool ok = sim.check("s_axis_edges_tready_o", d.s_axis_edges_tready_o, m.tready());
    ok = sim.check("done_o", d.done_o, m.done()) && ok;
    ok = sim.check("rd_data_o", d.rd_data_o, m.rd_data()) && ok;
    ok = sim.check("results_valid_o", d.results_valid_o, m.results_valid()) && ok;
    ok = sim.check("state_o", d.state_o, static_cast<uint32_t>(m.state())) && ok;
    ok = sim.check("edges_o", d.edges_o, k.edges) && ok;
    ok = sim.check("bad_edges_o", d.bad_edges_o, k.bad_edges) && ok;
    ok = sim.check("votes_o", d.votes_o, k.votes) && ok;
    ok = sim.check("dropped_o", d.dropped_o, k.dropped) && ok;
    ok = sim.check("saturated_o", d.saturated_o, k.saturated) && ok;
    ok = sim.check("trailer_edges_o", d.trailer_edges_o, k.trailer_edges) && ok;
    ok = sim.check("trailer_flags_o", d.trailer_flags_o, k.trailer_flags) && ok;
    if (m.done()) {
      ++dones;
      frames_dropping += k.dropped > 0 ? 1u : 0u;
      frames_saturating += k.saturated > 0 ? 1u : 0u;
    }
    return ok;
  }
};

template <class Top>
using HoughBench = BlockBench<Top, Hough, HoughPorts<Top>>;

// A line of random direction and offset through (or past) w x h.
std::vector<EdgePoint> random_line(Rng& rng, int w, int h) {
  return golden::line_points(static_cast<double>(rng.uniform(-w / 2, w + h)),
                             static_cast<double>(rng.uniform(0, 179)), w, h);
}

struct Frame {
  std::vector<uint64_t> words;  // edge beats
  std::vector<EdgePoint> points;
  uint64_t trailer = 0;
  HoughConfig cfg;
};

Frame random_frame(Rng& rng, const HoughShape& shape) {
  Frame f;
  const int w = static_cast<int>(rng.uniform(1, 640));
  const int h = static_cast<int>(rng.uniform(1, 480));
  const int64_t kind = rng.uniform(0, 9);
  if (kind < 4) {
    const int64_t n = rng.uniform(0, 80);
    for (int64_t i = 0; i < n; ++i) {
      const EdgePoint p{rng.uniform_as<uint16_t>(0, w - 1), rng.uniform_as<uint16_t>(0, h - 1)};
      const int64_t repeat = rng.chance(0.3) ? rng.uniform(2, 4) : 1;  // the same cell again
      for (int64_t r = 0; r < repeat; ++r) f.points.push_back(p);
    }
  } else if (kind < 8) {
    for (int l = static_cast<int>(rng.uniform(1, 3)); l > 0; --l) {
      const auto pts = random_line(rng, std::min(w, 160), std::min(h, 120));
      f.points.insert(f.points.end(), pts.begin(), pts.end());
    }
  } else {  // one point many times: the same cells on every edge (saturates)
    f.points.assign(
        static_cast<size_t>(rng.uniform(1, 60)),
        EdgePoint{rng.uniform_as<uint16_t>(0, w - 1), rng.uniform_as<uint16_t>(0, h - 1)});
  }  // a random list may be empty: an empty frame
  for (const EdgePoint& p : f.points) {
    f.words.push_back(stream::edge_word(p.x, p.y, static_cast<uint32_t>(rng.uniform(0, 0x7FFF))));
  }
  if (rng.chance(0.1)) {  // a coordinate past 2047: counted, not voted
    f.words.insert(f.words.begin() + static_cast<int64_t>(rng.index(f.words.size() + 1)),
                   stream::edge_word(rng.uniform_as<uint16_t>(2048, 65535), 3));
  }
  f.trailer = stream::trailer_word(static_cast<uint32_t>(f.words.size()),
                                   static_cast<uint32_t>(rng.uniform(0, 0xFFFFFFFF)));
  HoughConfig& c = f.cfg;
  c.enable = !rng.chance(0.05);
  c.unit_weight = rng.chance(0.2);
  c.weight_shift = rng.uniform_as<uint8_t>(0, 15);
  if (rng.chance(0.6)) c.weight_shift = rng.uniform_as<uint8_t>(0, 3);
  c.rho_shift = rng.uniform_as<uint8_t>(0, 7);
  const int64_t range = rng.uniform(0, 3);
  if (range == 0) {
    c.theta_first = 0;
    c.theta_count = 0;      // all
  } else if (range == 1) {  // one edge per cycle: the forwarding path
    c.theta_first = rng.uniform_as<uint8_t>(0, shape.n_theta() - 1);
    c.theta_count = rng.uniform_as<uint8_t>(1, 3);
  } else {
    c.theta_first = rng.uniform_as<uint8_t>(0, 255);
    c.theta_count = rng.uniform_as<uint8_t>(0, 255);
  }
  c.width = static_cast<uint16_t>(rng.chance(0.9) ? w : rng.uniform(0, 4095));
  return f;
}

// Appends the beats of a frame: random gaps before beats (tvalid low, garbage
// data), a random read each cycle, the config moving between frames only (it
// is sampled with a frame's first beat; the test moves it one beat late too).
void append_frame(std::vector<HoughCycle>& out, Rng& rng, const HoughShape& shape, const Frame& f,
                  double gap_prob, double read_prob) {
  const uint32_t index_mask = (1u << shape.index_bits()) - 1u;
  // Each beat is held until taken: the bench's stimulus is precomputed, so
  // hold every beat for a number of cycles covering its vote (tready is
  // checked by the model: a beat not taken repeats).
  const auto cycle = [&](const EdgeBeat& b, const HoughConfig& cfg) {
    HoughCycle c;
    c.in = b;
    c.cfg = cfg;
    c.rd_en = rng.chance(read_prob);
    c.rd_index = static_cast<uint32_t>(rng.uniform(0, index_mask));
    out.push_back(c);
  };
  for (size_t i = 0; i <= f.words.size(); ++i) {
    while (gap_prob > 0.0 && rng.chance(gap_prob)) {
      EdgeBeat idle;
      idle.tdata = rng.engine()();
      idle.tlast = rng.chance(0.2);
      cycle(idle, f.cfg);
    }
    EdgeBeat b;
    b.tvalid = true;
    b.tlast = i == f.words.size();
    b.tdata = b.tlast ? f.trailer : f.words[i];
    cycle(b, f.cfg);
  }
}

// Runs stimulus built on the fly (a beat is repeated until the model takes it).
template <class Top>
void run_random(const char* name, uint64_t default_seed, const HoughShape& shape,
                uint64_t budget_cycles, uint64_t min_frames) {
  const uint64_t seed = cosim_seed(default_seed);
  Rng rng(seed);
  HoughBench<Top> bench(name, seed, shape);
  const uint64_t budget = cosim_count(budget_cycles);
  uint64_t frames = 0;
  uint64_t checked_cells = 0;
  std::vector<HoughCycle> beats;
  while (bench.sim().cycle() < budget && !bench.sim().failed()) {
    Frame f = random_frame(rng, shape);
    if (frames % 8 == 7) {  // one point 200 times at weight 480: every variant saturates
      f.points.assign(200, EdgePoint{rng.uniform_as<uint16_t>(0, 639), 479});
      f.words.clear();
      for (const EdgePoint& p : f.points) f.words.push_back(stream::edge_word(p.x, p.y));
      f.trailer = stream::trailer_word(200, 0);
      f.cfg.enable = true;
      f.cfg.unit_weight = false;
      f.cfg.weight_shift = 0;
    }
    beats.clear();
    const double gap = std::array{0.0, 0.1, 0.6}[rng.index(3)];
    const double reads = std::array{0.0, 0.3, 1.0}[rng.index(3)];
    append_frame(beats, rng, shape, f, gap, reads);
    if (rng.chance(0.02)) {
      beats[rng.index(beats.size())].reset_before = true;
    }
    bool was_reset = false;
    for (const HoughCycle& c : beats) {
      if (bench.sim().failed()) break;
      was_reset = was_reset || c.reset_before;
      // A valid beat is offered until taken (AXI: tvalid and tdata held).
      HoughCycle held = c;
      for (;;) {
        const bool taken = held.in.tvalid && bench.model().tready();
        bench.step(held);
        held.reset_before = false;
        if (!held.in.tvalid || taken || bench.sim().failed()) break;
        held.rd_en = rng.chance(0.5);
        held.rd_index = static_cast<uint32_t>(rng.uniform(0, (1u << shape.index_bits()) - 1));
      }
    }
    ++frames;
    // Sometimes: wait for the result and read cells back through the RTL
    // port, against the golden accumulator (while the next frame may already
    // vote: no wait for the clear sweep).
    if (!was_reset && f.cfg.enable && rng.chance(0.3) && !bench.sim().failed()) {
      HoughCycle idle;
      idle.cfg = f.cfg;
      while (bench.model().state() == Hough::State::kVote ||
             bench.model().state() == Hough::State::kSwap) {
        bench.step(idle);
      }
      const auto gold = golden::hough_ref(shape, f.cfg, f.points);
      for (int n = 0; n < 64 && !bench.sim().failed(); ++n) {
        // Mostly the nonzero cells.
        size_t cell = rng.index(gold.size());
        for (int tries = 0; tries < 20 && gold[cell] == 0; ++tries) cell = rng.index(gold.size());
        const auto j = static_cast<uint32_t>(cell / shape.rho_bins());
        const auto rho = static_cast<uint32_t>(cell % shape.rho_bins());
        HoughCycle rd = idle;
        rd.rd_en = true;
        rd.rd_index = (j << shape.rho_bits) | rho;
        bench.step(rd);
        const uint64_t want = std::min<uint64_t>(gold[cell], shape.acc_max());
        if (bench.sim().dut().rd_data_o != want) {
          bench.sim().fail("cell " + std::to_string(cell) + " read through the RTL port is " +
                           std::to_string(bench.sim().dut().rd_data_o) + ", golden " +
                           std::to_string(want));
        }
        ++checked_cells;
      }
    }
  }
  bench.sim().report();
  EXPECT_GT(frames, min_frames);
  EXPECT_GT(bench.ports().dones, min_frames / 2);
  EXPECT_GT(checked_cells, 4 * min_frames);
  EXPECT_GT(bench.ports().frames_dropping, 0u);
  EXPECT_GT(bench.ports().frames_saturating, 0u);
}

TEST(CosimHough, SmallRandomFramesReadsAndResets) {
  run_random<Vhough>("hough_small", 0x48A00001, kSmall, 400'000, 100);
}

TEST(CosimHough, BigRandomFramesReadsAndResets) {
  run_random<Vhough_big>("hough_big", 0x48A00002, kBig, 800'000, 25);
}

// Back to back frames with no gaps, a full readout of each published frame
// through the port racing the next frame's voting, compared with the golden.
TEST(CosimHough, BackToBackFramesFullReadoutRacingVoting) {
  const uint64_t seed = cosim_seed(0x48A00003);
  Rng rng(seed);
  HoughBench<Vhough> bench("hough_b2b", seed, kSmall);
  const uint32_t cells = 1u << kSmall.index_bits();
  std::vector<uint64_t> gold_prev;
  uint64_t read_checks = 0;
  for (int frame = 0; frame < 12 && !bench.sim().failed(); ++frame) {
    Frame f = random_frame(rng, kSmall);
    f.cfg.enable = true;
    uint32_t index = 0;
    bool read_pending = false;
    uint32_t pending_index = 0;
    const auto check_read = [&]() {
      if (!read_pending || gold_prev.empty()) return;
      const uint32_t j = pending_index >> kSmall.rho_bits;
      const uint64_t want =
          j < static_cast<uint32_t>(kSmall.n_theta())
              ? std::min<uint64_t>(
                    gold_prev[j * kSmall.rho_bins() + (pending_index & (kSmall.rho_bins() - 1))],
                    kSmall.acc_max())
              : 0u;
      if (bench.sim().dut().rd_data_o != want) {
        bench.sim().fail("previous frame's cell " + std::to_string(pending_index) + " is " +
                         std::to_string(bench.sim().dut().rd_data_o) + ", golden " +
                         std::to_string(want));
      }
      ++read_checks;
    };
    for (size_t i = 0; i <= f.words.size() && !bench.sim().failed();) {
      HoughCycle c;
      c.cfg = f.cfg;
      c.in.tvalid = true;
      c.in.tlast = i == f.words.size();
      c.in.tdata = c.in.tlast ? f.trailer : f.words[i];
      // Read the previous frame while this one votes (until its trailer).
      c.rd_en = !gold_prev.empty() && index < cells;
      c.rd_index = index;
      const bool taken = bench.model().tready();
      bench.step(c);
      read_pending = c.rd_en;
      pending_index = index;
      check_read();
      if (c.rd_en) ++index;
      if (taken) ++i;
    }
    // SWAP until the publication edge (the vote pipeline writes the frame's
    // last votes first: 5 edges after a trailer that follows the last slot,
    // fewer after a gap); the next frame's reads start after it.
    do {
      bench.step(HoughCycle{.in = {}, .cfg = f.cfg});
    } while (bench.model().state() == Hough::State::kSwap && !bench.sim().failed());
    gold_prev = golden::hough_ref(kSmall, f.cfg, f.points);
  }
  bench.sim().report();
  EXPECT_GT(read_checks, 1000u);
}

}  // namespace
}  // namespace ceilnav::testbench
