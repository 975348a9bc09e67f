// frame_check: well-formed streams pass unchanged one cycle later; every
// malformed class is counted exactly, aborts the open frame once, and the next
// good frame comes through exact.
#include "stream/frame_check.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

using test::append_frame;
using test::append_gaps;
using test::pixel_beat;

struct Observed {
  std::vector<cv::Mat> frames;  // completed frames, reassembled from the x, y of the beats
  std::vector<char> events;     // 'A' = abort, 'F' = frame complete, in order
  int pixels = 0;
  int sofs = 0;  // SOF pixels emitted (frames opened)
};

// Clocks every beat and checks the registered output against the beat just
// sampled: a valid output pixel carries the input's grey, in raster order.
// From beat index switch_at on, the configuration input reads cfg_w2 x cfg_h2.
Observed run(FrameCheck& fc, const std::vector<VideoBeat>& beats, uint16_t cfg_w, uint16_t cfg_h,
             size_t switch_at = SIZE_MAX, uint16_t cfg_w2 = 0, uint16_t cfg_h2 = 0) {
  Observed obs;
  cv::Mat current;
  int next_x = 0;
  int next_y = 0;
  for (size_t i = 0; i < beats.size(); ++i) {
    const VideoBeat& beat = beats[i];
    if (i == switch_at) {
      cfg_w = cfg_w2;
      cfg_h = cfg_h2;
    }
    fc.clock(beat, cfg_w, cfg_h);
    const PixelBeat& p = fc.m_pix();
    if (p.abort) {
      obs.events.push_back('A');
      current.release();
    }
    if (!p.valid) {
      continue;
    }
    ++obs.pixels;
    EXPECT_TRUE(beat.tvalid);
    EXPECT_EQ(p.grey, beat.tdata);
    if (p.sof) {
      ++obs.sofs;
      EXPECT_TRUE(beat.tuser);
      current = cv::Mat(fc.height(), fc.width(), CV_8UC1, cv::Scalar(0));
      next_x = 0;
      next_y = 0;
    }
    EXPECT_FALSE(current.empty()) << "pixel outside a frame";
    if (current.empty()) {
      continue;
    }
    EXPECT_EQ(p.x, next_x);
    EXPECT_EQ(p.y, next_y);
    EXPECT_EQ(p.sof, p.x == 0 && p.y == 0);
    EXPECT_EQ(p.eol, p.x == current.cols - 1);
    EXPECT_EQ(p.eof, p.eol && p.y == current.rows - 1);
    current.at<uchar>(p.y, p.x) = p.grey;
    if (p.eol) {
      next_x = 0;
      ++next_y;
    } else {
      ++next_x;
    }
    if (p.eof) {
      obs.frames.push_back(current);
      obs.events.push_back('F');
      current.release();
    }
  }
  return obs;
}

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && cv::countNonZero(a != b) == 0;
}

TEST(FrameCheck, WellFormedFramesPassExactlyAnySizeAnyGaps) {
  std::mt19937 rng(11);
  const std::vector<std::pair<int, int>> sizes = {{1, 1},  {1, 7},  {7, 1},    {2, 2},
                                                  {13, 5}, {64, 3}, {640, 480}};
  for (const auto& [w, h] : sizes) {
    for (double gap_prob : {0.0, 0.3}) {
      FrameCheck fc;
      std::vector<VideoBeat> beats;
      std::vector<cv::Mat> images;
      for (int f = 0; f < 3; ++f) {  // back to back: no blanking between frames when gap_prob = 0
        images.push_back(test::random_image(rng, w, h));
        append_frame(beats, images.back(), rng, gap_prob);
      }
      const Observed obs = run(fc, beats, static_cast<uint16_t>(w), static_cast<uint16_t>(h));
      ASSERT_EQ(obs.frames.size(), images.size()) << w << "x" << h;
      for (size_t i = 0; i < images.size(); ++i) {
        EXPECT_TRUE(same(obs.frames[i], images[i])) << w << "x" << h << " frame " << i;
      }
      FrameErrorCounters expected;
      expected.frames_ok = 3;
      EXPECT_EQ(fc.counters(), expected);
      EXPECT_EQ(fc.state(), FrameCheck::State::kIdle);
    }
  }
}

// A malformed frame between two good ones: the good ones must come through exact.
struct MalformedCase {
  const char* name;
  std::vector<VideoBeat> bad;  // the malformed part
  FrameErrorCounters errors;   // expected counters (frames_ok = 2 added by the test)
  std::vector<char> events;    // expected events between the two good frames
  bool zero_blanking_after = false;
};

constexpr int kW = 9;
constexpr int kH = 4;

std::vector<VideoBeat> rows(const cv::Mat& img, int first_row, int row_count, bool sof) {
  std::vector<VideoBeat> out;
  for (int y = first_row; y < first_row + row_count; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      out.push_back(
          pixel_beat(img.at<uchar>(y, x), sof && x == 0 && y == first_row, x == img.cols - 1));
    }
  }
  return out;
}

std::vector<MalformedCase> malformed_cases(std::mt19937& rng) {
  const cv::Mat img = test::random_image(rng, kW, kH);
  std::vector<MalformedCase> cases;
  {
    MalformedCase c{"early_eol", rows(img, 0, 1, true), {}, {'A'}};
    std::vector<VideoBeat> line = rows(img, 1, 1, false);
    line[4].tlast = true;  // EOL at x = 4 < width-1
    c.bad.insert(c.bad.end(), line.begin(), line.end());
    const auto rest = rows(img, 2, 2, false);
    c.bad.insert(c.bad.end(), rest.begin(), rest.end());
    c.errors.early_eol = 1;
    c.errors.frames_aborted = 1;
    cases.push_back(c);
  }
  {
    MalformedCase c{"late_eol", rows(img, 0, 2, true), {}, {'A'}};
    c.bad[kW + kW - 1].tlast = false;  // row 1 has no EOL at x = width-1
    c.bad.push_back(pixel_beat(7, false, true));
    c.errors.late_eol = 1;
    c.errors.frames_aborted = 1;
    cases.push_back(c);
  }
  {
    // The frame is cut after two rows by the next SOF (no blanking): the SOF
    // beat aborts it and starts the following good frame.
    MalformedCase c{"early_sof", rows(img, 0, 2, true), {}, {'A'}, true};
    c.errors.early_sof = 1;
    c.errors.frames_aborted = 1;
    cases.push_back(c);
  }
  {
    MalformedCase c{"missing_sof", rows(img, 0, kH, false), {}, {}};
    c.errors.missing_sof = 1;
    cases.push_back(c);
  }
  {
    MalformedCase c{"extra_line", rows(img, 0, 1, false), {}, {}};
    c.errors.missing_sof = 1;
    cases.push_back(c);
  }
  {
    // A zero-length line: the beat after an EOL carries tlast again (x = 0).
    MalformedCase c{"zero_length_line", rows(img, 0, 1, true), {}, {'A'}};
    c.bad.push_back(pixel_beat(3, false, true));
    c.errors.early_eol = 1;
    c.errors.frames_aborted = 1;
    cases.push_back(c);
  }
  {
    // tlast on the SOF pixel itself: the frame never opens, no abort needed.
    MalformedCase c{"sof_with_eol", rows(img, 0, 1, true), {}, {}};
    c.bad[0].tlast = true;
    c.errors.early_eol = 1;
    cases.push_back(c);
  }
  {
    MalformedCase c{"too_long_line", rows(img, 0, 1, true), {}, {'A'}};
    c.bad.back().tlast = false;
    c.bad.push_back(pixel_beat(1, false, false));
    c.bad.push_back(pixel_beat(2, false, true));
    c.errors.late_eol = 1;
    c.errors.frames_aborted = 1;
    cases.push_back(c);
  }
  return cases;
}

TEST(FrameCheck, EveryMalformedClassCountedAndNextFrameExact) {
  std::mt19937 rng(12);
  for (const MalformedCase& c : malformed_cases(rng)) {
    for (double gap_prob : {0.0, 0.25}) {
      const cv::Mat good_a = test::random_image(rng, kW, kH);
      const cv::Mat good_b = test::random_image(rng, kW, kH);
      std::vector<VideoBeat> beats;
      append_frame(beats, good_a, rng, gap_prob);
      append_gaps(beats, 2);
      beats.insert(beats.end(), c.bad.begin(), c.bad.end());
      if (!c.zero_blanking_after) {
        append_gaps(beats, 3);
      }
      append_frame(beats, good_b, rng, gap_prob);
      FrameCheck fc;
      const Observed obs = run(fc, beats, kW, kH);
      FrameErrorCounters expected = c.errors;
      expected.frames_ok = 2;
      EXPECT_EQ(fc.counters(), expected) << c.name;
      std::vector<char> events = {'F'};
      events.insert(events.end(), c.events.begin(), c.events.end());
      events.push_back('F');
      EXPECT_EQ(obs.events, events) << c.name;
      ASSERT_EQ(obs.frames.size(), 2u) << c.name;
      EXPECT_TRUE(same(obs.frames[0], good_a)) << c.name;
      EXPECT_TRUE(same(obs.frames[1], good_b)) << c.name;
    }
  }
}

TEST(FrameCheck, EarlySofAbortAndSofPixelShareOneBeat) {
  std::mt19937 rng(13);
  const cv::Mat img = test::random_image(rng, kW, kH);
  FrameCheck fc;
  for (const VideoBeat& b : rows(img, 0, 1, true)) {
    fc.clock(b, kW, kH);
  }
  fc.clock(pixel_beat(77, true, false), kW, kH);
  const PixelBeat& p = fc.m_pix();
  EXPECT_TRUE(p.abort);
  EXPECT_TRUE(p.valid);
  EXPECT_TRUE(p.sof);
  EXPECT_EQ(p.grey, 77);
  EXPECT_EQ(fc.state(), FrameCheck::State::kInFrame);
}

TEST(FrameCheck, PixelsBeforeTheFirstSofAfterResetAreCountedOnce) {
  std::mt19937 rng(14);
  const cv::Mat img = test::random_image(rng, kW, kH);
  std::vector<VideoBeat> beats = rows(img, 2, 2, false);  // camera started mid-frame
  append_frame(beats, img, rng, 0.0);
  FrameCheck fc;
  const Observed obs = run(fc, beats, kW, kH);
  FrameErrorCounters expected;
  expected.missing_sof = 1;
  expected.frames_ok = 1;
  EXPECT_EQ(fc.counters(), expected);
  ASSERT_EQ(obs.frames.size(), 1u);
  EXPECT_TRUE(same(obs.frames[0], img));
  EXPECT_EQ(obs.events, std::vector<char>{'F'});
}

TEST(FrameCheck, GeometryChangesOnlyAtTheNextSof) {
  std::mt19937 rng(15);
  const cv::Mat a = test::random_image(rng, 12, 5);
  const cv::Mat b = test::random_image(rng, 7, 9);
  std::vector<VideoBeat> beats_a;
  append_frame(beats_a, a, rng, 0.1);
  std::vector<VideoBeat> beats_b;
  append_frame(beats_b, b, rng, 0.1);
  FrameCheck fc;
  // Frame a checked against 12x5 although the configuration input reads 7x9
  // from its middle on; frame b (zero blanking) is checked against 7x9.
  std::vector<VideoBeat> beats = beats_a;
  beats.insert(beats.end(), beats_b.begin(), beats_b.end());
  const Observed obs = run(fc, beats, 12, 5, beats_a.size() / 2, 7, 9);
  ASSERT_EQ(obs.frames.size(), 2u);
  EXPECT_TRUE(same(obs.frames[0], a));
  EXPECT_TRUE(same(obs.frames[1], b));
  FrameErrorCounters expected;
  expected.frames_ok = 2;
  EXPECT_EQ(fc.counters(), expected);
  EXPECT_EQ(fc.width(), 7);
  EXPECT_EQ(fc.height(), 9);
}

TEST(FrameCheck, ZeroGeometryIsClampedToOne) {
  FrameCheck fc;
  fc.clock(pixel_beat(5, true, true), 0, 0);
  EXPECT_TRUE(fc.m_pix().eof);
  EXPECT_EQ(fc.counters().frames_ok, 1u);
}

// Random streams with random faults: exactly the untouched frames come
// through (each checked pixel by pixel), and the counters balance.
TEST(FrameCheck, RandomFaultsPassOnlyTheGoodFramesAndBalanceTheBooks) {
  std::mt19937 rng(16);
  std::uniform_int_distribution<int> dim(1, 9);
  std::uniform_int_distribution<int> fault(0, 6);
  for (int trial = 0; trial < 40; ++trial) {
    const int w = dim(rng);
    const int h = dim(rng);
    std::vector<VideoBeat> beats;
    std::vector<cv::Mat> good;
    for (int f = 0; f < 12; ++f) {
      const cv::Mat img = test::random_image(rng, w, h);
      std::vector<VideoBeat> frame;
      append_frame(frame, img, rng, 0.2);
      std::uniform_int_distribution<size_t> pos(0, frame.size() - 1);
      size_t i = pos(rng);
      while (!frame[i].tvalid) {
        i = (i + 1) % frame.size();
      }
      switch (fault(rng)) {
        case 0:
          frame[i].tlast = !frame[i].tlast;
          break;
        case 1:  // an SOF inside the frame (the first pixel already has one)
          if (frame[i].tuser) {
            good.push_back(img);
          }
          frame[i].tuser = true;
          break;
        case 2:
          frame.resize(i);  // truncated: the next SOF comes early
          break;
        case 3:
          // Without tlast: the line becomes too long (late EOL) in every case,
          // whereas an extra tlast beat could make a complete frame of shifted data.
          // Before the SOF pixel it is a stray pixel outside the frame instead.
          if (frame[i].tuser) {
            good.push_back(img);
          }
          frame.insert(frame.begin() + static_cast<long>(i), pixel_beat(9, false, false));
          break;
        default:
          good.push_back(img);
          break;
      }
      beats.insert(beats.end(), frame.begin(), frame.end());
    }
    FrameCheck fc;
    const Observed obs = run(fc, beats, static_cast<uint16_t>(w), static_cast<uint16_t>(h));
    ASSERT_EQ(obs.frames.size(), good.size()) << "trial " << trial;
    for (size_t k = 0; k < good.size(); ++k) {
      EXPECT_TRUE(same(obs.frames[k], good[k])) << "trial " << trial << " frame " << k;
    }
    const FrameErrorCounters& c = fc.counters();
    const uint32_t open = fc.state() == FrameCheck::State::kInFrame ? 1u : 0u;
    const auto aborts =
        static_cast<uint32_t>(std::count(obs.events.begin(), obs.events.end(), 'A'));
    EXPECT_EQ(c.frames_ok, good.size());
    EXPECT_EQ(c.frames_aborted, aborts);
    EXPECT_EQ(static_cast<uint32_t>(obs.sofs), c.frames_ok + c.frames_aborted + open);
    EXPECT_LE(c.frames_aborted, c.early_eol + c.late_eol + c.early_sof);
  }
}

TEST(FrameCheck, FastPathEqualsClocked) {
  std::mt19937 rng(17);
  FrameCheck clocked;
  FrameCheck fast;
  const std::vector<std::pair<int, int>> sizes = {{5, 3}, {1, 1}, {8, 2}};
  for (const auto& [w, h] : sizes) {
    std::vector<VideoBeat> beats;
    append_frame(beats, test::random_image(rng, w, h), rng, 0.3);
    beats.push_back(test::gap_beat());
    run(clocked, beats, static_cast<uint16_t>(w), static_cast<uint16_t>(h));
    fast.process_frame(static_cast<uint16_t>(w), static_cast<uint16_t>(h));
    EXPECT_EQ(fast.counters(), clocked.counters());
    EXPECT_EQ(fast.state(), clocked.state());
    EXPECT_EQ(fast.width(), clocked.width());
    EXPECT_EQ(fast.height(), clocked.height());
    EXPECT_EQ(fast.m_pix().valid, clocked.m_pix().valid);
  }
  // An open frame, then a fast frame: counted as an early SOF by both.
  std::vector<VideoBeat> partial;
  append_frame(partial, test::random_image(rng, 4, 4), rng, 0.0);
  partial.resize(6);
  run(clocked, partial, 4, 4);
  run(fast, partial, 4, 4);
  std::vector<VideoBeat> whole;
  append_frame(whole, test::random_image(rng, 4, 4), rng, 0.0);
  whole.push_back(test::gap_beat());
  run(clocked, whole, 4, 4);
  fast.process_frame(4, 4);
  EXPECT_EQ(fast.counters(), clocked.counters());
  EXPECT_EQ(fast.counters().early_sof, 1u);
  EXPECT_EQ(fast.state(), clocked.state());
}

}  // namespace
}  // namespace ceilnav::stream
