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

#include <opencv2/imgcodecs.hpp>

// First: it includes verilated.h with the warnings that it trips switched off.
#include "testbench/cosim_common.hpp"

#include "Vmoment_gen.h"

#include "stream/beat.hpp"
#include "stream/moment_gen.hpp"
#include "stream/tests/beat_source.hpp"

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

class MomentGenBench {
 public:
  MomentGenBench(const std::string& name, uint64_t seed) : sim_(name, seed) { compare(); }

  // One clock with `in` on the s_lut port; false after the first mismatch.
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
    d.eof_drop_i = s.eof_drop;
    sim_.edge();
    model_.clock(in, s.eof_drop);
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

  uint64_t cycles() const { return sim_.cycle(); }
  uint64_t done_pulses() const { return done_pulses_; }
  uint64_t result_words() const { return words_; }
  const MomentGen& model() const { return model_; }
  bool failed() const { return sim_.failed(); }

 private:
  bool compare() {
    auto& d = sim_.dut();
    bool ok = sim_.check("done_o", d.done_o, model_.done());
    ok = sim_.check("combine_busy_o", d.combine_busy_o, model_.combine_busy()) && ok;
    ok = sim_.check("done_next_o", d.done_next_o, model_.done_next()) && ok;
    ok = sim_.check("overrun_count_o", d.overrun_count_o, model_.overrun_count()) && ok;
    const stream::MomentWord w = model_.mom_wr();
    ok = sim_.check("mom_wr_valid_o", d.mom_wr_valid_o, w.valid) && ok;
    ok = sim_.check("mom_wr_index_o", d.mom_wr_index_o, w.index) && ok;
    ok = sim_.check("mom_wr_data_o", d.mom_wr_data_o, w.data) && ok;
    if (w.valid) ++words_;
    if (model_.done()) ++done_pulses_;
    return ok;
  }

  Cosim<Vmoment_gen> sim_;
  MomentGen model_;
  uint64_t done_pulses_ = 0;
  uint64_t words_ = 0;
};

// Random legal LutBeat streams (what thresh_lut delivers after frame_check).
class StimGen {
 public:
  explicit StimGen(uint64_t seed) : rng_(seed), mt_(static_cast<uint32_t>(seed)) {}

  // Mostly small frames; now and then a large one.
  void random_size(uint16_t& w, uint16_t& h) {
    const int64_t kind = rng_.uniform(0, 999);
    if (kind < 600) {
      w = rng_.uniform_as<uint16_t>(1, 12);
      h = rng_.uniform_as<uint16_t>(1, 12);
    } else if (kind < 900) {
      w = rng_.uniform_as<uint16_t>(1, 64);
      h = rng_.uniform_as<uint16_t>(1, 48);
    } else if (kind < 998) {
      w = rng_.uniform_as<uint16_t>(1, 200);
      h = rng_.uniform_as<uint16_t>(1, 150);
    } else {
      w = rng_.uniform_as<uint16_t>(320, 640);
      h = rng_.uniform_as<uint16_t>(200, 480);
    }
  }

  // Appends one frame (possibly cut short) and the blanking after it.
  void append_frame(std::vector<Stim>& out, const LutFrame& f) {
    static constexpr double kGapChoices[] = {0.0, 0.0, 0.0, 0.05, 0.2, 0.6};
    const double gap = kGapChoices[rng_.uniform(0, 5)];
    const int64_t mode = rng_.uniform(0, 199);
    const auto pixels = static_cast<int64_t>(f.pixels());
    std::vector<LutBeat> beats;
    bool combine_abort_with_next_sof = false;
    size_t reset_at = SIZE_MAX;
    if (mode < 140) {
      stream::test::append_frame(beats, f, mt_, gap);
    } else if (mode < 165) {  // abort beat (valid = 0) after some pixels
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
    } else if (mode < 196) {  // early SOF: the next frame's SOF beat carries the abort
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
      beats.pop_back();
      combine_abort_with_next_sof = true;
    } else {  // reset somewhere in the frame
      stream::test::append_frame(beats, f, mt_, gap);
      reset_at = static_cast<size_t>(rng_.uniform(0, static_cast<int64_t>(beats.size()) - 1));
    }
    for (size_t i = 0; i < beats.size(); ++i) {
      Stim s{beats[i], false};
      if (pending_abort_ && s.beat.pix.valid) {
        s.beat.pix.abort = true;  // combined abort + SOF beat (frame_check's early SOF)
        pending_abort_ = false;
      }
      s.reset_before = i == reset_at;
      s.eof_drop = s.beat.pix.eof && rng_.chance(0.1);
      out.push_back(s);
    }
    pending_abort_ = combine_abort_with_next_sof;
    if (pending_abort_) return;  // zero blanking: the next frame's SOF aborts this one
    // Blanking: none (back to back), short, or long; sometimes stray beats
    // that a closed frame must ignore.
    const int64_t blank_kind = rng_.uniform(0, 9);
    const int64_t blank = blank_kind < 4   ? 0
                          : blank_kind < 8 ? rng_.uniform(1, 10)
                                           : rng_.uniform(10, 60);
    for (int64_t i = 0; i < blank; ++i) {
      Stim s;
      if (rng_.chance(0.1)) {
        s.beat.pix.abort = true;  // abort with no frame open
      } else if (rng_.chance(0.1)) {
        s.beat.pix.valid = true;  // pixel outside a frame, no SOF
        s.beat.pix.x = rng_.uniform_as<uint16_t>(0, 2047);
        s.beat.pix.y = rng_.uniform_as<uint16_t>(0, 2047);
        s.beat.pix.eol = rng_.chance(0.5);
        s.beat.pix.eof = s.beat.pix.eol && rng_.chance(0.5);
        s.beat.remap = rng_.byte();
        s.beat.mask = rng_.chance(0.5);
      }
      out.push_back(s);
    }
  }

  // Random frames until at least `cycles` beats.
  std::vector<Stim> random_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      uint16_t w = 0;
      uint16_t h = 0;
      random_size(w, h);
      append_frame(out, stream::test::random_frame(mt_, w, h));
    }
    finish(out);
    return out;
  }

  // A closing frame, so that a pending combined abort has its SOF.
  void finish(std::vector<Stim>& out) {
    if (pending_abort_) {
      append_frame(out, stream::test::random_frame(mt_, 3, 2));
    }
    out.resize(out.size() + MomentGen::kCombineCycles + 16);  // let the combine finish
  }

  Rng& rng() { return rng_; }
  std::mt19937& mt() { return mt_; }

 private:
  Rng rng_;
  std::mt19937 mt_;
  bool pending_abort_ = false;
};

TEST(CosimMomentGen, RandomFramesGapsAbortsResets) {
  const uint64_t seed = cosim_seed(0x6d6f6d31);
  StimGen gen(seed);
  const auto stim = gen.random_stream(cosim_count(1200000));
  MomentGenBench bench("moment_gen_random", seed);
  EXPECT_TRUE(bench.run(stim));
  // The stimulus must have completed frames and overrun tiny ones.
  EXPECT_GT(bench.done_pulses(), 200u);
  std::printf("moment_gen random: %llu cycles compared, %llu frames done, %u overruns\n",
              static_cast<unsigned long long>(bench.cycles()),
              static_cast<unsigned long long>(bench.done_pulses()), bench.model().overrun_count());
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
  EXPECT_GT(bench.done_pulses(), 1000u);
}

// A real photo (building.jpg from opencv-doc), random remap LUT and threshold,
// twice back to back with random gaps on the second pass.
TEST(CosimMomentGen, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0x6d6f6d33);
  const cv::Mat img =
      cv::imread("/usr/share/doc/opencv-doc/examples/data/building.jpg", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty()) << "opencv-doc sample data missing";
  ASSERT_TRUE(img.isContinuous());
  StimGen gen(seed);
  std::array<stream::LutEntry, 256> lut{};
  const int threshold = gen.rng().uniform_as<int>(64, 200);
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = stream::lut_entry(gen.rng().byte(), g >= threshold);
  }
  const std::vector<uint8_t> grey(img.data, img.data + img.total());
  const auto f = LutFrame::from_grey(grey, static_cast<uint16_t>(img.cols),
                                     static_cast<uint16_t>(img.rows), lut);
  std::vector<LutBeat> beats;
  stream::test::append_frame(beats, f, gen.mt(), 0.0);
  stream::test::append_frame(beats, f, gen.mt(), 0.2);
  std::vector<Stim> stim;
  for (const auto& b : beats) stim.push_back({b, false});
  gen.finish(stim);
  MomentGenBench bench("moment_gen_photo", seed);
  EXPECT_TRUE(bench.run(stim));
  EXPECT_EQ(bench.done_pulses(), 2u);
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
  EXPECT_EQ(bench.done_pulses(), 1u);
  EXPECT_EQ(bench.model().results().grey[stream::kM20], 255ull * 5859767746560ull);
}

}  // namespace
}  // namespace ceilnav::testbench
