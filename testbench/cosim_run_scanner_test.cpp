// Co-simulation: rtl_model/run_scanner.sv (Verilated, FifoDepth 1024 and 8)
// against stream::RunScanner, every output port on every clock, under random
// frames, tvalid gaps, zero-blanking back-to-back frames, aborts (alone and
// combined with the next SOF), random configurations on the config port,
// random m_axis back-pressure (including long stalls), resets mid-frame and a
// real photo.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

// First: it includes verilated.h with the warnings that it trips switched off.
#include "testbench/block_bench.hpp"
#include "testbench/lut_stream.hpp"
#include "testbench/ports.hpp"

#include "Vrun_scanner.h"
#include "Vrun_scanner_d8.h"

#include "stream/beat.hpp"
#include "stream/run_scanner.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::testbench {
namespace {

using stream::LutBeat;
using stream::RunScanConfig;
using stream::RunScanner;
using stream::test::LutFrame;

static_assert(stream::unpack_run_beat(stream::pack_run_beat({2047, 7, 2046, 522240, 534512640})) ==
              stream::RunRecord{2047, 7, 2046, 522240, 534512640});

// One clock of stimulus: the s_lut beat, the config port, tready, and an
// optional reset cycle before the edge.
struct Stim {
  LutBeat beat;
  RunScanConfig cfg;
  bool tready = true;
  bool reset_before = false;
};

struct Events {
  uint64_t runs = 0;        // run beats transferred
  uint64_t trailers = 0;    // trailer beats transferred
  uint64_t aborted = 0;     // trailers with kTrailerFrameAborted
  uint64_t overflowed = 0;  // trailers with kTrailerFifoOverflow
  uint64_t done = 0;        // done pulses
  uint32_t max_occupancy = 0;
  uint64_t trailers_lost = 0;  // across resets
};

// run_scanner's ports for BlockBench (either FIFO depth); counts what the
// stream reached in `events`.
template <class Top>
struct RunScannerPorts {
  using Stim = testbench::Stim;

  void drive(Top& d, const Stim& s) {
    drive_s_lut(d, s.beat);
    d.cfg_background_level_i = s.cfg.background_level;
    d.cfg_min_run_length_i = s.cfg.min_run_length;
    d.cfg_max_runs_per_row_i = s.cfg.max_runs_per_row;
    d.m_axis_runs_tready_i = s.tready;
  }
  // The beat on the output before the edge is transferred if tready.
  void before_edge(Cosim<Top>& /*sim*/, const RunScanner& m, const Stim& s) {
    const stream::RunBeat before = m.m_axis_runs();
    if (before.tvalid && s.tready) {
      if (before.tlast) {
        ++events.trailers;
        if (before.tdata.x_start & stream::kTrailerFrameAborted) ++events.aborted;
        if (before.tdata.x_start & stream::kTrailerFifoOverflow) ++events.overflowed;
      } else {
        ++events.runs;
      }
    }
  }
  void clock(RunScanner& m, const Stim& s) {
    m.set_active_config(s.cfg);
    m.clock(s.beat, s.tready);
  }
  bool compare(Cosim<Top>& sim, const RunScanner& m) {
    auto& d = sim.dut();
    const stream::RunBeat out = m.m_axis_runs();
    // One packing for all: the model's record must survive it.
    bool ok =
        sim.check("pack_run_beat round trip",
                  stream::unpack_run_beat(stream::pack_run_beat(out.tdata)) == out.tdata, true);
    ok = check_m_axis_runs(sim, d, out) && ok;
    const stream::RunStats& st = m.last_frame_stats();
    ok = sim.check("done_o", d.done_o, m.done()) && ok;
    ok = sim.check("runs_emitted_o", d.runs_emitted_o, st.runs_emitted) && ok;
    ok = sim.check("runs_dropped_row_limit_o", d.runs_dropped_row_limit_o,
                   st.runs_dropped_row_limit) &&
         ok;
    ok =
        sim.check("runs_dropped_overflow_o", d.runs_dropped_overflow_o, st.runs_dropped_overflow) &&
        ok;
    ok = sim.check("fifo_high_water_o", d.fifo_high_water_o, st.fifo_high_water) && ok;
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
using RunScannerBench = BlockBench<Top, RunScanner, RunScannerPorts<Top>>;

// Random legal LutBeat streams with a random config port and tready.
class StimGen : public FifoStreamGen<StimGen, Stim, RunScanConfig> {
 public:
  StimGen(uint64_t seed, uint32_t max_stall_cycles)
      : FifoStreamGen(seed, LutStreamShape{}, max_stall_cycles) {
    cfg_ = random_config();
  }

  RunScanConfig random_config() {
    RunScanConfig c;
    c.background_level = rng_.chance(0.3) ? 0 : rng_.byte();
    static constexpr uint16_t kMinLen[] = {0, 1, 1, 2, 3, 5, 0xFFFF};
    c.min_run_length =
        rng_.chance(0.8) ? kMinLen[rng_.uniform(0, 6)] : rng_.uniform_as<uint16_t>(0, 40);
    static constexpr uint16_t kMaxRuns[] = {0, 1, 2, 4, 8, 8, 64, 0xFFFF};
    c.max_runs_per_row =
        rng_.chance(0.8) ? kMaxRuns[rng_.uniform(0, 7)] : rng_.uniform_as<uint16_t>(0, 20);
    return c;
  }

  // Salt-and-pepper mask: about width/4 runs per row.
  LutFrame noise_frame(uint16_t w, uint16_t h) {
    LutFrame f{w, h, {}, std::vector<uint8_t>(size_t{w} * h), std::vector<uint8_t>(size_t{w} * h)};
    for (size_t i = 0; i < f.pixels(); ++i) {
      f.remap[i] = rng_.byte();
      f.mask[i] = rng_.chance(0.5) ? 1 : 0;
    }
    return f;
  }

  // A frame with thousands of runs while the consumer stalls: fills a FIFO of
  // 1024 entries, so runs overflow and trailers get lost.
  void append_burst(std::vector<Stim>& out) {
    cfg_ = {rng_.byte(), 1, 0xFFFF};
    stall_ = true;
    append_frame(
        out, noise_frame(rng_.uniform_as<uint16_t>(100, 300), rng_.uniform_as<uint16_t>(20, 60)));
    stall_ = rng_.chance(0.5);  // sometimes the next frame's trailer is lost too
    append_frame(out,
                 noise_frame(rng_.uniform_as<uint16_t>(1, 20), rng_.uniform_as<uint16_t>(1, 4)));
    stall_ = false;
  }

  // Tiny frames (1..3 x 1..2) back to back, many aborted by the next SOF:
  // an edge can then write an aborted-frame trailer, a run and a trailer.
  std::vector<Stim> tiny_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      const auto w = rng_.uniform_as<uint16_t>(1, 3);
      const auto h = rng_.uniform_as<uint16_t>(1, 2);
      append_frame(out, stream::test::random_frame(mt_, w, h));
    }
    finish(out);
    return out;
  }
};

void print_events(const char* name, uint64_t cycles, const Events& e) {
  std::printf(
      "%s: %llu cycles compared; %llu runs, %llu trailers (%llu aborted, %llu overflow), "
      "%llu done, max occupancy %u, %llu trailers lost\n",
      name, static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(e.runs),
      static_cast<unsigned long long>(e.trailers), static_cast<unsigned long long>(e.aborted),
      static_cast<unsigned long long>(e.overflowed), static_cast<unsigned long long>(e.done),
      e.max_occupancy, static_cast<unsigned long long>(e.trailers_lost));
}

// Runs `stim` on the RTL with FIFO depth `depth` (Top) and the model of the
// same depth; prints and returns what the stream reached.
template <class Top>
Events run_bench(const char* name, uint64_t seed, uint32_t depth, const std::vector<Stim>& stim) {
  RunScannerBench<Top> bench(name, seed, depth);
  EXPECT_TRUE(bench.run(stim));
  print_events(name, bench.cycles(), bench.ports().events);
  return bench.ports().events;
}

TEST(CosimRunScanner, RandomFramesDepth1024) {
  const uint64_t seed = cosim_seed(0x72756e31);
  StimGen gen(seed, 6000);
  const auto stim = gen.random_stream(cosim_count(1500000), 0.03);
  const Events e = run_bench<Vrun_scanner>("run_scanner_d1024", seed, 1024, stim);
  EXPECT_GT(e.runs, 10000u);
  EXPECT_GT(e.aborted, 50u);
  EXPECT_GT(e.done, 200u);
  EXPECT_EQ(e.max_occupancy, 1024u);
  EXPECT_GT(e.overflowed, 5u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimRunScanner, RandomFramesDepth8BackPressure) {
  const uint64_t seed = cosim_seed(0x72756e32);
  StimGen gen(seed, 400);
  const auto stim = gen.random_stream(cosim_count(1000000), 0.01);
  const Events e = run_bench<Vrun_scanner_d8>("run_scanner_d8", seed, 8, stim);
  EXPECT_EQ(e.max_occupancy, 8u);
  EXPECT_GT(e.overflowed, 50u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimRunScanner, TinyFramesDepth8ThreeWritesPerEdge) {
  const uint64_t seed = cosim_seed(0x72756e33);
  StimGen gen(seed, 200);
  const auto stim = gen.tiny_stream(cosim_count(200000));
  const Events e = run_bench<Vrun_scanner_d8>("run_scanner_tiny_d8", seed, 8, stim);
  EXPECT_GT(e.aborted, 1000u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimRunScanner, TinyFramesDepth1024) {
  const uint64_t seed = cosim_seed(0x72756e34);
  StimGen gen(seed, 3000);
  const auto stim = gen.tiny_stream(cosim_count(150000));
  const Events e = run_bench<Vrun_scanner>("run_scanner_tiny_d1024", seed, 1024, stim);
  EXPECT_GT(e.aborted, 1000u);
}

// A real photo (building.jpg from opencv-doc), random LUT and threshold, three
// times back to back under random back-pressure, with a different config each.
TEST(CosimRunScanner, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0x72756e35);
  const auto img = stream::test::load_photo("building.jpg");
  ASSERT_TRUE(img) << "opencv-doc sample data missing";
  StimGen gen(seed, 3000);
  std::array<stream::LutEntry, 256> lut{};
  const int threshold = gen.rng().uniform_as<int>(100, 200);
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = stream::lut_entry(static_cast<uint8_t>(g), g >= threshold);
  }
  const LutFrame f = lut_frame(*img, lut);
  std::vector<Stim> stim;
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), pass == 1 ? 0.2 : 0.0);
    RunScanConfig cfg = gen.random_config();
    cfg.max_runs_per_row = pass == 0 ? 0xFFFF : cfg.max_runs_per_row;
    for (const auto& b : beats) {
      Stim s = gen.make(b);
      s.cfg = cfg;
      stim.push_back(s);
    }
  }
  gen.finish(stim);
  const Events e = run_bench<Vrun_scanner>("run_scanner_photo", seed, 1024, stim);
  EXPECT_EQ(e.done, 3u);
  EXPECT_GT(e.runs, 1000u);
}

}  // namespace
}  // namespace ceilnav::testbench
