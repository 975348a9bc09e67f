// histogram: clocked == fast == cv::calcHist exactly, frames back to back with
// zero blanking, aborted and dropped frames never published, stale bins never
// resurface, the clear sweep's timing and the frames it cannot serve.
#include "stream/histogram.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "golden/histogram_ref.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "stream/frame_check.hpp"
#include "stream/tests/video_source.hpp"
#include "stream/thresh_lut.hpp"

namespace ceilnav::stream {
namespace {

struct Published {
  std::vector<HistogramResults> results;  // one per done() pulse
  std::vector<uint64_t> done_cycles;      // edge index at which done() rose
  std::vector<uint64_t> eof_cycles;       // edge index at which the EOF pixel was on s_axis_video
  std::vector<bool> sof_counted;          // per SOF reaching the histogram: counts() on it
};

// frame_check -> thresh_lut -> histogram. source(i) is the configuration input
// before beat i, keep(f) the keep input with the EOF of the f-th frame that
// reaches the histogram. Checks that results() only change when done() rises.
template <typename F, typename K>
Published run_chain(Histogram& hist, const std::array<LutEntry, 256>& table,
                    const std::vector<VideoBeat>& beats, uint16_t w, uint16_t h, F source, K keep,
                    int drain_cycles = 4) {
  FrameCheck fc;
  ThreshLut lut;
  for (unsigned g = 0; g < 256; ++g) {
    lut.write(static_cast<uint8_t>(g), table[g]);
  }
  Published out;
  HistogramResults shown = hist.results();
  const size_t total = beats.size() + static_cast<size_t>(drain_cycles);
  for (size_t i = 0; i < total; ++i) {
    const VideoBeat beat = i < beats.size() ? beats[i] : VideoBeat{};
    const LutBeat lut_out = lut.m_lut();
    const PixelBeat fc_out = fc.m_pix();
    if (lut_out.pix.valid && lut_out.pix.sof) {
      out.sof_counted.push_back(hist.counts(lut_out));
    }
    const size_t frame = out.sof_counted.empty() ? 0 : out.sof_counted.size() - 1;
    hist.clock(lut_out, source(i), keep(frame));
    lut.clock(fc_out, beat.tvalid && beat.tuser);
    fc.clock(beat, w, h);
    if (fc.m_pix().valid && fc.m_pix().eof) {
      out.eof_cycles.push_back(i);
    }
    // results() may only change when done() rises (checked on small runs: a
    // 1 KiB copy per cycle is too slow for the big frames).
    const bool check_stable = total < 100000;
    if (hist.done()) {
      out.results.push_back(hist.results());
      out.done_cycles.push_back(i);
      shown = out.results.back();
    } else if (check_stable) {
      EXPECT_EQ(hist.results(), shown) << "results changed without done at beat " << i;
    }
  }
  return out;
}

template <typename F>
Published run_chain(Histogram& hist, const std::array<LutEntry, 256>& table,
                    const std::vector<VideoBeat>& beats, uint16_t w, uint16_t h, F source,
                    int drain_cycles = 4) {
  return run_chain(
      hist, table, beats, w, h, source, [](size_t) { return true; }, drain_cycles);
}

// Idle cycles after a frame that let the bank it frees be cleared before the
// frame after next starts (frames of fewer pixels need them).
void append_clear_blanking(std::vector<VideoBeat>& beats, int pixels) {
  test::append_gaps(beats, std::max(0, Histogram::kClearCycles + 2 - pixels));
}

std::array<LutEntry, 256> random_table(std::mt19937& rng) {
  std::uniform_int_distribution<int> entry(0, 0x1FF);
  std::array<LutEntry, 256> t{};
  for (LutEntry& e : t) {
    e = static_cast<LutEntry>(entry(rng));
  }
  return t;
}

cv::Mat remap_of(const cv::Mat& grey, const std::array<LutEntry, 256>& table) {
  cv::Mat remap;
  cv::Mat mask;
  golden::lut_ref(grey, table, remap, mask);
  return remap;
}

HistogramResults fast_of(const cv::Mat& img) {
  Histogram h;
  h.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0]);
  EXPECT_FALSE(h.done());
  return h.results();
}

TEST(Histogram, WidthsFollowFromTheFrameLimit) {
  EXPECT_EQ(Histogram::kBinBits, 23);  // 2048 * 2048 = 2^22 counts needs 23 bits
  HistogramResults r;
  EXPECT_GE(sizeof(r.bins[0]) * 8, static_cast<size_t>(Histogram::kBinBits));
}

TEST(Histogram, ClockedEqualsFastEqualsGoldenBackToBack) {
  std::mt19937 rng(31);
  const std::vector<std::pair<int, int>> sizes = {{1, 1}, {1, 5},   {6, 1},
                                                  {2, 3}, {33, 17}, {640, 480}};
  for (const auto& [w, h] : sizes) {
    for (bool remap_source : {false, true}) {
      for (double gap_prob : {0.0, 0.3}) {
        const auto table = random_table(rng);
        std::vector<cv::Mat> images;
        std::vector<VideoBeat> beats;
        for (int f = 0; f < 3; ++f) {
          images.push_back(f == 1 ? test::blob_image(rng, w, h) : test::random_image(rng, w, h));
          test::append_frame(beats, images.back(), rng, gap_prob);
          append_clear_blanking(beats, w * h);  // none for frames of >= 258 pixels
        }
        Histogram hist;
        const Published pub =
            run_chain(hist, table, beats, static_cast<uint16_t>(w), static_cast<uint16_t>(h),
                      [&](size_t) { return remap_source; });
        ASSERT_EQ(pub.results.size(), images.size()) << w << "x" << h;
        for (size_t f = 0; f < images.size(); ++f) {
          const cv::Mat src = remap_source ? remap_of(images[f], table) : images[f];
          const HistogramResults ref = golden::histogram_ref(src);
          EXPECT_EQ(pub.results[f], ref) << w << "x" << h << " frame " << f;
          EXPECT_EQ(fast_of(src), ref);
          // EOF on s_axis_video at edge t -> LUT output at t+2 sampled -> done at t+3.
          EXPECT_EQ(pub.done_cycles[f], pub.eof_cycles[f] + 2 + Histogram::kDoneLatencyCycles);
        }
      }
    }
  }
}

TEST(Histogram, ClockedEqualsFastEqualsGoldenOnPhotos) {
  std::mt19937 rng(32);
  int photos = 0;
  for (const std::string& name : test::photo_names()) {
    const auto img = test::load_photo(name);
    if (!img) {
      continue;
    }
    ++photos;
    const auto table = threshold_lut(100);
    std::vector<VideoBeat> beats;
    test::append_frame(beats, *img, rng, 0.02);
    Histogram hist;
    const Published pub = run_chain(hist, table, beats, static_cast<uint16_t>(img->cols),
                                    static_cast<uint16_t>(img->rows), [](size_t) { return false; });
    ASSERT_EQ(pub.results.size(), 1u) << name;
    const HistogramResults ref = golden::histogram_ref(*img);
    EXPECT_EQ(pub.results[0], ref) << name;
    EXPECT_EQ(fast_of(*img), ref) << name;
  }
  EXPECT_GE(photos, 3) << "opencv-doc photos missing";
}

// A bin used in frame 0 and never again must read 0 in frames 1, 2, 3, 4:
// the same bank comes back every second frame (a 1-bit epoch tag would alias).
TEST(Histogram, StaleBinsNeverResurface) {
  std::mt19937 rng(33);
  const auto table = threshold_lut(0);
  std::vector<cv::Mat> images = {test::random_image(rng, 16, 16)};
  for (int f = 1; f < 5; ++f) {
    images.push_back(cv::Mat(16, 16, CV_8UC1, cv::Scalar(f)));
  }
  std::vector<VideoBeat> beats;
  for (const cv::Mat& img : images) {
    test::append_frame(beats, img, rng, 0.0);
    append_clear_blanking(beats, 16 * 16);
  }
  Histogram hist;
  const Published pub = run_chain(hist, table, beats, 16, 16, [](size_t) { return false; });
  ASSERT_EQ(pub.results.size(), images.size());
  for (size_t f = 0; f < images.size(); ++f) {
    EXPECT_EQ(pub.results[f], golden::histogram_ref(images[f])) << "frame " << f;
  }
}

TEST(Histogram, AbortedFrameIsNeverPublished) {
  std::mt19937 rng(34);
  const auto table = threshold_lut(0);
  const cv::Mat a = test::random_image(rng, 10, 8);
  const cv::Mat bad = test::random_image(rng, 10, 8);
  const cv::Mat b = test::random_image(rng, 10, 8);
  for (bool early_sof : {false, true}) {
    std::vector<VideoBeat> beats;
    test::append_frame(beats, a, rng, 0.1);
    append_clear_blanking(beats, 0);
    std::vector<VideoBeat> broken;
    test::append_frame(broken, bad, rng, 0.0);
    if (early_sof) {
      broken.resize(broken.size() - 15);  // cut short: b's SOF aborts it
    } else {
      broken[35].tlast = true;  // early EOL in row 3
    }
    beats.insert(beats.end(), broken.begin(), broken.end());
    if (!early_sof) append_clear_blanking(beats, 0);
    test::append_frame(beats, b, rng, 0.0);
    Histogram hist;
    const Published pub = run_chain(hist, table, beats, 10, 8, [](size_t) { return false; });
    ASSERT_EQ(pub.results.size(), 2u);
    EXPECT_EQ(pub.results[0], golden::histogram_ref(a));
    EXPECT_EQ(pub.results[1], golden::histogram_ref(b));
  }
}

// The source select changes mid-frame; the frame keeps the one latched at its SOF.
TEST(Histogram, SourceSelectLatchedAtSof) {
  std::mt19937 rng(35);
  const auto table = random_table(rng);
  const cv::Mat a = test::random_image(rng, 20, 10);
  const cv::Mat b = test::random_image(rng, 20, 10);
  std::vector<VideoBeat> beats;
  test::append_frame(beats, a, rng, 0.1);
  const size_t switch_at = beats.size() / 2;
  append_clear_blanking(beats, 0);
  test::append_frame(beats, b, rng, 0.1);
  Histogram hist;
  const Published pub =
      run_chain(hist, table, beats, 20, 10, [&](size_t i) { return i >= switch_at; });
  ASSERT_EQ(pub.results.size(), 2u);
  EXPECT_EQ(pub.results[0], golden::histogram_ref(a));
  EXPECT_EQ(pub.results[1], golden::histogram_ref(remap_of(b, table)));
}

TEST(Histogram, DoneIsAOneCyclePulseAndResetClears) {
  std::mt19937 rng(36);
  const cv::Mat a = test::random_image(rng, 3, 3);
  std::vector<VideoBeat> beats;
  test::append_frame(beats, a, rng, 0.0);
  Histogram hist;
  const Published pub = run_chain(
      hist, threshold_lut(0), beats, 3, 3, [](size_t) { return false; }, 10);
  ASSERT_EQ(pub.done_cycles.size(), 1u);  // high for exactly one cycle
  EXPECT_FALSE(hist.done());
  EXPECT_EQ(hist.results(), golden::histogram_ref(a));
  hist.reset();
  EXPECT_EQ(hist.results(), HistogramResults{});
}

// A bank that stops being the result bank is dirty on the publication edge and
// clean again kClearCycles + 1 edges later (one bin per edge, from the next edge).
TEST(Histogram, ClearSweepTiming) {
  std::mt19937 rng(37);
  const cv::Mat a = test::random_image(rng, 5, 4);
  const cv::Mat b = test::random_image(rng, 5, 4);
  std::vector<VideoBeat> beats;
  test::append_gaps(beats, Histogram::kClearCycles + 10);  // the reset's mark is cleared
  test::append_frame(beats, a, rng, 0.0);
  append_clear_blanking(beats, 0);
  test::append_frame(beats, b, rng, 0.0);
  FrameCheck fc;
  ThreshLut lut;
  for (unsigned g = 0; g < 256; ++g) lut.write(static_cast<uint8_t>(g), threshold_lut(0)[g]);
  Histogram hist;
  std::vector<std::array<bool, Histogram::kBanks>> dirty;  // after each edge
  std::vector<uint64_t> done_at;
  const size_t total = beats.size() + Histogram::kClearCycles + 10;
  for (size_t i = 0; i < total; ++i) {
    const VideoBeat beat = i < beats.size() ? beats[i] : VideoBeat{};
    const LutBeat lut_out = lut.m_lut();
    const PixelBeat fc_out = fc.m_pix();
    hist.clock(lut_out, false);
    lut.clock(fc_out, beat.tvalid && beat.tuser);
    fc.clock(beat, 5, 4);
    dirty.push_back({hist.dirty(0), hist.dirty(1), hist.dirty(2)});
    if (hist.done()) done_at.push_back(i);
  }
  ASSERT_EQ(done_at.size(), 2u);
  EXPECT_EQ(hist.results(), golden::histogram_ref(b));
  // Every bank clean before the first frame; after each publication exactly
  // one bank (the old result bank) is dirty for kClearCycles + 1 edges.
  for (const uint64_t p : done_at) {
    EXPECT_EQ(dirty[p - 1], (std::array<bool, 3>{false, false, false}));
    unsigned dirty_bank = Histogram::kBanks;
    for (unsigned bank = 0; bank < Histogram::kBanks; ++bank) {
      if (dirty[p][bank]) {
        EXPECT_EQ(dirty_bank, Histogram::kBanks) << "two dirty banks";
        dirty_bank = bank;
      }
    }
    ASSERT_LT(dirty_bank, Histogram::kBanks);
    for (uint64_t e = p; e <= p + Histogram::kClearCycles; ++e) {
      EXPECT_TRUE(dirty[e][dirty_bank]) << "edge " << e - p << " after the publication";
    }
    EXPECT_FALSE(dirty[p + Histogram::kClearCycles + 1][dirty_bank]);
  }
}

// Frames back to back with zero blanking: a frame whose SOF finds no clean
// bank is not counted (counts() low at its SOF) and never published; every
// counted frame is published exactly, in order. The bank freed by frame N's
// publication is clean for frame N + 2 when frame N + 1 has at least
// kClearCycles + 2 pixels (258: never a drop; 257: drops).
TEST(Histogram, FramesWithoutACleanBankAreNotCounted) {
  std::mt19937 rng(38);
  const std::vector<std::pair<int, int>> sizes = {{1, 1},   {9, 7},   {16, 16},
                                                  {257, 1}, {258, 1}, {20, 13}};
  for (const auto& [w, h] : sizes) {
    std::vector<cv::Mat> images;
    std::vector<VideoBeat> beats;
    test::append_gaps(beats, Histogram::kClearCycles + 2);
    for (int f = 0; f < 30; ++f) {
      images.push_back(test::random_image(rng, w, h));
      test::append_frame(beats, images.back(), rng, f % 5 == 4 ? 0.5 : 0.0);
    }
    Histogram hist;
    const Published pub = run_chain(hist, threshold_lut(0), beats, static_cast<uint16_t>(w),
                                    static_cast<uint16_t>(h), [](size_t) { return false; });
    ASSERT_EQ(pub.sof_counted.size(), images.size());
    std::vector<HistogramResults> expected;
    for (size_t f = 0; f < images.size(); ++f) {
      if (pub.sof_counted[f]) expected.push_back(golden::histogram_ref(images[f]));
    }
    EXPECT_TRUE(pub.sof_counted[0]);
    EXPECT_TRUE(pub.sof_counted[1]);  // the spare bank is clean
    if (w * h >= Histogram::kClearCycles + 2) {
      EXPECT_EQ(expected.size(), images.size()) << w << "x" << h << ": no frame may be dropped";
    } else {
      EXPECT_LT(expected.size(), images.size()) << w << "x" << h << ": frames must be dropped";
    }
    EXPECT_EQ(pub.results, expected) << w << "x" << h;
  }
}

// keep low with the EOF (the pipeline drops the frame): no done, the bank is
// cleared, the results stay those of the last kept frame.
TEST(Histogram, DroppedEofIsNotPublished) {
  std::mt19937 rng(39);
  std::vector<cv::Mat> images;
  std::vector<VideoBeat> beats;
  for (int f = 0; f < 5; ++f) {
    images.push_back(test::random_image(rng, 12, 6));
    test::append_frame(beats, images.back(), rng, 0.2);
    append_clear_blanking(beats, 0);
  }
  Histogram hist;
  const Published pub = run_chain(
      hist, threshold_lut(0), beats, 12, 6, [](size_t) { return false; },
      [](size_t f) { return f != 1 && f != 2; });
  ASSERT_EQ(pub.results.size(), 3u);
  EXPECT_EQ(pub.results[0], golden::histogram_ref(images[0]));
  EXPECT_EQ(pub.results[1], golden::histogram_ref(images[3]));
  EXPECT_EQ(pub.results[2], golden::histogram_ref(images[4]));
}

// A reset in mid-frame: reads give 0 until the next publication, a frame may
// start at once (a clean bank is free) and is exact.
TEST(Histogram, ResetInMidFrameLosesNothingAfterIt) {
  std::mt19937 rng(40);
  const cv::Mat a = test::random_image(rng, 20, 20);
  const cv::Mat b = test::random_image(rng, 20, 20);
  std::vector<VideoBeat> first;
  test::append_frame(first, a, rng, 0.0);
  first.resize(first.size() / 2);
  Histogram hist;
  const auto table = threshold_lut(0);
  run_chain(
      hist, table, first, 20, 20, [](size_t) { return false; }, 0);
  hist.reset();
  EXPECT_EQ(hist.results(), HistogramResults{});
  EXPECT_EQ(hist.read_bin(a.at<uint8_t>(0, 0)), 0u);
  std::vector<VideoBeat> second;
  test::append_frame(second, b, rng, 0.0);
  const Published pub = run_chain(hist, table, second, 20, 20, [](size_t) { return false; });
  ASSERT_EQ(pub.sof_counted.size(), 1u);
  EXPECT_TRUE(pub.sof_counted[0]);
  ASSERT_EQ(pub.results.size(), 1u);
  EXPECT_EQ(pub.results[0], golden::histogram_ref(b));
}

}  // namespace
}  // namespace ceilnav::stream
