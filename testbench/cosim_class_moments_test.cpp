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

#include <opencv2/imgcodecs.hpp>

// First: it includes verilated.h with the warnings that it trips switched off.
#include "testbench/cosim_common.hpp"

#include "Vclass_moments.h"

#include "stream/beat.hpp"
#include "stream/class_moments.hpp"
#include "stream/tests/beat_source.hpp"

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

class ClassMomentsBench {
 public:
  ClassMomentsBench(const std::string& name, uint64_t seed) : sim_(name, seed) { compare(); }

  bool step(const Stim& s) {
    if (s.reset_before) {
      sim_.reset_cycle();
      model_.reset();
      if (!compare()) return false;
    }
    auto& d = sim_.dut();
    const LutBeat& in = s.beat;
    d.s_lut_valid_i = in.pix.valid;
    d.s_lut_grey_i = in.pix.grey;
    d.s_lut_x_i = in.pix.x;
    d.s_lut_y_i = in.pix.y;
    d.s_lut_sof_i = in.pix.sof;
    d.s_lut_eol_i = in.pix.eol;
    d.s_lut_eof_i = in.pix.eof;
    d.s_lut_abort_i = in.pix.abort;
    d.s_lut_remap_i = in.remap;
    d.s_lut_mask_i = in.mask;
    d.s_lut_class_i = in.cls & 3u;
    d.win_x0_i = s.win.x0 & 0xFFFu;
    d.win_x1_i = s.win.x1 & 0xFFFu;
    d.win_y0_i = s.win.y0 & 0xFFFu;
    d.win_y1_i = s.win.y1 & 0xFFFu;
    d.eof_keep_i = s.keep;
    sim_.edge();
    model_.clock(in, s.win, s.keep);
    if (sim_.ctx().gotError()) {
      sim_.fail("RTL assertion failed");
      return false;
    }
    return compare();
  }

  bool run(const std::vector<Stim>& stim) {
    for (const Stim& s : stim) {
      if (!step(s)) return false;
    }
    return true;
  }

  uint64_t done_pulses() const { return done_pulses_; }
  uint64_t cycles() const { return sim_.cycle(); }
  const ClassMoments& model() const { return model_; }
  Cosim<Vclass_moments>& sim() { return sim_; }

 private:
  bool compare() {
    static constexpr const char* kPort[stream::kMomentCount] = {"m00_o", "m10_o", "m01_o",
                                                                "m20_o", "m11_o", "m02_o"};
    auto& d = sim_.dut();
    const auto& r = model_.results();
    bool ok = sim_.check("done_o", d.done_o, model_.done());
    for (unsigned c = 0; c < stream::kMomentClasses; ++c) {
      for (size_t k = 0; k < stream::kMomentCount; ++k) {
        const auto bits = static_cast<unsigned>(widths::kMomentBits[k]);
        uint64_t rtl = 0;
        switch (k) {
          case stream::kM00:
            rtl = slice(d.m00_o, c * bits, bits);
            break;
          case stream::kM10:
            rtl = slice(d.m10_o, c * bits, bits);
            break;
          case stream::kM01:
            rtl = slice(d.m01_o, c * bits, bits);
            break;
          case stream::kM20:
            rtl = slice(d.m20_o, c * bits, bits);
            break;
          case stream::kM11:
            rtl = slice(d.m11_o, c * bits, bits);
            break;
          default:
            rtl = slice(d.m02_o, c * bits, bits);
            break;
        }
        ok = sim_.check(kPort[k], rtl, r.cls[c][k]) && ok;
      }
    }
    if (model_.done()) ++done_pulses_;
    return ok;
  }

  Cosim<Vclass_moments> sim_;
  ClassMoments model_;
  uint64_t done_pulses_ = 0;
};

class StimGen {
 public:
  explicit StimGen(uint64_t seed) : rng_(seed), mt_(static_cast<uint32_t>(seed)) {}

  void random_size(uint16_t& w, uint16_t& h) {
    const int64_t kind = rng_.uniform(0, 999);
    if (kind < 600) {
      w = rng_.uniform_as<uint16_t>(1, 12);
      h = rng_.uniform_as<uint16_t>(1, 12);
    } else if (kind < 900) {
      w = rng_.uniform_as<uint16_t>(1, 64);
      h = rng_.uniform_as<uint16_t>(1, 48);
    } else if (kind < 995) {
      w = rng_.uniform_as<uint16_t>(1, 200);
      h = rng_.uniform_as<uint16_t>(1, 150);
    } else if (kind < 998) {  // long thin frames up to the width / height limit
      w = rng_.chance(0.5) ? rng_.uniform_as<uint16_t>(1000, 2048) : 1;
      h = w == 1 ? rng_.uniform_as<uint16_t>(1000, 2048) : rng_.uniform_as<uint16_t>(1, 3);
    } else {
      w = rng_.uniform_as<uint16_t>(320, 640);
      h = rng_.uniform_as<uint16_t>(200, 480);
    }
  }

  // Classes in runs of random length (long runs and single pixels).
  LutFrame class_frame(uint16_t w, uint16_t h) {
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

  // One frame (possibly cut short or reset) and the blanking after it.
  void append_frame(std::vector<Stim>& out, const LutFrame& f) {
    static constexpr double kGapChoices[] = {0.0, 0.0, 0.0, 0.05, 0.2, 0.6};
    const double gap = kGapChoices[rng_.uniform(0, 5)];
    const int64_t mode = rng_.uniform(0, 199);
    const auto pixels = static_cast<int64_t>(f.pixels());
    const ClassWindow win = window(f.width, f.height);
    const bool keep = rng_.chance(0.85);
    std::vector<LutBeat> beats;
    bool combine_abort_with_next_sof = false;
    size_t reset_at = SIZE_MAX;
    if (mode < 140) {
      stream::test::append_frame(beats, f, mt_, gap);
    } else if (mode < 165) {
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
    } else if (mode < 196) {
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
      beats.pop_back();
      combine_abort_with_next_sof = true;
    } else {
      stream::test::append_frame(beats, f, mt_, gap);
      reset_at = static_cast<size_t>(rng_.uniform(0, static_cast<int64_t>(beats.size()) - 1));
    }
    for (size_t i = 0; i < beats.size(); ++i) {
      Stim s{beats[i], beats[i].pix.sof ? win : garbage_window(),
             beats[i].pix.eof ? keep : rng_.chance(0.5), i == reset_at};
      if (pending_abort_ && s.beat.pix.valid) {
        s.beat.pix.abort = true;  // combined abort + SOF beat (frame_check's early SOF)
        pending_abort_ = false;
      }
      out.push_back(s);
    }
    pending_abort_ = combine_abort_with_next_sof;
    if (pending_abort_) return;
    const int64_t blank_kind = rng_.uniform(0, 9);
    const int64_t blank = blank_kind < 5   ? 0
                          : blank_kind < 8 ? rng_.uniform(1, 4)
                                           : rng_.uniform(5, 40);
    for (int64_t i = 0; i < blank; ++i) {
      Stim s;
      s.win = garbage_window();
      s.keep = rng_.chance(0.5);
      if (rng_.chance(0.1)) {
        s.beat.pix.abort = true;  // abort with no frame open
      } else if (rng_.chance(0.1)) {
        s.beat.pix.valid = true;  // pixel outside a frame, no SOF: ignored
        s.beat.pix.x = rng_.uniform_as<uint16_t>(0, 2047);
        s.beat.pix.y = rng_.uniform_as<uint16_t>(0, 2047);
        s.beat.pix.eol = rng_.chance(0.5);
        s.beat.pix.eof = s.beat.pix.eol && rng_.chance(0.5);
        s.beat.cls = rng_.uniform_as<uint8_t>(0, 3);
      }
      out.push_back(s);
    }
  }

  std::vector<Stim> random_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      uint16_t w = 0;
      uint16_t h = 0;
      random_size(w, h);
      append_frame(out, class_frame(w, h));
    }
    finish(out);
    return out;
  }

  void finish(std::vector<Stim>& out) {
    if (pending_abort_) append_frame(out, class_frame(3, 2));
    out.resize(out.size() + ClassMoments::kLatencyCycles + 4);
  }

  Rng& rng() { return rng_; }
  std::mt19937& mt() { return mt_; }

 private:
  Rng rng_;
  std::mt19937 mt_;
  bool pending_abort_ = false;
};

TEST(CosimClassMoments, RandomFramesWindowsGapsAbortsResets) {
  const uint64_t seed = cosim_seed(0x636c6d31);
  StimGen gen(seed);
  const auto stim = gen.random_stream(cosim_count(1000000));
  ClassMomentsBench bench("class_moments_random", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_GT(bench.done_pulses(), 300u);
  std::printf("class_moments random: %llu cycles compared, %llu frames done\n",
              static_cast<unsigned long long>(bench.cycles()),
              static_cast<unsigned long long>(bench.done_pulses()));
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
    const LutFrame f = gen.class_frame(w, h);
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
  EXPECT_EQ(bench.done_pulses(), kept);
  bench.sim().report();
}

// building.jpg through a class LUT (grey bands), twice, whole frame then a window.
TEST(CosimClassMoments, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0x636c6d33);
  const cv::Mat img =
      cv::imread("/usr/share/doc/opencv-doc/examples/data/building.jpg", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty()) << "opencv-doc sample data missing";
  ASSERT_TRUE(img.isContinuous());
  StimGen gen(seed);
  std::array<stream::LutEntry, 256> lut{};
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] =
        stream::lut_entry(static_cast<uint8_t>(g), false, static_cast<uint8_t>((g / 48) % 4));
  }
  const std::vector<uint8_t> grey(img.data, img.data + img.total());
  const auto f = LutFrame::from_grey(grey, static_cast<uint16_t>(img.cols),
                                     static_cast<uint16_t>(img.rows), lut);
  std::vector<Stim> stim;
  for (const ClassWindow& win : {ClassWindow{}, ClassWindow{37, 411, 20, 300}}) {
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), 0.1);
    for (const auto& b : beats) stim.push_back({b, b.pix.sof ? win : gen.garbage_window()});
  }
  gen.finish(stim);
  ClassMomentsBench bench("class_moments_photo", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_EQ(bench.done_pulses(), 2u);
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
  EXPECT_EQ(bench.done_pulses(), 1u);
  // m20 = 2048 * sum of x^2 over [0, 2048) = 5 859 767 746 560 < 2^43
  const uint64_t s2 = uint64_t{kSide - 1} * kSide * (2 * kSide - 1) / 6;
  EXPECT_EQ(bench.model().results().of(stream::kClassBar)[stream::kM20], s2 * kSide);
}

}  // namespace
}  // namespace ceilnav::testbench
