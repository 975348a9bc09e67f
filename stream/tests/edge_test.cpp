// edge: golden (OpenCV absdiff / Sobel) == fast frame path == clocked model,
// exactly; FIFO, back-pressure, overflow, trailers, aborts, disabled frames.
#include "stream/edge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "golden/edge_ref.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

using test::LutFrame;

static_assert(unpack_edge_beat(pack_edge_beat({2047, 2046, 2040, true, EdgeKind::kSobel})) ==
              EdgeRecord{2047, 2046, 2040, true, EdgeKind::kSobel});
static_assert(pack_edge_beat({3, 5, 0xABC, true, EdgeKind::kVertical}) ==
              (0x0005'0003ull | (uint64_t{0xABC | 1u << 12 | 1u << 13} << 32)));
static_assert(pack_edge_trailer(7, kEdgeTrailerAborted, 0x12345) ==
              (7ull | (uint64_t{2u | 0xFFFFu << 16} << 32)));

constexpr EdgeMode kModes[] = {EdgeMode::kHorizontal, EdgeMode::kVertical, EdgeMode::kSobel};

cv::Mat remap_mat(const LutFrame& f) {
  return cv::Mat(f.height, f.width, CV_8UC1, const_cast<uint8_t*>(f.remap.data())).clone();
}

std::vector<EdgeRecord> golden_edges(const LutFrame& f, const EdgeConfig& c) {
  return golden::find_edges_ref(remap_mat(f), {c.mode, c.threshold});
}

std::vector<EdgeRecord> fast_edges(const LutFrame& f, const EdgeConfig& c) {
  std::vector<EdgeRecord> e;
  EdgeDetector::scan_frame(c, f.remap.data(), f.width, f.height, e);
  return e;
}

// Everything the m_axis_edges consumer saw, split into frames at tlast.
struct Received {
  std::vector<std::vector<EdgeRecord>> edges;  // per trailer
  std::vector<uint64_t> trailers;
  std::vector<EdgeStats> stats;  // at every done pulse
  uint32_t max_occupancy = 0;
};

// Clocks the beats (then idle until the FIFO drains) with tready from
// `ready`; checks that the output holds while stalled. cfgs[k] is on the
// config port from the k-th SOF beat on.
Received run_clocked(EdgeDetector& d, const std::vector<LutBeat>& beats,
                     const std::vector<EdgeConfig>& cfgs, const std::function<bool()>& ready) {
  size_t sof_count = 0;
  Received rx;
  std::vector<EdgeRecord> current;
  EdgeBeat prev{};
  bool prev_stalled = false;
  const LutBeat idle{};
  for (size_t i = 0; i < beats.size() + 10000000; ++i) {
    const bool done_feeding = i >= beats.size();
    const EdgeBeat out = d.m_axis_edges();
    if (prev_stalled) {
      EXPECT_EQ(out, prev) << "m_axis changed while stalled, cycle " << i;
    }
    if (!out.tvalid) {
      EXPECT_EQ(out, EdgeBeat{}) << "idle output not zero, cycle " << i;
    }
    const bool tready = done_feeding || ready();
    if (out.tvalid && tready) {
      if (out.tlast) {
        rx.edges.push_back(current);
        rx.trailers.push_back(out.tdata);
        current.clear();
      } else {
        current.push_back(unpack_edge_beat(out.tdata));
        EXPECT_EQ(pack_edge_beat(current.back()), out.tdata) << "unused tdata bits set";
      }
    }
    prev = out;
    prev_stalled = out.tvalid && !tready;
    const LutBeat& in = done_feeding ? idle : beats[i];
    if (in.pix.valid && in.pix.sof) d.set_config(cfgs.at(sof_count++));
    d.clock(in, tready);
    rx.max_occupancy = std::max(rx.max_occupancy, d.fifo_occupancy());
    if (d.done()) rx.stats.push_back(d.last_frame_stats());
    if (done_feeding && !d.pending() && d.fifo_occupancy() == 0 && !d.m_axis_edges().tvalid) {
      break;
    }
  }
  EXPECT_TRUE(current.empty()) << "edges after the last trailer";
  return rx;
}

EdgeConfig random_config(std::mt19937& rng, EdgeMode mode) {
  std::uniform_int_distribution<int> t(0, 80);
  std::uniform_int_distribution<int> big(0, 4095);
  std::bernoulli_distribution rare(0.1);
  return {true, mode, static_cast<uint16_t>(rare(rng) ? big(rng) : t(rng))};
}

bool always() {
  return true;
}

// Frames of small and odd sizes, every mode, random thresholds.
TEST(Edge, GoldenEqualsFastRandomFrames) {
  std::mt19937 rng(0xED6E01);
  std::uniform_int_distribution<int> dim(1, 40);
  size_t total = 0;
  for (int k = 0; k < 600; ++k) {
    const auto w = static_cast<uint16_t>(k < 30 ? 1 + k % 3 : dim(rng));
    const auto h = static_cast<uint16_t>(k < 30 ? 1 + k / 10 : dim(rng));
    const LutFrame f = test::random_frame(rng, w, h);
    for (EdgeMode m : kModes) {
      const EdgeConfig c = random_config(rng, m);
      const auto g = golden_edges(f, c);
      ASSERT_EQ(fast_edges(f, c), g) << w << "x" << h << " mode " << int(m) << " t " << c.threshold;
      total += g.size();
    }
  }
  EXPECT_GT(total, 50000u);
}

// Known values: a vertical step 0 | 255 and a horizontal one.
TEST(Edge, StepMagnitudesAndPolarity) {
  LutFrame f{6, 5, {}, std::vector<uint8_t>(30), std::vector<uint8_t>(30)};
  for (uint32_t y = 0; y < 5; ++y) {
    for (uint32_t x = 3; x < 6; ++x) f.remap[y * 6 + x] = 255;
  }
  const auto h = fast_edges(f, {true, EdgeMode::kHorizontal, 0});
  ASSERT_EQ(h.size(), 5u);
  EXPECT_EQ(h[0], (EdgeRecord{3, 0, 255, true, EdgeKind::kHorizontal}));
  EXPECT_TRUE(fast_edges(f, {true, EdgeMode::kHorizontal, 255}).empty());  // > t, not >=
  EXPECT_TRUE(fast_edges(f, {true, EdgeMode::kVertical, 0}).empty());
  const auto s = fast_edges(f, {true, EdgeMode::kSobel, 0});
  ASSERT_EQ(s.size(), 6u);  // centres x = 2, 3 on rows 1..3
  EXPECT_EQ(s[0], (EdgeRecord{2, 1, 1020, true, EdgeKind::kSobel}));
  EXPECT_EQ(s[1], (EdgeRecord{3, 1, 1020, true, EdgeKind::kSobel}));
  EXPECT_EQ(golden_edges(f, {true, EdgeMode::kSobel, 0}), s);
  // The transpose, falling: vertical differences and gy.
  LutFrame v{5, 6, {}, std::vector<uint8_t>(30, 255), std::vector<uint8_t>(30)};
  for (uint32_t i = 15; i < 30; ++i) v.remap[i] = 0;
  const auto vv = fast_edges(v, {true, EdgeMode::kVertical, 100});
  ASSERT_EQ(vv.size(), 5u);
  EXPECT_EQ(vv[4], (EdgeRecord{4, 3, 255, false, EdgeKind::kVertical}));
  EXPECT_EQ(golden_edges(v, {true, EdgeMode::kVertical, 100}), vv);
  const auto vs = fast_edges(v, {true, EdgeMode::kSobel, 1019});
  ASSERT_EQ(vs.size(), 6u);
  EXPECT_EQ(vs[0], (EdgeRecord{1, 2, 1020, false, EdgeKind::kSobel}));
  // A corner: gx = gy = 3 * 255 (the bound 2 * 1020 needs gx and gy of 1020 at once).
  LutFrame c{3, 3, {}, {0, 0, 0, 0, 0, 255, 0, 255, 255}, std::vector<uint8_t>(9)};
  const auto cs = fast_edges(c, {true, EdgeMode::kSobel, 0});
  ASSERT_EQ(cs.size(), 1u);
  EXPECT_EQ(cs[0].magnitude, 2 * (255 * 3));  // gx = gy = 765
  EXPECT_EQ(golden_edges(c, {true, EdgeMode::kSobel, 0}), cs);
}

// A photo through a random LUT: golden == fast == clocked, every mode.
TEST(Edge, PhotoGoldenFastClocked) {
  const auto img = test::load_photo("building.jpg", 320, 240);
  ASSERT_TRUE(img) << "opencv-doc sample data missing";
  std::vector<uint8_t> grey(img->begin<uint8_t>(), img->end<uint8_t>());
  std::array<LutEntry, 256> lut{};
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = lut_entry(static_cast<uint8_t>(g), false);
  }
  const LutFrame f = LutFrame::from_grey(grey, static_cast<uint16_t>(img->cols),
                                         static_cast<uint16_t>(img->rows), lut);
  std::mt19937 rng(0xED6E02);
  std::vector<LutBeat> beats;
  std::vector<EdgeConfig> cfgs;
  std::vector<std::vector<EdgeRecord>> expect;
  for (EdgeMode m : kModes) {
    const EdgeConfig c{true, m, static_cast<uint16_t>(m == EdgeMode::kSobel ? 200 : 24)};
    expect.push_back(golden_edges(f, c));
    ASSERT_EQ(fast_edges(f, c), expect.back());
    EXPECT_GT(expect.back().size(), 1000u);
    // The edge density and the densest row (docs/blocks/edge.md, FIFO sizing).
    std::vector<uint32_t> per_row(f.height);
    for (const EdgeRecord& e : expect.back()) ++per_row[e.y];
    std::printf(
        "building.jpg %ux%u mode %d t %u: %zu edges (%.1f %% of the pixels), at most %u in a row\n",
        f.width, f.height, static_cast<int>(m), c.threshold, expect.back().size(),
        100.0 * static_cast<double>(expect.back().size()) / static_cast<double>(f.pixels()),
        *std::max_element(per_row.begin(), per_row.end()));
    test::append_frame(beats, f, rng, 0.1);
    cfgs.push_back(c);
  }
  EdgeDetector d(1 << 20);
  std::bernoulli_distribution ready(0.95);
  const Received rx = run_clocked(d, beats, cfgs, [&] { return ready(rng); });
  ASSERT_EQ(rx.edges.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(rx.edges[k], expect[k]);
    EXPECT_EQ(rx.trailers[k], pack_edge_trailer(expect[k].size(), 0, 0));
    EXPECT_EQ(rx.stats.at(k), (EdgeStats{static_cast<uint32_t>(expect[k].size()), 0}));
  }
}

// Random frames with gaps and random back-pressure, a FIFO large enough:
// clocked == fast per frame, trailers and stats exact.
TEST(Edge, ClockedEqualsFastWithGaps) {
  std::mt19937 rng(0xED6E03);
  std::uniform_int_distribution<int> dim(1, 30);
  std::uniform_int_distribution<int> mode(0, 3);
  std::vector<LutBeat> beats;
  std::vector<EdgeConfig> cfgs;
  std::vector<std::vector<EdgeRecord>> expect;
  for (int k = 0; k < 300; ++k) {
    const LutFrame f =
        test::random_frame(rng, static_cast<uint16_t>(dim(rng)), static_cast<uint16_t>(dim(rng)));
    const EdgeConfig c = random_config(rng, static_cast<EdgeMode>(mode(rng)));
    expect.push_back(fast_edges(f, c));
    if (c.mode == EdgeMode::kReserved) {
      EXPECT_TRUE(expect.back().empty());
    }
    test::append_frame(beats, f, rng, k % 3 == 0 ? 0.0 : 0.3);
    if (k % 5 == 0) test::append_idle(beats, 3);
    cfgs.push_back(c);
  }
  EdgeDetector d(4096);
  std::bernoulli_distribution ready(0.7);
  const Received rx = run_clocked(d, beats, cfgs, [&] { return ready(rng); });
  ASSERT_EQ(rx.edges.size(), expect.size());
  for (size_t k = 0; k < expect.size(); ++k) {
    EXPECT_EQ(rx.edges[k], expect[k]) << "frame " << k;
    EXPECT_EQ(rx.trailers[k], pack_edge_trailer(expect[k].size(), 0, 0));
    EXPECT_EQ(rx.stats.at(k).edges_emitted, expect[k].size());
  }
  EXPECT_EQ(d.trailers_lost(), 0u);
}

// A stalled consumer: depth 8 keeps 8 edges (7 in the memory, one in the
// output register, loaded while tvalid was low) and the trailer; the rest are
// dropped, counted and flagged. A second frame while still stalled loses its
// trailer; the next stored trailer carries the overflow flag.
TEST(Edge, OverflowDropsCountsAndFlags) {
  std::mt19937 rng(0xED6E04);
  const LutFrame f = test::random_frame(rng, 40, 10);
  const EdgeConfig c{true, EdgeMode::kHorizontal, 0};
  const auto all = fast_edges(f, c);
  ASSERT_GT(all.size(), 100u);
  EdgeDetector d(8);
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, 0.0);
  bool stall = true;
  std::vector<EdgeStats> stats;
  for (const LutBeat& b : beats) {
    d.set_config(c);
    d.clock(b, !stall);
    if (d.done()) stats.push_back(d.last_frame_stats());
  }
  // The EOF pixel's edge and trailer are staged and admitted on the next
  // edge, which also publishes the counters (done()).
  EXPECT_TRUE(stats.empty());
  EXPECT_TRUE(d.pending());
  d.clock(LutBeat{}, !stall);
  EXPECT_FALSE(d.pending());
  ASSERT_TRUE(d.done());
  stats.push_back(d.last_frame_stats());
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_EQ(stats[0].edges_emitted, 8u);
  EXPECT_EQ(stats[0].edges_dropped, all.size() - 8);
  EXPECT_EQ(d.fifo_occupancy(), 8u);  // 7 edges and the trailer
  // A 2x1 frame while stalled: its edge is dropped and its trailer lost.
  LutFrame tiny{2, 1, {}, {0, 200}, {0, 0}};
  std::vector<LutBeat> tb;
  test::append_frame(tb, tiny, rng, 0.0);
  for (const LutBeat& b : tb) d.clock(b, false);
  EXPECT_EQ(d.trailers_lost(), 0u);  // the EOF pixel's events are staged
  d.clock(LutBeat{}, false);
  EXPECT_EQ(d.trailers_lost(), 1u);
  EXPECT_EQ(d.last_frame_stats(), (EdgeStats{0, 1}));
  // Drain, then a third frame: its trailer says overflow (the lost one).
  std::vector<uint64_t> trailers;
  std::vector<EdgeRecord> got;
  auto drain = [&] {
    for (int i = 0; i < 100; ++i) {
      const EdgeBeat o = d.m_axis_edges();
      if (o.tvalid) {
        if (o.tlast) {
          trailers.push_back(o.tdata);
        } else {
          got.push_back(unpack_edge_beat(o.tdata));
        }
      }
      d.clock(LutBeat{}, true);
    }
  };
  drain();
  ASSERT_EQ(trailers.size(), 1u);
  EXPECT_EQ(trailers[0], pack_edge_trailer(8, kEdgeTrailerOverflow, all.size() - 8));
  EXPECT_EQ(got, std::vector<EdgeRecord>(all.begin(), all.begin() + 8));
  tb.clear();
  test::append_frame(tb, tiny, rng, 0.0);
  for (const LutBeat& b : tb) d.clock(b, true);
  drain();
  ASSERT_EQ(trailers.size(), 2u);
  EXPECT_EQ(trailers[1], pack_edge_trailer(1, kEdgeTrailerOverflow, 0));
  EXPECT_EQ(got.back(), (EdgeRecord{1, 0, 200, true, EdgeKind::kHorizontal}));
}

// Aborts (alone and with the next SOF), a disabled frame, a reserved mode.
TEST(Edge, AbortsDisabledAndReservedFrames) {
  std::mt19937 rng(0xED6E05);
  const LutFrame f = test::random_frame(rng, 12, 6);
  const EdgeConfig on{true, EdgeMode::kVertical, 10};
  const auto all = fast_edges(f, on);
  ASSERT_GT(all.size(), 10u);
  std::vector<LutBeat> beats;
  std::vector<EdgeConfig> cfgs;
  // 1: aborted after 40 pixels by an abort beat.
  test::append_frame(beats, f, rng, 0.2, 40);
  cfgs.push_back(on);
  // 2: aborted after 50 pixels by the next SOF (combined beat).
  test::append_frame(beats, f, rng, 0.2, 50);
  beats.pop_back();
  const size_t combined = beats.size();
  // 3: full, disabled; 4: full, reserved mode; 5: full, enabled.
  test::append_frame(beats, f, rng, 0.0);
  beats[combined].pix.abort = true;
  cfgs.push_back({false, EdgeMode::kVertical, 10});
  test::append_frame(beats, f, rng, 0.0);
  cfgs.push_back({true, EdgeMode::kReserved, 0});
  test::append_frame(beats, f, rng, 0.1);
  cfgs.push_back(on);
  cfgs.insert(cfgs.begin() + 1, on);
  EdgeDetector d(1024);
  const Received rx = run_clocked(d, beats, cfgs, always);
  auto before = [&](int pixels) {
    std::vector<EdgeRecord> e;
    for (const EdgeRecord& r : all) {
      if (int{r.y} * 12 + r.x < pixels) e.push_back(r);
    }
    return e;
  };
  ASSERT_EQ(rx.edges.size(), 4u);  // the disabled frame has no trailer
  EXPECT_EQ(rx.edges[0], before(40));
  EXPECT_EQ(rx.trailers[0], pack_edge_trailer(before(40).size(), kEdgeTrailerAborted, 0));
  EXPECT_EQ(rx.edges[1], before(50));
  EXPECT_EQ(rx.trailers[1], pack_edge_trailer(before(50).size(), kEdgeTrailerAborted, 0));
  EXPECT_TRUE(rx.edges[2].empty());
  EXPECT_EQ(rx.trailers[2], pack_edge_trailer(0, 0, 0));
  EXPECT_EQ(rx.edges[3], all);
  EXPECT_EQ(rx.stats.size(), 2u);  // done only at an EOF of an enabled frame
}

// The line buffer holds a row of the largest width; one-pixel-wide frames
// read the word they write.
TEST(Edge, WidestAndNarrowestFrames) {
  std::mt19937 rng(0xED6E06);
  for (uint16_t w : {uint16_t{2048}, uint16_t{1}, uint16_t{2}}) {
    const auto h = static_cast<uint16_t>(w == 2048 ? 4 : 300);
    const LutFrame f = test::random_frame(rng, w, h);
    for (EdgeMode m : kModes) {
      const EdgeConfig c{true, m, 3};
      std::vector<LutBeat> beats;
      test::append_frame(beats, f, rng, 0.1);
      EdgeDetector d(1 << 14);
      const Received rx = run_clocked(d, beats, {c}, always);
      ASSERT_EQ(rx.edges.size(), 1u);
      EXPECT_EQ(rx.edges[0], golden_edges(f, c)) << w << " mode " << int(m);
    }
  }
}

TEST(Edge, RejectsBadDepthAndPosition) {
  EXPECT_THROW(EdgeDetector(6), std::invalid_argument);
  EXPECT_THROW(EdgeDetector(4), std::invalid_argument);
  EdgeDetector d(8);
  d.set_config({true, EdgeMode::kHorizontal, 0});
  LutBeat b;
  b.pix.valid = true;
  b.pix.sof = true;
  d.clock(b, true);
  b.pix.sof = false;
  b.pix.x = 5;  // the counters say 1
  EXPECT_THROW(d.clock(b, true), std::logic_error);
}

}  // namespace
}  // namespace ceilnav::stream
