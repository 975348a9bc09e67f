// class_moments: clocked == fast == golden (cv::moments of each class mask in
// the window), exactly.
#include "stream/class_moments.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "golden/class_moments_ref.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

using test::LutFrame;
__extension__ typedef unsigned __int128 u128;

// A frame of random classes: runs of one class of random length, so masks have
// both long runs and single pixels. p_class[c] weights class c.
LutFrame random_class_frame(std::mt19937& rng, uint16_t w, uint16_t h) {
  LutFrame f;
  f.width = w;
  f.height = h;
  const size_t n = size_t{w} * h;
  f.remap.assign(n, 0);
  f.mask.assign(n, 0);
  f.cls.resize(n);
  std::uniform_int_distribution<int> cls(0, 3);
  std::uniform_int_distribution<int> run(1, 40);
  uint8_t c = 0;
  int left = 0;
  for (auto& v : f.cls) {
    if (left-- <= 0) {
      c = static_cast<uint8_t>(cls(rng));
      left = run(rng) - 1;
    }
    v = c;
  }
  for (size_t i = 0; i < n; ++i) f.remap[i] = static_cast<uint8_t>(rng());
  return f;
}

cv::Mat cls_mat(const LutFrame& f) {
  return cv::Mat(f.height, f.width, CV_8UC1, const_cast<uint8_t*>(f.cls.data())).clone();
}

ClassMomentResults fast(const LutFrame& f, const ClassWindow& win) {
  return ClassMoments::frame(f.cls.data(), f.width, f.height, f.width, win);
}

ClassWindow random_window(std::mt19937& rng, uint16_t w, uint16_t h) {
  std::uniform_int_distribution<int> kind(0, 9);
  auto pick = [&](uint16_t n, uint16_t& lo, uint16_t& hi) {
    std::uniform_int_distribution<int> pos(0, n + 2);
    switch (kind(rng)) {
      case 0:  // whole frame (register default)
        lo = 0;
        hi = static_cast<uint16_t>(kMaxWidth);
        break;
      case 1:  // empty: hi == lo
        lo = hi = static_cast<uint16_t>(pos(rng));
        break;
      case 2:  // reversed: empty
        lo = static_cast<uint16_t>(pos(rng) + 1);
        hi = static_cast<uint16_t>(lo - 1);
        break;
      case 3:  // last line / column only
        lo = static_cast<uint16_t>(n - 1);
        hi = n;
        break;
      case 4:  // first only
        lo = 0;
        hi = 1;
        break;
      case 5:  // beyond the frame edge
        lo = static_cast<uint16_t>(pos(rng));
        hi = 4095;
        break;
      default: {
        lo = static_cast<uint16_t>(pos(rng));
        hi = static_cast<uint16_t>(pos(rng));
        if (hi < lo) std::swap(lo, hi);
      }
    }
  };
  ClassWindow win;
  pick(w, win.x0, win.x1);
  pick(h, win.y0, win.y1);
  return win;
}

struct Beat {
  LutBeat beat;
  ClassWindow win;  // on the window ports this cycle
  bool keep = true;
};

// Frames to beats: the frame's window is on the ports at its SOF pixel;
// every other cycle carries garbage on the window ports (they are latched at
// SOF, so it must not matter).
void append(std::vector<Beat>& out, const LutFrame& f, const ClassWindow& win, std::mt19937& rng,
            double gap, int64_t abort_after = -1, bool keep = true) {
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, gap, abort_after);
  for (const LutBeat& b : beats) {
    Beat x{b, b.pix.sof ? win : random_window(rng, 2048, 2048), keep};
    out.push_back(x);
  }
}

struct Done {
  size_t cycle;
  ClassMomentResults results;
};

std::vector<Done> run_clocked(ClassMoments& cm, const std::vector<Beat>& beats, size_t tail = 4) {
  std::vector<Done> out;
  std::mt19937 rng(5);
  for (size_t i = 0; i < beats.size() + tail; ++i) {
    if (i < beats.size()) {
      cm.clock(beats[i].beat, beats[i].win, beats[i].keep);
    } else {
      cm.clock(LutBeat{}, random_window(rng, 2048, 2048), false);
    }
    if (cm.done()) out.push_back({i, cm.results()});
  }
  return out;
}

size_t eof_index(const std::vector<Beat>& beats, size_t from = 0) {
  for (size_t i = from; i < beats.size(); ++i) {
    if (beats[i].beat.pix.valid && beats[i].beat.pix.eof) return i;
  }
  return beats.size();
}

constexpr bool tight(uint64_t max, int bits) {
  return bits < 64 && max < (uint64_t{1} << bits) &&
         (bits == 1 || max >= (uint64_t{1} << (bits - 1)));
}

TEST(ClassMoments, WidthsCoverTheLargestFrame) {
  // Sum of x^a y^b over a full 2048 x 2048 frame, brute force along x and y.
  const uint64_t n = kMaxWidth;
  u128 s0 = 0, s1 = 0, s2 = 0;
  for (uint64_t x = 0; x < n; ++x) {
    s0 += 1;
    s1 += x;
    s2 += u128{x} * x;
  }
  const std::array<u128, kMomentCount> full = {s0 * s0, s1 * s0, s0 * s1,
                                               s2 * s0, s1 * s1, s0 * s2};
  for (size_t k = 0; k < kMomentCount; ++k) {
    EXPECT_TRUE(tight(static_cast<uint64_t>(full[k]), class_moments_widths::kMomentBits[k])) << k;
  }
  EXPECT_TRUE(tight(uint64_t{n - 1} * (n - 1), class_moments_widths::kTermBits));
  EXPECT_TRUE(tight(n, class_moments_widths::kWindowBits));
}

TEST(ClassMoments, RandomFramesAndWindowsClockedFastGolden) {
  std::mt19937 rng(301);
  std::vector<std::pair<uint16_t, uint16_t>> sizes = {{1, 1},    {1, 7},    {9, 1},    {2, 2},
                                                      {5, 3},    {17, 11},  {64, 48},  {33, 70},
                                                      {2048, 2}, {3, 2048}, {640, 480}};
  std::uniform_int_distribution<int> small(1, 40);
  for (int i = 0; i < 30; ++i) {
    sizes.emplace_back(static_cast<uint16_t>(small(rng)), static_cast<uint16_t>(small(rng)));
  }
  int frames = 0;
  for (const auto& [w, h] : sizes) {
    for (int rep = 0; rep < 3; ++rep) {
      const LutFrame f = random_class_frame(rng, w, h);
      const ClassWindow win = rep == 0 ? ClassWindow{} : random_window(rng, w, h);
      const ClassMomentResults want = golden::class_moments_ref(cls_mat(f), win);
      EXPECT_EQ(fast(f, win), want) << w << "x" << h;
      std::vector<Beat> beats;
      append(beats, f, win, rng, rep == 2 ? 0.3 : 0.0);
      ClassMoments cm;
      const auto done = run_clocked(cm, beats);
      ASSERT_EQ(done.size(), 1u);
      EXPECT_EQ(done[0].cycle, eof_index(beats) + ClassMoments::kLatencyCycles);
      EXPECT_EQ(done[0].results, want) << w << "x" << h;
      ++frames;
    }
  }
  EXPECT_EQ(frames, 3 * static_cast<int>(sizes.size()));
}

TEST(ClassMoments, WholeWindowEqualsMomentGenMaskPerClass) {
  // Independent cross-check with the other moment block: the mask plane
  // set to (class == c) gives moment_gen's mask moments of class c.
  std::mt19937 rng(302);
  const LutFrame f = random_class_frame(rng, 97, 61);
  const ClassMomentResults got = fast(f, ClassWindow{});
  for (int c = 1; c <= kMomentClasses; ++c) {
    MomentGen::FrameSums sums;
    std::vector<uint8_t> mask(f.width);
    for (uint32_t y = 0; y < f.height; ++y) {
      for (uint32_t x = 0; x < f.width; ++x) mask[x] = f.cls_row(y)[x] == c ? 1 : 0;
      MomentGen::accumulate_row(sums, y, f.remap_row(y), mask.data(), f.width);
    }
    EXPECT_EQ(got.of(c), MomentGen::finish(sums).mask) << c;
  }
  EXPECT_THROW((void)got.of(0), std::out_of_range);
}

TEST(ClassMoments, PhotosThroughAClassLut) {
  std::mt19937 rng(303);
  int photos = 0;
  for (const std::string& name : test::photo_names()) {
    const auto img = test::load_photo(name, 640, 480);
    if (!img) continue;
    ++photos;
    // Classes by grey level: dark = bar, mid = shadow, bright = pattern.
    std::array<LutEntry, 256> lut{};
    for (int g = 0; g < 256; ++g) {
      const uint8_t c = g < 60    ? kClassBar
                        : g < 120 ? kClassShadow
                        : g < 200 ? kClassBackground
                                  : kClassPattern;
      lut[static_cast<size_t>(g)] = lut_entry(static_cast<uint8_t>(g), g > 128, c);
    }
    std::vector<uint8_t> grey(img->begin<uchar>(), img->end<uchar>());
    const LutFrame f = LutFrame::from_grey(grey, static_cast<uint16_t>(img->cols),
                                           static_cast<uint16_t>(img->rows), lut);
    const cv::Mat cls = golden::lut_class_ref(*img, lut);
    for (const ClassWindow& win :
         {ClassWindow{}, ClassWindow{100, 500, 50, 400}, random_window(rng, f.width, f.height)}) {
      const ClassMomentResults want = golden::class_moments_ref(cls, win);
      EXPECT_EQ(fast(f, win), want) << name;
      std::vector<Beat> beats;
      append(beats, f, win, rng, 0.05);
      ClassMoments cm;
      const auto done = run_clocked(cm, beats);
      ASSERT_EQ(done.size(), 1u);
      EXPECT_EQ(done[0].results, want) << name;
      if (win == ClassWindow{}) {  // every class occurs in these photos
        for (int c = 1; c <= kMomentClasses; ++c) EXPECT_GT(want.of(c)[kM00], 0u) << name << c;
      }
    }
  }
  EXPECT_GE(photos, 3) << "opencv-doc photos missing";
}

TEST(ClassMoments, LargestFrameAllOneClassMatchesClosedForm) {
  const uint16_t n = 2048;
  LutFrame f;
  f.width = f.height = n;
  f.remap.assign(size_t{n} * n, 0);
  f.mask.assign(size_t{n} * n, 0);
  f.cls.assign(size_t{n} * n, kClassBar);
  std::mt19937 rng(304);
  std::vector<Beat> beats;
  append(beats, f, ClassWindow{}, rng, 0.0);
  ClassMoments cm;
  const auto done = run_clocked(cm, beats);
  ASSERT_EQ(done.size(), 1u);
  const uint64_t s0 = n;
  const uint64_t s1 = uint64_t{n} * (n - 1) / 2;
  const uint64_t s2 = uint64_t{n - 1} * n * (2 * n - 1) / 6;
  const std::array<uint64_t, kMomentCount> want = {s0 * s0, s1 * s0, s0 * s1,
                                                   s2 * s0, s1 * s1, s0 * s2};
  EXPECT_EQ(done[0].results.of(kClassBar), want);
  EXPECT_EQ(done[0].results.of(kClassPattern), (std::array<uint64_t, kMomentCount>{}));
  EXPECT_EQ(golden::class_moments_ref(cls_mat(f), ClassWindow{}).of(kClassBar), want);
  EXPECT_EQ(fast(f, ClassWindow{}).of(kClassBar), want);
}

TEST(ClassMoments, BackToBackZeroBlankingAbortsAndDiscardedFrames) {
  std::mt19937 rng(305);
  std::uniform_int_distribution<int> dim(1, 9);
  std::uniform_int_distribution<int> pct(0, 99);
  std::vector<Beat> beats;
  std::vector<ClassMomentResults> want;
  std::vector<size_t> want_cycle;
  for (int i = 0; i < 200; ++i) {
    const auto w = static_cast<uint16_t>(dim(rng));
    const auto h = static_cast<uint16_t>(dim(rng));
    const LutFrame f = random_class_frame(rng, w, h);
    const ClassWindow win = random_window(rng, w, h);
    const int roll = pct(rng);
    if (roll < 20) {  // aborted partway: never shown
      std::uniform_int_distribution<int64_t> cut(0, int64_t{w} * h - 1);
      append(beats, f, win, rng, 0.1, cut(rng));
    } else if (roll < 30) {  // complete, but the EOF is not kept
      append(beats, f, win, rng, 0.1, -1, false);
    } else {
      append(beats, f, win, rng, roll < 65 ? 0.0 : 0.2);
      want.push_back(golden::class_moments_ref(cls_mat(f), win));
      want_cycle.push_back(eof_index(beats, beats.size() - 1) + ClassMoments::kLatencyCycles);
    }
    if (pct(rng) < 10) beats.push_back({LutBeat{}, random_window(rng, 2048, 2048), true});
  }
  ClassMoments cm;
  const auto done = run_clocked(cm, beats);
  ASSERT_EQ(done.size(), want.size());
  for (size_t i = 0; i < done.size(); ++i) {
    EXPECT_EQ(done[i].cycle, want_cycle[i]) << i;
    EXPECT_EQ(done[i].results, want[i]) << i;
  }
}

TEST(ClassMoments, PositionThatDoesNotFollowThrows) {
  std::mt19937 rng(306);
  const LutFrame f = random_class_frame(rng, 4, 3);
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, 0.0);
  beats[5].pix.x = 3;  // (1, 1) claims x = 3
  ClassMoments cm;
  EXPECT_THROW(
      {
        for (const LutBeat& b : beats) cm.clock(b, ClassWindow{});
      },
      std::logic_error);
}

TEST(ClassMoments, ResetMidFrameThenExactFrame) {
  std::mt19937 rng(307);
  const LutFrame a = random_class_frame(rng, 30, 20);
  const LutFrame b = random_class_frame(rng, 25, 19);
  std::vector<Beat> first;
  append(first, a, ClassWindow{}, rng, 0.1);
  ClassMoments cm;
  for (size_t i = 0; i < first.size() / 2; ++i) cm.clock(first[i].beat, first[i].win);
  cm.reset();
  EXPECT_FALSE(cm.done());
  EXPECT_EQ(cm.results(), ClassMomentResults{});
  std::vector<Beat> second;
  const ClassWindow win{3, 20, 2, 17};
  append(second, b, win, rng, 0.1);
  const auto done = run_clocked(cm, second);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].results, golden::class_moments_ref(cls_mat(b), win));
}

TEST(ClassMoments, BackgroundIsTheWindowMinusTheThreeClasses) {
  // The documented derivation of the unmeasured class 0.
  std::mt19937 rng(308);
  const LutFrame f = random_class_frame(rng, 50, 40);
  const ClassWindow win{5, 45, 3, 38};
  const ClassMomentResults r = fast(f, win);
  cv::Mat bg = cls_mat(f) == 0;
  cv::Mat masked = cv::Mat::zeros(bg.size(), CV_8UC1);
  bg(cv::Rect(5, 3, 40, 35)).copyTo(masked(cv::Rect(5, 3, 40, 35)));
  const cv::Moments m = cv::moments(masked, true);
  std::array<uint64_t, kMomentCount> window{};
  for (uint64_t y = win.y0; y < win.y1; ++y) {
    for (uint64_t x = win.x0; x < win.x1; ++x) {
      const std::array<uint64_t, kMomentCount> t = {1, x, y, x * x, x * y, y * y};
      for (size_t k = 0; k < kMomentCount; ++k) window[k] += t[k];
    }
  }
  std::array<uint64_t, kMomentCount> background = window;
  for (int c = 1; c <= kMomentClasses; ++c) {
    for (size_t k = 0; k < kMomentCount; ++k) background[k] -= r.of(c)[k];
  }
  const std::array<double, kMomentCount> cv_bg = {m.m00, m.m10, m.m01, m.m20, m.m11, m.m02};
  for (size_t k = 0; k < kMomentCount; ++k) {
    EXPECT_EQ(static_cast<double>(background[k]), cv_bg[k]) << k;
  }
}

}  // namespace
}  // namespace ceilnav::stream
