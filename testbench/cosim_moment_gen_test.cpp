// Co-simulation: rtl_model/moment_gen.sv (Verilated) against stream::MomentGen,
// every output port on every clock, under random frames, tvalid gaps,
// zero-blanking back-to-back frames, aborts (alone and combined with the next
// SOF), stray beats, resets mid-frame and a real photo.
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

#include "Vmoment_gen.h"

#include "stream/beat.hpp"
#include "stream/moment_gen.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::testbench {
namespace {

using stream::LutBeat;
using stream::MomentGen;
using stream::test::LutFrame;

// One beat of stimulus; reset_before runs a reset cycle before the beat's edge.
struct Stim {
  LutBeat beat;
  bool reset_before = false;
  bool eof_drop = false;  // eof_drop_i (the pipeline drops the frame at its EOF)
};

// moment_gen's ports for BlockBench.
struct MomentGenPorts {
  using Stim = testbench::Stim;

  void drive(Vmoment_gen& d, const Stim& s) {
    drive_s_lut(d, s.beat);
    d.eof_drop_i = s.eof_drop;
  }
  void clock(MomentGen& m, const Stim& s) { m.clock(s.beat, s.eof_drop); }
  bool compare(Cosim<Vmoment_gen>& sim, const MomentGen& m) {
    auto& d = sim.dut();
    bool ok = sim.check("done_o", d.done_o, m.done());
    ok = sim.check("combine_busy_o", d.combine_busy_o, m.combine_busy()) && ok;
    ok = sim.check("done_next_o", d.done_next_o, m.done_next()) && ok;
    ok = sim.check("overrun_count_o", d.overrun_count_o, m.overrun_count()) && ok;
    const stream::MomentWord w = m.mom_wr();
    ok = sim.check("mom_wr_valid_o", d.mom_wr_valid_o, w.valid) && ok;
    ok = sim.check("mom_wr_index_o", d.mom_wr_index_o, w.index) && ok;
    ok = sim.check("mom_wr_data_o", d.mom_wr_data_o, w.data) && ok;
    if (w.valid) ++words;
    if (m.done()) ++done_pulses;
    return ok;
  }

  uint64_t done_pulses = 0;
  uint64_t words = 0;
};

using MomentGenBench = BlockBench<Vmoment_gen, MomentGen, MomentGenPorts>;

// Random legal LutBeat streams; eof_drop on one EOF in ten.
class StimGen : public LutStreamGen<StimGen, Stim> {
 public:
  explicit StimGen(uint64_t seed) : LutStreamGen(seed, LutStreamShape{}) {}

  Stim make(const LutBeat& b) {
    Stim s{b, false};
    s.eof_drop = b.pix.eof && rng_.chance(0.1);
    return s;
  }
  Stim make_blank() {
    Stim s;
    s.beat = blank_beat();
    return s;
  }
  void begin_frame(const LutFrame& /*f*/) {}
  LutFrame frame(uint16_t w, uint16_t h) { return stream::test::random_frame(mt_, w, h); }
  void drain(std::vector<Stim>& out) {
    out.resize(out.size() + MomentGen::kCombineCycles + 16);  // let the combine finish
  }
};

TEST(CosimMomentGen, RandomFramesGapsAbortsResets) {
  const uint64_t seed = cosim_seed(0x6d6f6d31);
  StimGen gen(seed);
  const auto stim = gen.random_stream(cosim_count(1200000));
  MomentGenBench bench("moment_gen_random", seed);
  EXPECT_TRUE(bench.run(stim));
  // The stimulus must have completed frames and overrun tiny ones.
  EXPECT_GT(bench.ports().done_pulses, 200u);
  std::printf("moment_gen random: %llu cycles compared, %llu frames done, %u overruns\n",
              static_cast<unsigned long long>(bench.cycles()),
              static_cast<unsigned long long>(bench.ports().done_pulses),
              bench.model().overrun_count());
}

// Frames of 1..9 pixels at zero or little blanking: the combine is still busy
// at the next EOF, so frames are dropped and counted (overrun_count_o), and
// an EOF on the combine's done edge is accepted.
TEST(CosimMomentGen, TinyFramesBackToBackOverrun) {
  const uint64_t seed = cosim_seed(0x6d6f6d32);
  StimGen gen(seed);
  std::vector<Stim> stim;
  while (stim.size() < cosim_count(150000)) {
    const auto w = gen.rng().uniform_as<uint16_t>(1, 3);
    const auto h = gen.rng().uniform_as<uint16_t>(1, 3);
    const auto f = stream::test::random_frame(gen.mt(), w, h);
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), gen.rng().chance(0.8) ? 0.0 : 0.3);
    for (const auto& b : beats) stim.push_back({b, false});
    stim.resize(stim.size() + static_cast<size_t>(gen.rng().uniform(0, 8) / 4));
  }
  gen.finish(stim);
  MomentGenBench bench("moment_gen_tiny", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_GT(bench.model().overrun_count(), 1000u);
  EXPECT_GT(bench.ports().done_pulses, 1000u);
}

// A real photo (building.jpg from opencv-doc), random remap LUT and threshold,
// twice back to back with random gaps on the second pass.
TEST(CosimMomentGen, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0x6d6f6d33);
  const auto img = stream::test::load_photo("building.jpg");
  ASSERT_TRUE(img) << "opencv-doc sample data missing";
  StimGen gen(seed);
  std::array<stream::LutEntry, 256> lut{};
  const int threshold = gen.rng().uniform_as<int>(64, 200);
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = stream::lut_entry(gen.rng().byte(), g >= threshold);
  }
  const LutFrame f = lut_frame(*img, lut);
  std::vector<LutBeat> beats;
  stream::test::append_frame(beats, f, gen.mt(), 0.0);
  stream::test::append_frame(beats, f, gen.mt(), 0.2);
  std::vector<Stim> stim;
  for (const auto& b : beats) stim.push_back({b, false});
  gen.finish(stim);
  MomentGenBench bench("moment_gen_photo", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_EQ(bench.ports().done_pulses, 2u);
}

// The largest frame (2048 x 2048) with every pixel 255 and mask 1: the
// moments reach the derived port widths (m20 = 255 * 5 859 767 746 560).
// 4.2 M cycles, about 3 s.
TEST(CosimMomentGen, LargestFrameAll255) {
  const uint64_t seed = cosim_seed(0x6d6f6d34);
  MomentGenBench bench("moment_gen_largest", seed);
  constexpr uint32_t kSide = stream::kMaxWidth;
  for (uint32_t y = 0; y < kSide; ++y) {
    for (uint32_t x = 0; x < kSide; ++x) {
      Stim s;
      s.beat.pix.valid = true;
      s.beat.pix.grey = 255;
      s.beat.pix.x = static_cast<uint16_t>(x);
      s.beat.pix.y = static_cast<uint16_t>(y);
      s.beat.pix.sof = x == 0 && y == 0;
      s.beat.pix.eol = x + 1 == kSide;
      s.beat.pix.eof = s.beat.pix.eol && y + 1 == kSide;
      s.beat.remap = 255;
      s.beat.mask = true;
      ASSERT_TRUE(bench.step(s));
    }
  }
  for (int i = 0; i < MomentGen::kCombineCycles + 2; ++i) ASSERT_TRUE(bench.step(Stim{}));
  EXPECT_EQ(bench.ports().done_pulses, 1u);
  EXPECT_EQ(bench.model().results().grey[stream::kM20], 255ull * 5859767746560ull);
}

}  // namespace
}  // namespace ceilnav::testbench
