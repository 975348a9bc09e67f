// Co-simulation: rtl_model/class_moments.sv (Verilated) against
// stream::ClassMoments, every output port on every clock, under random class
// frames, random windows (garbage on the window ports outside SOF), random
// eof_keep, tvalid gaps, zero-blanking back-to-back frames, aborts (alone and
// combined with the next SOF), stray beats, resets mid-frame, a real photo
// through a class LUT and the largest frame.
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

#include "Vclass_moments.h"

#include "stream/beat.hpp"
#include "stream/class_moments.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::testbench {
namespace {

using stream::ClassMoments;
using stream::ClassWindow;
using stream::LutBeat;
using stream::test::LutFrame;
namespace widths = stream::class_moments_widths;

struct Stim {
  LutBeat beat;
  ClassWindow win;
  bool keep = true;
  bool reset_before = false;
};

// Bits [lsb, lsb + bits) of a Verilated wide port (VlWide, 32-bit words).
template <class V>
uint64_t slice(const V& v, unsigned lsb, unsigned bits) {
  uint64_t r = 0;
  for (unsigned i = 0; i < bits; ++i) {
    const unsigned b = lsb + i;
    r |= uint64_t{(v[b / 32] >> (b % 32)) & 1u} << i;
  }
  return r;
}

// class_moments's ports for BlockBench.
struct ClassMomentsPorts {
  using Stim = testbench::Stim;

  void drive(Vclass_moments& d, const Stim& s) {
    drive_s_lut(d, s.beat);
    d.win_x0_i = s.win.x0 & 0xFFFu;
    d.win_x1_i = s.win.x1 & 0xFFFu;
    d.win_y0_i = s.win.y0 & 0xFFFu;
    d.win_y1_i = s.win.y1 & 0xFFFu;
    d.eof_keep_i = s.keep;
  }
  void clock(ClassMoments& m, const Stim& s) { m.clock(s.beat, s.win, s.keep); }
  // Each moment port holds the four classes side by side (class c at bits
  // [c * bits, (c + 1) * bits)).
  bool compare(Cosim<Vclass_moments>& sim, const ClassMoments& m) {
    static constexpr const char* kPort[stream::kMomentCount] = {"m00_o", "m10_o", "m01_o",
                                                                "m20_o", "m11_o", "m02_o"};
    auto& d = sim.dut();
    const auto& r = m.results();
    const auto moment_slice = [&d](size_t k, unsigned lsb, unsigned bits) {
      switch (k) {
        case stream::kM00:
          return slice(d.m00_o, lsb, bits);
        case stream::kM10:
          return slice(d.m10_o, lsb, bits);
        case stream::kM01:
          return slice(d.m01_o, lsb, bits);
        case stream::kM20:
          return slice(d.m20_o, lsb, bits);
        case stream::kM11:
          return slice(d.m11_o, lsb, bits);
        default:
          return slice(d.m02_o, lsb, bits);
      }
    };
    bool ok = sim.check("done_o", d.done_o, m.done());
    for (unsigned c = 0; c < stream::kMomentClasses; ++c) {
      for (size_t k = 0; k < stream::kMomentCount; ++k) {
        const auto bits = static_cast<unsigned>(widths::kMomentBits[k]);
        ok = sim.check(kPort[k], moment_slice(k, c * bits, bits), r.cls[c][k]) && ok;
      }
    }
    if (m.done()) ++done_pulses;
    return ok;
  }

  uint64_t done_pulses = 0;
};

using ClassMomentsBench = BlockBench<Vclass_moments, ClassMoments, ClassMomentsPorts>;

// Random LutBeat streams of class frames, with a random window at each SOF
// (garbage on the window ports elsewhere) and random eof_keep.
class StimGen : public LutStreamGen<StimGen, Stim> {
 public:
  explicit StimGen(uint64_t seed)
      : LutStreamGen(seed, LutStreamShape{true, 5, 1, 4, 5, 40, true}) {}

  // Classes in runs of random length (long runs and single pixels).
  LutFrame frame(uint16_t w, uint16_t h) {
    LutFrame f = stream::test::random_frame(mt_, w, h);
    f.cls.resize(f.pixels());
    uint8_t c = 0;
    int64_t left = 0;
    for (auto& v : f.cls) {
      if (left-- <= 0) {
        c = rng_.uniform_as<uint8_t>(0, 3);
        left = rng_.uniform(0, 30);
      }
      v = c;
    }
    return f;
  }

  ClassWindow window(uint16_t w, uint16_t h) {
    ClassWindow win;
    auto pick = [&](uint16_t n, uint16_t& lo, uint16_t& hi) {
      switch (rng_.uniform(0, 7)) {
        case 0:
          lo = 0;
          hi = 2048;
          break;
        case 1:  // empty
          lo = hi = rng_.uniform_as<uint16_t>(0, n + 1);
          break;
        case 2:  // reversed
          lo = rng_.uniform_as<uint16_t>(1, n + 1);
          hi = static_cast<uint16_t>(lo - 1);
          break;
        case 3:  // last line / column
          lo = static_cast<uint16_t>(n - 1);
          hi = n;
          break;
        case 4:  // past the frame edge, up to the 12-bit maximum
          lo = rng_.uniform_as<uint16_t>(0, n);
          hi = 4095;
          break;
        default:
          lo = rng_.uniform_as<uint16_t>(0, n);
          hi = rng_.uniform_as<uint16_t>(lo, n + 1);
      }
    };
    pick(w, win.x0, win.x1);
    pick(h, win.y0, win.y1);
    return win;
  }

  ClassWindow garbage_window() {
    return {rng_.uniform_as<uint16_t>(0, 4095), rng_.uniform_as<uint16_t>(0, 4095),
            rng_.uniform_as<uint16_t>(0, 4095), rng_.uniform_as<uint16_t>(0, 4095)};
  }

  void begin_frame(const LutFrame& f) {
    win_ = window(f.width, f.height);
    keep_ = rng_.chance(0.85);
  }
  Stim make(const LutBeat& b) {
    return {b, b.pix.sof ? win_ : garbage_window(), b.pix.eof ? keep_ : rng_.chance(0.5), false};
  }
  Stim make_blank() {
    Stim s;
    s.win = garbage_window();
    s.keep = rng_.chance(0.5);
    s.beat = blank_beat();
    return s;
  }
  void drain(std::vector<Stim>& out) { out.resize(out.size() + ClassMoments::kLatencyCycles + 4); }

 private:
  ClassWindow win_;
  bool keep_ = true;
};

TEST(CosimClassMoments, RandomFramesWindowsGapsAbortsResets) {
  const uint64_t seed = cosim_seed(0x636c6d31);
  StimGen gen(seed);
  const auto stim = gen.random_stream(cosim_count(1000000));
  ClassMomentsBench bench("class_moments_random", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_GT(bench.ports().done_pulses, 300u);
  std::printf("class_moments random: %llu cycles compared, %llu frames done\n",
              static_cast<unsigned long long>(bench.cycles()),
              static_cast<unsigned long long>(bench.ports().done_pulses));
  bench.sim().report();
}

// 1x1 .. 3x3 frames back to back with zero blanking: every kept frame is shown.
TEST(CosimClassMoments, TinyFramesBackToBack) {
  const uint64_t seed = cosim_seed(0x636c6d32);
  StimGen gen(seed);
  std::vector<Stim> stim;
  uint64_t kept = 0;
  while (stim.size() < cosim_count(100000)) {
    const auto w = gen.rng().uniform_as<uint16_t>(1, 3);
    const auto h = gen.rng().uniform_as<uint16_t>(1, 3);
    const LutFrame f = gen.frame(w, h);
    const ClassWindow win = gen.window(w, h);
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), gen.rng().chance(0.8) ? 0.0 : 0.3);
    const bool keep = gen.rng().chance(0.9);
    for (const auto& b : beats) {
      stim.push_back({b, b.pix.sof ? win : gen.garbage_window(), b.pix.eof ? keep : false, false});
    }
    kept += keep ? 1 : 0;
  }
  gen.finish(stim);
  ClassMomentsBench bench("class_moments_tiny", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_EQ(bench.ports().done_pulses, kept);
  bench.sim().report();
}

// building.jpg through a class LUT (grey bands), twice, whole frame then a window.
TEST(CosimClassMoments, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0x636c6d33);
  const auto img = stream::test::load_photo("building.jpg");
  ASSERT_TRUE(img) << "opencv-doc sample data missing";
  StimGen gen(seed);
  std::array<stream::LutEntry, 256> lut{};
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] =
        stream::lut_entry(static_cast<uint8_t>(g), false, static_cast<uint8_t>((g / 48) % 4));
  }
  const LutFrame f = lut_frame(*img, lut);
  std::vector<Stim> stim;
  for (const ClassWindow& win : {ClassWindow{}, ClassWindow{37, 411, 20, 300}}) {
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), 0.1);
    for (const auto& b : beats) stim.push_back({b, b.pix.sof ? win : gen.garbage_window()});
  }
  gen.finish(stim);
  ClassMomentsBench bench("class_moments_photo", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_EQ(bench.ports().done_pulses, 2u);
  const stream::ClassMomentResults fast =
      ClassMoments::frame(f.cls.data(), f.width, f.height, f.width, ClassWindow{37, 411, 20, 300});
  EXPECT_EQ(bench.model().results(), fast);
}

// 2048 x 2048, every pixel class 3: the bar's moments reach the port widths.
TEST(CosimClassMoments, LargestFrameAllBar) {
  const uint64_t seed = cosim_seed(0x636c6d34);
  ClassMomentsBench bench("class_moments_largest", seed);
  constexpr uint32_t kSide = stream::kMaxWidth;
  for (uint32_t y = 0; y < kSide; ++y) {
    for (uint32_t x = 0; x < kSide; ++x) {
      Stim s;
      s.beat.pix.valid = true;
      s.beat.pix.x = static_cast<uint16_t>(x);
      s.beat.pix.y = static_cast<uint16_t>(y);
      s.beat.pix.sof = x == 0 && y == 0;
      s.beat.pix.eol = x + 1 == kSide;
      s.beat.pix.eof = s.beat.pix.eol && y + 1 == kSide;
      s.beat.cls = stream::kClassBar;
      ASSERT_TRUE(bench.step(s));
    }
  }
  for (int i = 0; i < ClassMoments::kLatencyCycles + 2; ++i) ASSERT_TRUE(bench.step(Stim{}));
  EXPECT_EQ(bench.ports().done_pulses, 1u);
  // m20 = 2048 * sum of x^2 over [0, 2048) = 5 859 767 746 560 < 2^43
  const uint64_t s2 = uint64_t{kSide - 1} * kSide * (2 * kSide - 1) / 6;
  EXPECT_EQ(bench.model().results().of(stream::kClassBar)[stream::kM20], s2 * kSide);
}

}  // namespace
}  // namespace ceilnav::testbench
