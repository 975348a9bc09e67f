// moment_gen: clocked == fast == golden (cv::moments), exactly.
#include "stream/moment_gen.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "golden/moment_gen_ref.hpp"
#include "stream/tests/beat_source.hpp"

namespace ceilnav::stream {
namespace {

using test::LutFrame;
__extension__ typedef unsigned __int128 u128;  // exact closed forms

cv::Mat plane_mat(const std::vector<uint8_t>& v, const LutFrame& f) {
  return cv::Mat(f.height, f.width, CV_8UC1, const_cast<uint8_t*>(v.data())).clone();
}

MomentResults golden(const LutFrame& f) {
  return golden::moments_ref(plane_mat(f.remap, f), plane_mat(f.mask, f));
}

MomentResults fast(const LutFrame& f) {
  MomentGen::FrameSums sums;
  for (uint32_t y = 0; y < f.height; ++y) {
    MomentGen::accumulate_row(sums, y, f.remap_row(y), f.mask_row(y), f.width);
  }
  return MomentGen::finish(sums);
}

struct DonePulse {
  size_t cycle;  // index of the beat whose clock edge raised done
  MomentResults results;
};

// Clocks every beat, then `tail` idle cycles; records every done pulse.
std::vector<DonePulse> run_clocked(MomentGen& gen, const std::vector<LutBeat>& beats,
                                   size_t tail = MomentGen::kCombineCycles + 4) {
  std::vector<DonePulse> pulses;
  const LutBeat idle{};
  for (size_t i = 0; i < beats.size() + tail; ++i) {
    gen.clock(i < beats.size() ? beats[i] : idle);
    if (gen.done()) pulses.push_back({i, gen.results()});
  }
  return pulses;
}

std::vector<size_t> eof_cycles(const std::vector<LutBeat>& beats) {
  std::vector<size_t> c;
  for (size_t i = 0; i < beats.size(); ++i) {
    if (beats[i].pix.valid && beats[i].pix.eof) c.push_back(i);
  }
  return c;
}

TEST(MomentGen, WidthsCoverTheLargestFrame) {
  using namespace moment_gen_widths;
  // Brute force over a 2048 x 2048 frame with every pixel 1: the row and frame
  // cascade weights (u = W - x, v = H - y) and the moment weights x^a y^b.
  const auto tri = [](u128 n) { return n * (n + 1) / 2; };
  u128 row[kRowCount] = {};
  for (uint64_t x = 0; x < kW; ++x) {
    const u128 u = kW - x;
    row[0] += 1;
    row[1] += u;
    row[2] += tri(u);
  }
  u128 frame[kMomentCount] = {};
  u128 mom[kMomentCount] = {};
  for (uint64_t y = 0; y < kH; ++y) {
    const u128 v = kH - y;
    for (uint64_t x = 0; x < kW; ++x) {
      const u128 u = kW - x;
      frame[kM00] += 1;
      frame[kM10] += u;
      frame[kM01] += v;
      frame[kM20] += tri(u);
      frame[kM11] += u * v;
      frame[kM02] += tri(v);
      mom[kM00] += 1;
      mom[kM10] += x;
      mom[kM01] += y;
      mom[kM20] += u128{x} * x;
      mom[kM11] += u128{x} * y;
      mom[kM02] += u128{y} * y;
    }
  }
  // Width n is tight for s: s < 2^n and s >= 2^(n-1).
  const auto tight = [](u128 s, int n) { return s < (u128{1} << n) && s >= (u128{1} << (n - 1)); };
  for (size_t k = 0; k < kRowCount; ++k) {
    EXPECT_EQ(row[k], kRowWeightMax[k]) << k;
    EXPECT_TRUE(tight(kGreyMax * row[k], kGreyRowBits[k])) << k;
    EXPECT_TRUE(tight(row[k], kMaskRowBits[k])) << k;
  }
  for (size_t k = 0; k < kMomentCount; ++k) {
    EXPECT_EQ(frame[k], kFrameWeightMax[k]) << k;
    EXPECT_EQ(mom[k], kMomentWeightMax[k]) << k;
    EXPECT_TRUE(tight(kGreyMax * frame[k], kGreyFrameBits[k])) << k;
    EXPECT_TRUE(tight(frame[k], kMaskFrameBits[k])) << k;
    EXPECT_TRUE(tight(kGreyMax * mom[k], kGreyMomentBits[k])) << k;
    EXPECT_TRUE(tight(mom[k], kMaskMomentBits[k])) << k;
    EXPECT_LE(kGreyWorkBits[k], kGreyPassBits);
    EXPECT_LE(kMaskWorkBits[k], kMaskPassBits);
  }
  // The accumulators grow with every pixel value, so all-255 is the worst
  // case; the widest row and frame sums stay below 2^64.
  EXPECT_LT(kGreyMax * frame[kM11], u128{1} << 63);
  // W, H are 1 .. 2048: 12 bits.
  EXPECT_EQ(uint64_t{1} << (kDimBits - 1), kW);
}

TEST(MomentGen, RandomSizesWithGapsClockedFastGolden) {
  std::mt19937 rng(20240611);
  std::vector<std::pair<uint16_t, uint16_t>> sizes = {{1, 1},   {1, 37}, {53, 1},    {1, 480},
                                                      {640, 1}, {2, 2},  {640, 480}, {3, 1}};
  std::uniform_int_distribution<int> small(1, 96);
  std::uniform_int_distribution<int> big_w(1, 640);
  std::uniform_int_distribution<int> big_h(1, 480);
  for (int i = 0; i < 30; ++i) {
    sizes.emplace_back(small(rng), small(rng));
  }
  for (int i = 0; i < 4; ++i) sizes.emplace_back(big_w(rng), big_h(rng));

  MomentGen gen;
  std::vector<LutBeat> beats;
  std::vector<MomentResults> expected;
  std::uniform_real_distribution<double> gap_p(0.0, 0.5);
  for (const auto& [w, h] : sizes) {
    const LutFrame f = test::random_frame(rng, w, h);
    const MomentResults g = golden(f);
    ASSERT_EQ(fast(f), g) << w << "x" << h;
    expected.push_back(g);
    test::append_frame(beats, f, rng, gap_p(rng));
    test::append_idle(beats, MomentGen::kCombineCycles);  // tiny frames: no overrun here
  }
  const auto pulses = run_clocked(gen, beats);
  ASSERT_EQ(pulses.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(pulses[i].results, expected[i]) << "frame " << i;
  }
  EXPECT_EQ(gen.overrun_count(), 0u);
}

TEST(MomentGen, DoneIsOneCyclePulseCombineCyclesAfterEof) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> dim(1, 12);
  std::uniform_int_distribution<size_t> extra(0, 20);
  MomentGen gen;
  std::vector<LutBeat> beats;
  for (int i = 0; i < 8; ++i) {
    test::append_frame(
        beats,
        test::random_frame(rng, static_cast<uint16_t>(dim(rng)), static_cast<uint16_t>(dim(rng))),
        rng, 0.3);
    test::append_idle(beats, MomentGen::kCombineCycles + extra(rng));
  }
  const auto eofs = eof_cycles(beats);
  size_t busy_cycles = 0;
  std::vector<DonePulse> pulses;
  for (size_t i = 0; i < beats.size(); ++i) {
    gen.clock(beats[i]);
    if (gen.done()) pulses.push_back({i, gen.results()});
    if (gen.combine_busy()) ++busy_cycles;
  }
  ASSERT_EQ(pulses.size(), eofs.size());
  for (size_t i = 0; i < eofs.size(); ++i) {
    EXPECT_EQ(pulses[i].cycle, eofs[i] + MomentGen::kCombineCycles);
  }
  // busy from the EOF edge up to the done edge: kCombineCycles cycles a frame.
  EXPECT_EQ(busy_cycles, eofs.size() * MomentGen::kCombineCycles);
  // The pulse lasts one cycle: consecutive pulses are at least a frame apart.
  for (size_t i = 1; i < pulses.size(); ++i) EXPECT_GT(pulses[i].cycle, pulses[i - 1].cycle + 1);
}

TEST(MomentGen, RealPhotosWithRandomLut) {
  const std::filesystem::path dir = "/usr/share/doc/opencv-doc/examples/data";
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> byte(0, 255);
  int tested = 0;
  for (const char* name : {"building.jpg", "baboon.jpg", "fruits.jpg"}) {
    const cv::Mat img = cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty()) << name;
    ASSERT_TRUE(img.isContinuous());
    std::array<LutEntry, 256> lut{};
    const int threshold = byte(rng);
    for (int g = 0; g < 256; ++g) {
      lut[static_cast<size_t>(g)] = lut_entry(static_cast<uint8_t>(byte(rng)), g >= threshold);
    }
    const LutFrame f =
        LutFrame::from_grey(std::vector<uint8_t>(img.datastart, img.dataend),
                            static_cast<uint16_t>(img.cols), static_cast<uint16_t>(img.rows), lut);
    const MomentResults g = golden(f);
    EXPECT_EQ(fast(f), g) << name;
    std::vector<LutBeat> beats;
    test::append_frame(beats, f, rng, 0.1);
    MomentGen gen;
    const auto pulses = run_clocked(gen, beats);
    ASSERT_EQ(pulses.size(), 1u) << name;
    EXPECT_EQ(pulses[0].results, g) << name;
    ++tested;
  }
  EXPECT_EQ(tested, 3);
}

TEST(MomentGen, LargestFrameAll255MatchesClosedForm) {
  const uint16_t n = kMaxWidth;
  LutFrame f;
  f.width = n;
  f.height = n;
  f.remap.assign(f.pixels(), 255);
  f.mask.assign(f.pixels(), 1);
  // Closed forms in 128 bits: S1 = sum_{0}^{n-1} v, S2 = sum v^2.
  const u128 s0 = n;
  const u128 s1 = u128{n} * (n - 1) / 2;
  const u128 s2 = u128{n - 1} * n * (2 * u128{n} - 1) / 6;
  const u128 mask_ref[kMomentCount] = {s0 * s0, s1 * s0, s0 * s1, s2 * s0, s1 * s1, s0 * s2};
  MomentResults exact;
  for (size_t k = 0; k < kMomentCount; ++k) {
    exact.mask[k] = static_cast<uint64_t>(mask_ref[k]);
    exact.grey[k] = static_cast<uint64_t>(255 * mask_ref[k]);
    ASSERT_LT(255 * mask_ref[k], u128{1} << 53) << "double would not be exact";
  }
  EXPECT_EQ(fast(f), exact);
  // cv::moments stays exact here: every sum is an integer below 2^53.
  EXPECT_EQ(golden(f), exact);
  std::vector<LutBeat> beats;
  std::mt19937 rng(1);
  test::append_frame(beats, f, rng, 0.0);
  MomentGen gen;
  const auto pulses = run_clocked(gen, beats);
  ASSERT_EQ(pulses.size(), 1u);
  EXPECT_EQ(pulses[0].results, exact);
}

TEST(MomentGen, BackToBackZeroBlankingWithAborts) {
  std::mt19937 rng(31337);
  std::uniform_int_distribution<int> dim(1, 40);
  std::bernoulli_distribution abort_frame(0.3);
  MomentGen gen;
  std::vector<LutBeat> beats;
  std::vector<MomentResults> expected;
  int aborted = 0;
  for (int i = 0; i < 60; ++i) {
    uint16_t w = static_cast<uint16_t>(dim(rng));
    uint16_t h = static_cast<uint16_t>(dim(rng));
    if (size_t{w} * h < MomentGen::kCombineCycles)
      h = MomentGen::kCombineCycles;  // see overrun test
    const LutFrame f = test::random_frame(rng, w, h);
    if (abort_frame(rng)) {
      std::uniform_int_distribution<int64_t> at(0, static_cast<int64_t>(f.pixels()) - 1);
      test::append_frame(beats, f, rng, 0.0, at(rng));
      ++aborted;
    } else {
      test::append_frame(beats, f, rng, 0.0);
      expected.push_back(golden(f));
    }
  }
  ASSERT_GT(aborted, 5);
  const auto pulses = run_clocked(gen, beats);
  ASSERT_EQ(pulses.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(pulses[i].results, expected[i]) << "good frame " << i;
  }
  EXPECT_EQ(gen.overrun_count(), 0u);
}

TEST(MomentGen, TinyFramesBackToBackOverrunIsCounted) {
  // 1x1 and 1x3 frames with no blanking end faster than the combine; a frame
  // that ends while the combine is busy (except on its last step) is dropped.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> len(1, 3);
  MomentGen gen;
  std::vector<LutBeat> beats;
  std::vector<MomentResults> frame_results;
  for (int i = 0; i < 50; ++i) {
    const LutFrame f = test::random_frame(rng, 1, static_cast<uint16_t>(len(rng)));
    frame_results.push_back(golden(f));
    test::append_frame(beats, f, rng, 0.0);
  }
  // Expected acceptance: an EOF is taken if no combine started fewer than
  // kCombineCycles cycles before.
  const auto eofs = eof_cycles(beats);
  std::vector<MomentResults> expected;
  uint32_t dropped = 0;
  bool have_last = false;
  size_t last = 0;
  for (size_t i = 0; i < eofs.size(); ++i) {
    if (have_last && eofs[i] - last < MomentGen::kCombineCycles) {
      ++dropped;
      continue;
    }
    have_last = true;
    last = eofs[i];
    expected.push_back(frame_results[i]);
  }
  ASSERT_GT(dropped, 10u);
  const auto pulses = run_clocked(gen, beats);
  EXPECT_EQ(gen.overrun_count(), dropped);
  ASSERT_EQ(pulses.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(pulses[i].results, expected[i]) << i;
}

// eof_drop high with an EOF: no combine, no done, counted as an overrun; the
// combine stays free, so the next frame (even right behind) is taken.
TEST(MomentGen, DroppedEofIsCountedAndNotCombined) {
  std::mt19937 rng(13);
  const LutFrame a = test::random_frame(rng, 9, 4);
  const LutFrame b = test::random_frame(rng, 5, 3);
  const LutFrame c = test::random_frame(rng, 7, 6);
  std::vector<LutBeat> beats;
  test::append_frame(beats, a, rng, 0.1);
  test::append_idle(beats, MomentGen::kCombineCycles);
  test::append_frame(beats, b, rng, 0.0);
  const size_t b_eof = beats.size() - 1;
  test::append_frame(beats, c, rng, 0.0);  // zero blanking after the dropped EOF
  MomentGen gen;
  std::vector<DonePulse> pulses;
  for (size_t i = 0; i < beats.size() + MomentGen::kCombineCycles + 4; ++i) {
    gen.clock(i < beats.size() ? beats[i] : LutBeat{}, /*eof_drop=*/i == b_eof);
    if (gen.done()) pulses.push_back({i, gen.results()});
  }
  EXPECT_EQ(gen.overrun_count(), 1u);
  ASSERT_EQ(pulses.size(), 2u);
  EXPECT_EQ(pulses[0].results, golden(a));
  EXPECT_EQ(pulses[1].results, golden(c));
}

TEST(MomentGen, ResetMidFrameThenExactFrame) {
  std::mt19937 rng(12);
  const LutFrame a = test::random_frame(rng, 30, 20);
  const LutFrame b = test::random_frame(rng, 17, 23);
  std::vector<LutBeat> beats;
  test::append_frame(beats, a, rng, 0.2);
  MomentGen gen;
  for (size_t i = 0; i < beats.size() / 2; ++i) gen.clock(beats[i]);
  gen.reset();
  EXPECT_EQ(gen.results(), MomentResults{});
  EXPECT_FALSE(gen.done());
  // The rest of frame a (no SOF) is ignored; frame b is exact.
  std::vector<LutBeat> rest(beats.begin() + static_cast<std::ptrdiff_t>(beats.size() / 2),
                            beats.end());
  test::append_frame(rest, b, rng, 0.2);
  const auto pulses = run_clocked(gen, rest);
  ASSERT_EQ(pulses.size(), 1u);
  EXPECT_EQ(pulses[0].results, golden(b));
}

// The overrun rule at its boundary: an EOF kCombineCycles - 1 edges after
// the last accepted EOF is dropped, one kCombineCycles edges after is taken;
// frames of exactly kCombineCycles pixels back to back never overrun.
TEST(MomentGen, OverrunBoundaryIsCombineCycles) {
  std::mt19937 rng(77);
  const size_t l = MomentGen::kCombineCycles;
  // 1x1 frames: EOF at cycle 0; then at l - 1 (dropped); then at l (taken,
  // measured from 0, the last accepted); then at 2l - 1 (dropped: l - 1 after).
  std::vector<LutFrame> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(test::random_frame(rng, 1, 1));
  std::vector<LutBeat> beats;
  test::append_frame(beats, frames[0], rng, 0.0);
  test::append_idle(beats, l - 2);
  test::append_frame(beats, frames[1], rng, 0.0);  // cycle l - 1
  test::append_frame(beats, frames[2], rng, 0.0);  // cycle l
  test::append_idle(beats, l - 2);
  test::append_frame(beats, frames[3], rng, 0.0);  // cycle 2l - 1
  const auto eofs = eof_cycles(beats);
  ASSERT_EQ(eofs, (std::vector<size_t>{0, l - 1, l, 2 * l - 1}));
  MomentGen gen;
  const auto pulses = run_clocked(gen, beats);
  ASSERT_EQ(pulses.size(), 2u);
  EXPECT_EQ(pulses[0].cycle, l);
  EXPECT_EQ(pulses[0].results, golden(frames[0]));
  EXPECT_EQ(pulses[1].cycle, 2 * l);
  EXPECT_EQ(pulses[1].results, golden(frames[2]));
  EXPECT_EQ(gen.overrun_count(), 2u);

  // Back to back, zero blanking: l pixels per frame pass, l - 1 do not.
  for (const auto& [w, h, expect_all] :
       std::vector<std::tuple<uint16_t, uint16_t, bool>>{{3, 19, true}, {7, 8, false}}) {
    ASSERT_EQ(size_t{w} * h == l, expect_all);
    MomentGen g;
    std::vector<LutBeat> b;
    std::vector<MomentResults> want;
    for (int i = 0; i < 6; ++i) {
      const LutFrame f = test::random_frame(rng, w, h);
      test::append_frame(b, f, rng, 0.0);
      if (expect_all || i % 2 == 0) want.push_back(golden(f));
    }
    const auto p = run_clocked(g, b);
    ASSERT_EQ(p.size(), want.size()) << w << "x" << h;
    for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(p[i].results, want[i]) << i;
    EXPECT_EQ(g.overrun_count(), expect_all ? 0u : 3u);
  }
}

// frame_check guarantees positions and rectangular frames; the model checks.
TEST(MomentGen, NonRectangularFrameOrWrongPositionThrows) {
  std::mt19937 rng(8);
  const LutFrame f = test::random_frame(rng, 5, 3);
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, 0.0);
  {
    std::vector<LutBeat> bad;  // row 1 loses its pixel x = 2: 4 pixels
    for (const LutBeat& b : beats) {
      if (b.pix.y == 1 && b.pix.x == 2) continue;
      bad.push_back(b);
      if (b.pix.y == 1 && b.pix.x > 2) bad.back().pix.x = static_cast<uint16_t>(b.pix.x - 1);
    }
    MomentGen gen;
    EXPECT_THROW(for (const auto& b : bad) gen.clock(b), std::logic_error);
  }
  {
    auto bad = beats;
    bad[3].pix.x = 4;
    MomentGen gen;
    EXPECT_THROW(for (const auto& b : bad) gen.clock(b), std::logic_error);
  }
  {
    auto bad = beats;
    bad.pop_back();
    bad.back().pix.eof = true;  // EOF on a pixel that does not end the row
    MomentGen gen;
    EXPECT_THROW(for (const auto& b : bad) gen.clock(b), std::logic_error);
  }
  MomentGen gen;
  EXPECT_NO_THROW(for (const auto& b : beats) gen.clock(b));
}

// The frames of the throughput benchmarks (bench/block_bench.cpp): the cycle
// model over two frames back to back, and the fast path.
TEST(MomentGen, ClockedEqualsGoldenOnRandomVgaFramesBackToBack) {
  std::mt19937 rng(4);
  const LutFrame f = test::random_frame(rng, 640, 480);
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, 0.0);
  test::append_idle(beats, MomentGen::kCombineCycles);
  MomentGen gen;
  for (int i = 0; i < 2; ++i) {
    for (const LutBeat& b : beats) gen.clock(b);
    EXPECT_EQ(gen.results(), golden(f)) << "frame " << i;
  }
}

TEST(MomentGen, FastPathEqualsGoldenOnARandomVgaFrame) {
  std::mt19937 rng(3);
  const LutFrame f = test::random_frame(rng, 640, 480);
  EXPECT_EQ(fast(f), golden(f));
}

}  // namespace
}  // namespace ceilnav::stream
