// thresh_lut: clocked == fast == cv::LUT exactly; the table a frame sees
// changes only at an SOF, one cycle of latency.
#include "stream/thresh_lut.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "golden/thresh_lut_ref.hpp"
#include "stream/frame_check.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

using Table = std::array<LutEntry, 256>;

Table random_table(std::mt19937& rng) {
  std::uniform_int_distribution<int> entry(0, 0x7FF);
  Table t{};
  for (LutEntry& e : t) {
    e = static_cast<LutEntry>(entry(rng));
  }
  return t;
}

void write_table(ThreshLut& lut, const Table& t) {
  for (unsigned i = 0; i < 256; ++i) {
    lut.write(static_cast<uint8_t>(i), t[i]);
  }
}

struct LutFrames {
  std::vector<cv::Mat> remap;
  std::vector<cv::Mat> mask;
  std::vector<cv::Mat> cls;
};

// frame_check -> thresh_lut, frame_start = the SOF beat accepted by frame_check.
// between_beats(i) runs before beat i (host writes). Checks the latency: the
// LUT output's pixel is frame_check's output of the previous cycle.
template <typename F>
LutFrames run_chain(ThreshLut& lut, const std::vector<VideoBeat>& beats, uint16_t w, uint16_t h,
                    F between_beats) {
  FrameCheck fc;
  LutFrames out;
  cv::Mat remap;
  cv::Mat mask;
  cv::Mat cls;
  for (size_t i = 0; i <= beats.size() + 1; ++i) {
    between_beats(i);
    const VideoBeat beat = i < beats.size() ? beats[i] : VideoBeat{};
    const PixelBeat fc_out = fc.m_pix();
    lut.clock(fc_out, beat.tvalid && beat.tuser);
    fc.clock(beat, w, h);
    const LutBeat& o = lut.m_lut();
    EXPECT_EQ(o.pix.valid, fc_out.valid);
    EXPECT_EQ(o.pix.grey, fc_out.grey);
    EXPECT_EQ(o.pix.x, fc_out.x);
    EXPECT_EQ(o.pix.y, fc_out.y);
    EXPECT_EQ(o.pix.abort, fc_out.abort);
    if (!o.pix.valid) {
      EXPECT_EQ(o.remap, 0);
      EXPECT_FALSE(o.mask);
      EXPECT_EQ(o.cls, 0);
      continue;
    }
    if (o.pix.sof) {
      remap = cv::Mat(h, w, CV_8UC1);
      mask = cv::Mat(h, w, CV_8UC1);
      cls = cv::Mat(h, w, CV_8UC1);
    }
    remap.at<uchar>(o.pix.y, o.pix.x) = o.remap;
    mask.at<uchar>(o.pix.y, o.pix.x) = o.mask ? 1 : 0;
    cls.at<uchar>(o.pix.y, o.pix.x) = o.cls;
    if (o.pix.eof) {
      out.remap.push_back(remap.clone());
      out.mask.push_back(mask.clone());
      out.cls.push_back(cls.clone());
    }
  }
  return out;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && cv::countNonZero(a != b) == 0;
}

void expect_matches_golden(const cv::Mat& grey, const Table& table, const cv::Mat& remap,
                           const cv::Mat& mask, const cv::Mat& cls, const ThreshLut& lut_for_fast) {
  cv::Mat ref_remap;
  cv::Mat ref_mask;
  golden::lut_ref(grey, table, ref_remap, ref_mask);
  const cv::Mat ref_cls = golden::lut_class_ref(grey, table);
  EXPECT_TRUE(same(remap, ref_remap));
  EXPECT_TRUE(same(mask, ref_mask));
  EXPECT_TRUE(same(cls, ref_cls));
  // Fast path: lookup in the active bank.
  cv::Mat fast_remap(grey.size(), CV_8UC1);
  cv::Mat fast_mask(grey.size(), CV_8UC1);
  cv::Mat fast_cls(grey.size(), CV_8UC1);
  for (int y = 0; y < grey.rows; ++y) {
    for (int x = 0; x < grey.cols; ++x) {
      const LutEntry e = lut_for_fast.active_entry(grey.at<uchar>(y, x));
      fast_remap.at<uchar>(y, x) = static_cast<uchar>(e & kLutRemapMask);
      fast_mask.at<uchar>(y, x) = (e & kLutMaskBit) != 0 ? 1 : 0;
      fast_cls.at<uchar>(y, x) = lut_class(e);
    }
  }
  EXPECT_TRUE(same(fast_remap, ref_remap));
  EXPECT_TRUE(same(fast_mask, ref_mask));
  EXPECT_TRUE(same(fast_cls, ref_cls));
}

TEST(ThreshLut, ClockedEqualsFastEqualsGoldenOnRandomImages) {
  std::mt19937 rng(21);
  const std::vector<std::pair<int, int>> sizes = {{1, 1}, {3, 1}, {1, 4}, {17, 9}, {640, 480}};
  for (const auto& [w, h] : sizes) {
    ThreshLut lut;
    const Table table = random_table(rng);
    write_table(lut, table);
    const cv::Mat img = test::random_image(rng, w, h);
    std::vector<VideoBeat> beats;
    test::append_frame(beats, img, rng, 0.3);
    const LutFrames got =
        run_chain(lut, beats, static_cast<uint16_t>(w), static_cast<uint16_t>(h), [](size_t) {});
    ASSERT_EQ(got.remap.size(), 1u);
    expect_matches_golden(img, table, got.remap[0], got.mask[0], got.cls[0], lut);
  }
}

TEST(ThreshLut, ClockedEqualsFastEqualsGoldenOnPhotos) {
  std::mt19937 rng(22);
  int photos = 0;
  for (const std::string& name : test::photo_names()) {
    const auto img = test::load_photo(name, 640, 480);
    if (!img) {
      continue;
    }
    ++photos;
    for (const Table& table : {threshold_lut(128), random_table(rng)}) {
      ThreshLut lut;
      write_table(lut, table);
      std::vector<VideoBeat> beats;
      test::append_frame(beats, *img, rng, 0.05);
      const LutFrames got = run_chain(lut, beats, static_cast<uint16_t>(img->cols),
                                      static_cast<uint16_t>(img->rows), [](size_t) {});
      ASSERT_EQ(got.remap.size(), 1u) << name;
      expect_matches_golden(*img, table, got.remap[0], got.mask[0], got.cls[0], lut);
    }
  }
  EXPECT_GE(photos, 3) << "opencv-doc photos missing";
}

// Host writes during frame A (zero blanking before B) reach B exactly, never A.
TEST(ThreshLut, TableChangesExactlyAtTheNextSof) {
  std::mt19937 rng(23);
  for (double gap_prob : {0.0, 0.2}) {
    const cv::Mat a = test::random_image(rng, 11, 6);
    const cv::Mat b = test::random_image(rng, 11, 6);
    const cv::Mat c = test::random_image(rng, 11, 6);
    const Table t1 = random_table(rng);
    const Table t2 = random_table(rng);
    std::vector<VideoBeat> beats;
    test::append_frame(beats, a, rng, gap_prob);
    const size_t mid_a = beats.size() / 2;
    const size_t end_a = beats.size();
    test::append_frame(beats, b, rng, gap_prob);
    test::append_frame(beats, c, rng, gap_prob);
    ThreshLut lut;
    write_table(lut, t1);
    const LutFrames got = run_chain(lut, beats, 11, 6, [&](size_t i) {
      if (i == mid_a) {
        write_table(lut, t2);  // half the table before the pixel of the middle...
      }
      if (i == end_a) {
        EXPECT_EQ(lut.active_table(), t1);  // ...the rest still in frame A's time
        EXPECT_TRUE(lut.commit_pending());
      }
    });
    ASSERT_EQ(got.remap.size(), 3u);
    cv::Mat ref_remap;
    cv::Mat ref_mask;
    golden::lut_ref(a, t1, ref_remap, ref_mask);
    EXPECT_TRUE(same(got.remap[0], ref_remap));
    EXPECT_TRUE(same(got.mask[0], ref_mask));
    golden::lut_ref(b, t2, ref_remap, ref_mask);
    EXPECT_TRUE(same(got.remap[1], ref_remap));
    EXPECT_TRUE(same(got.mask[1], ref_mask));
    // No write since: frame C keeps t2 (no swap without a pending commit).
    golden::lut_ref(c, t2, ref_remap, ref_mask);
    EXPECT_TRUE(same(got.remap[2], ref_remap));
    EXPECT_FALSE(lut.commit_pending());
  }
}

// Documented hardware behaviour: after a swap, the shadow bank holds the table
// before the active one, so a partial write commits a mixture.
TEST(ThreshLut, ShadowBankAfterASwapHoldsTheOlderTable) {
  std::mt19937 rng(24);
  const Table t1 = random_table(rng);
  const Table t2 = random_table(rng);
  ThreshLut lut;
  write_table(lut, t1);
  lut.commit_at_frame_start();
  write_table(lut, t2);
  lut.commit_at_frame_start();
  EXPECT_EQ(lut.active_table(), t2);
  EXPECT_EQ(lut.shadow_table(), t1);
  lut.write(7, 0x1AB);
  lut.commit_at_frame_start();
  Table expected = t1;
  expected[7] = 0x1AB;
  EXPECT_EQ(lut.active_table(), expected);
}

TEST(ThreshLut, WriteIgnoresBitsAboveTen) {
  ThreshLut lut;
  lut.write(3, 0xFFFF);
  lut.commit_at_frame_start();
  EXPECT_EQ(lut.active_entry(3), 0x7FF);
  PixelBeat p;
  p.valid = true;
  p.grey = 3;
  lut.clock(p, false);
  EXPECT_EQ(lut.m_lut().remap, 0xFF);
  EXPECT_TRUE(lut.m_lut().mask);
  EXPECT_EQ(lut.m_lut().cls, kClassBar);
}

TEST(ThreshLut, ClassFieldIsIndependentOfRemapAndMask) {
  EXPECT_EQ(lut_entry(0x5A, true, kClassShadow), 0x55A);
  EXPECT_EQ(lut_class(lut_entry(0xFF, true, kClassPattern)), kClassPattern);
  EXPECT_EQ(lut_class(lut_entry(0xFF, true)), kClassBackground);  // default class 0
  EXPECT_EQ(lut_entry(7, false, kClassBar) & kLutRemapMask, 7);
  EXPECT_EQ(lut_entry(7, false, kClassBar) & kLutMaskBit, 0);
}

}  // namespace
}  // namespace ceilnav::stream
