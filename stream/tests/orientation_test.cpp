// orientation: clocked model == fast frame path == bit-true golden
// (golden::orientation_histogram_fixed) exactly; the publication's latency,
// the double buffer (reads of the published frame while the next one votes),
// the sweep and the frames it skips, aborts, resets, disabled frames and the
// configuration latched at the SOF.
#include "stream/orientation.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "golden/orientation_ref.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

using test::append_idle;
using test::LutFrame;

LutFrame frame_of(const cv::Mat& img) {
  LutFrame f{static_cast<uint16_t>(img.cols), static_cast<uint16_t>(img.rows), {}, {}, {}};
  f.remap.assign(img.begin<uint8_t>(), img.end<uint8_t>());
  f.grey = f.remap;
  f.mask.assign(f.remap.size(), 0);
  return f;
}

cv::Mat mat_of(const LutFrame& f) {
  return cv::Mat(f.height, f.width, CV_8UC1, const_cast<uint8_t*>(f.remap.data())).clone();
}

std::vector<uint32_t> golden_fixed(const LutFrame& f, const OrientationConfig& c, uint32_t bins) {
  return golden::orientation_histogram_fixed(
      mat_of(f), {static_cast<int>(bins), static_cast<int>(c.threshold)});
}

// Clocks `beats` with cfgs[k] on the config port from the k-th SOF beat on;
// returns the published histograms (read through read_bin() on the done
// pulse) and checks that done comes kDoneLatencyCycles after each published
// EOF.
struct Published {
  std::vector<std::vector<uint32_t>> hists;
  std::vector<uint32_t> votes;
};
Published run(Orientation& o, const std::vector<LutBeat>& beats,
              const std::vector<OrientationConfig>& cfgs) {
  Published out;
  size_t sofs = 0;
  std::vector<uint64_t> eof_edges;
  uint64_t edge = 0;
  auto step = [&](const LutBeat& b) {
    if (b.pix.valid && b.pix.sof && sofs < cfgs.size()) o.set_config(cfgs[sofs++]);
    o.clock(b);
    if (b.pix.valid && b.pix.eof) eof_edges.push_back(edge);
    if (o.done()) {
      out.hists.push_back(o.results());
      out.votes.push_back(o.frame_votes());
      bool found = false;
      for (uint64_t e : eof_edges) found = found || e + Orientation::kDoneLatencyCycles == edge;
      EXPECT_TRUE(found) << "done at edge " << edge << " without an EOF "
                         << Orientation::kDoneLatencyCycles << " edges before";
    }
    ++edge;
  };
  for (const auto& b : beats) step(b);
  for (int i = 0; i < 400; ++i) step(LutBeat{});
  return out;
}

uint32_t count_votes(const LutFrame& f, const OrientationConfig& c, uint32_t bins) {
  uint32_t n = 0;
  for (uint32_t y = 2; y < f.height; ++y) {
    for (uint32_t x = 2; x < f.width; ++x) {
      auto at = [&](uint32_t u, uint32_t v) { return int{f.remap[size_t{v} * f.width + u]}; };
      const int gx = at(x, y - 2) + 2 * at(x, y - 1) + at(x, y) -
                     (at(x - 2, y - 2) + 2 * at(x - 2, y - 1) + at(x - 2, y));
      const int gy = at(x - 2, y) + 2 * at(x - 1, y) + at(x, y) -
                     (at(x - 2, y - 2) + 2 * at(x - 1, y - 2) + at(x, y - 2));
      n += fp::orientation::vote(gx, gy, c.threshold, bins).valid ? 1u : 0u;
    }
  }
  return n;
}

TEST(Orientation, ClockedEqualsFastEqualsGoldenOnRandomFrames) {
  std::mt19937 rng(0x0A1E);
  for (uint32_t bins : {90u, 64u, 2u, 256u}) {
    Orientation o(bins);
    for (int i = 0; i < 6; ++i) {
      std::uniform_int_distribution<int> wd(45, 200), hd(3, 90), td(0, 300);
      const LutFrame f =
          test::random_frame(rng, static_cast<uint16_t>(wd(rng)), static_cast<uint16_t>(hd(rng)));
      const OrientationConfig c{true, static_cast<uint16_t>(td(rng))};
      std::vector<LutBeat> beats(100);  // idle: the reset's sweep
      test::append_frame(beats, f, rng, i % 2 == 0 ? 0.0 : 0.3);
      const Published p = run(o, beats, {c});
      ASSERT_EQ(p.hists.size(), 1u);
      const auto gold = golden_fixed(f, c, bins);
      EXPECT_EQ(p.hists[0], gold) << "bins " << bins << " frame " << i;
      EXPECT_EQ(Orientation::scan_frame(c, bins, f.remap.data(), f.width, f.height), gold);
      EXPECT_EQ(p.votes[0], count_votes(f, c, bins));
      EXPECT_GT(p.votes[0], 0u);
    }
  }
}

TEST(Orientation, PhotosBackToBackWithZeroBlanking) {
  std::mt19937 rng(7);
  Orientation o;
  std::vector<LutFrame> frames;
  std::vector<OrientationConfig> cfgs;
  for (const auto& name : test::photo_names()) {
    const auto img = test::load_photo(name, 320, 240);
    ASSERT_TRUE(img) << name;
    frames.push_back(frame_of(*img));
    cfgs.push_back({true, static_cast<uint16_t>(8 * frames.size())});
  }
  std::vector<LutBeat> beats(100);  // idle
  for (const auto& f : frames) test::append_frame(beats, f, rng, 0.0);
  const Published p = run(o, beats, cfgs);
  ASSERT_EQ(p.hists.size(), frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(p.hists[i], golden_fixed(frames[i], cfgs[i], 90)) << i;
  }
  EXPECT_EQ(o.frames(), frames.size());
  EXPECT_EQ(o.frames_skipped(), 0u);
}

// Zero blanking: the sweep of the bank freed by frame N's publication ends
// before frame N+1's first vote (pixel (2, 2)) reaches it when the frame is
// at least 45 pixels wide (90 bins); at 44 that vote meets the sweep and the
// frame is skipped. docs/blocks/orientation.md, "Sweep".
TEST(Orientation, FramesThatMeetTheSweepAreSkipped) {
  for (const uint16_t width : {uint16_t{44}, uint16_t{45}}) {
    Orientation o;
    std::mt19937 rng(1);
    // Every pixel votes: a vertical step at x = 2 makes (1..) gradients in
    // column x = 1, 2; noise elsewhere at threshold 0.
    LutFrame f = test::random_frame(rng, width, 6);
    for (uint32_t y = 0; y < 6; ++y) {
      for (uint32_t x = 0; x < width; ++x) f.remap[y * width + x] = x < 2 ? 0 : 200;
    }
    const OrientationConfig c{true, 0};
    std::vector<LutBeat> beats(100);  // idle
    for (int k = 0; k < 3; ++k) test::append_frame(beats, f, rng, 0.0);
    const Published p = run(o, beats, {c, c, c});
    if (width == 45) {
      EXPECT_EQ(p.hists.size(), 3u);
      EXPECT_EQ(o.frames_skipped(), 0u);
    } else {
      // Frame 1 published; frame 2's first vote meets the sweep (skipped,
      // its bank swept again); frame 3's first vote meets that sweep too.
      EXPECT_EQ(p.hists.size(), 1u);
      EXPECT_EQ(o.frames_skipped(), 2u);
    }
    for (const auto& h : p.hists) EXPECT_EQ(h, golden_fixed(f, c, 90));
    EXPECT_FALSE(o.clearing());
  }
}

TEST(Orientation, ReadsShowThePublishedFrameWhileTheNextVotes) {
  std::mt19937 rng(3);
  Orientation o;
  const LutFrame a = test::random_frame(rng, 80, 20);
  const LutFrame b = test::random_frame(rng, 64, 30);
  const OrientationConfig c{true, 20};
  const auto ga = golden_fixed(a, c, 90);
  const auto gb = golden_fixed(b, c, 90);
  ASSERT_NE(ga, gb);
  // Nothing is published before the first frame: reads give 0.
  for (int i = 0; i < 100; ++i) o.clock(LutBeat{}, true, static_cast<uint16_t>(i % 90));
  EXPECT_EQ(o.hist_rd_data(), 0u);
  EXPECT_FALSE(o.results_valid());
  o.set_config(c);
  std::vector<LutBeat> beats;
  test::append_frame(beats, a, rng, 0.0);
  test::append_frame(beats, b, rng, 0.0);
  append_idle(beats, 20);
  int published = 0;
  uint16_t bin = 0;
  for (const auto& beat : beats) {
    // The read sampled on this edge returns the bin as it is before it.
    const uint32_t want = o.read_bin(bin);
    o.clock(beat, true, bin);
    EXPECT_EQ(o.hist_rd_data(), want);
    if (o.done()) ++published;
    if (published == 1) {
      EXPECT_EQ(o.results(), ga);
    }
    bin = static_cast<uint16_t>((bin + 7) % 97);  // 90 .. 96 read 0
  }
  EXPECT_EQ(published, 2);
  EXPECT_EQ(o.results(), gb);
  o.clock(LutBeat{}, false, 3);
  EXPECT_EQ(o.hist_rd_data(), 0u);  // no read, no data
  o.clock(LutBeat{}, true, 95);
  EXPECT_EQ(o.hist_rd_data(), 0u);  // beyond the bins
  o.clock(LutBeat{}, true, 3);
  EXPECT_EQ(o.hist_rd_data(), gb[3]);
}

TEST(Orientation, AbortsResetsAndDisabledFrames) {
  std::mt19937 rng(5);
  const LutFrame a = test::random_frame(rng, 60, 20);
  const LutFrame b = test::random_frame(rng, 70, 25);
  const OrientationConfig on{true, 10};
  const OrientationConfig off{false, 10};
  const auto gb = golden_fixed(b, on, 90);
  {
    // An aborted frame is never published and its votes do not reach the next.
    Orientation o;
    std::vector<LutBeat> beats(100);  // idle
    test::append_frame(beats, a, rng, 0.1, 700);
    append_idle(beats, 3);
    test::append_frame(beats, b, rng, 0.1);
    const Published p = run(o, beats, {on, on});
    ASSERT_EQ(p.hists.size(), 1u);
    EXPECT_EQ(p.hists[0], gb);
  }
  {
    // A disabled frame is not taken: the next enabled one is.
    Orientation o;
    std::vector<LutBeat> beats(100);  // idle
    test::append_frame(beats, a, rng, 0.0);
    test::append_frame(beats, b, rng, 0.0);
    const Published p = run(o, beats, {off, on});
    ASSERT_EQ(p.hists.size(), 1u);
    EXPECT_EQ(p.hists[0], gb);
    EXPECT_EQ(o.frames(), 1u);
  }
  {
    // A reset mid-frame: nothing published, the sweep restarts; then b.
    Orientation o;
    std::vector<LutBeat> beats(100);  // idle
    test::append_frame(beats, a, rng, 0.0);
    o.set_config(on);
    for (size_t i = 0; i < beats.size() - 300; ++i) o.clock(beats[i]);
    o.reset();
    EXPECT_TRUE(o.clearing());
    EXPECT_FALSE(o.results_valid());
    std::vector<LutBeat> rest(90);  // idle
    test::append_frame(rest, b, rng, 0.0);
    const Published p = run(o, rest, {on});
    ASSERT_EQ(p.hists.size(), 1u);
    EXPECT_EQ(p.hists[0], gb);
  }
  {
    // The threshold is latched at the SOF: changing the port mid-frame does
    // nothing to the open frame.
    Orientation o;
    std::vector<LutBeat> beats(100);  // idle
    test::append_frame(beats, b, rng, 0.0);
    o.set_config(on);
    for (size_t i = 0; i < beats.size(); ++i) {
      if (i == 400) o.set_config({true, 4000});
      o.clock(beats[i]);
    }
    for (int i = 0; i < 20; ++i) o.clock(LutBeat{});
    EXPECT_EQ(o.results(), gb);
  }
}

TEST(Orientation, ParametersAreChecked) {
  EXPECT_THROW(Orientation(1), std::invalid_argument);
  EXPECT_THROW(Orientation(257), std::invalid_argument);
  EXPECT_NO_THROW(Orientation(256));
}

}  // namespace
}  // namespace ceilnav::stream
