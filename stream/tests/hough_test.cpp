// stream::Hough: the clocked model == the fast frame path == the golden
// accumulator (quantised table, exact on every cell), per-frame counters,
// saturation, cycles per edge and the trailer -> results latency; the golden
// quantised accumulator against the double-precision one and cv::HoughLines
// on lines (peaks within one bin).
#include "stream/hough.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "golden/hough_ref.hpp"

namespace ceilnav::stream {
namespace {

using golden::EdgePoint;

std::vector<uint64_t> words_of(const std::vector<EdgePoint>& pts) {
  std::vector<uint64_t> w;
  for (const EdgePoint& p : pts) {
    w.push_back(edge_word(p.x, p.y, 0x1234u));
  }
  return w;
}

// The golden cells saturated at the shape's maximum (a saturating sum of
// non-negative weights is the clipped total).
std::vector<uint32_t> clipped(const HoughShape& shape, const std::vector<uint64_t>& acc) {
  std::vector<uint32_t> out(acc.size());
  for (size_t i = 0; i < acc.size(); ++i) {
    out[i] = static_cast<uint32_t>(std::min<uint64_t>(acc[i], shape.acc_max()));
  }
  return out;
}

// Clocks a frame through the model: random input gaps, a random read each
// cycle (results unchanged by it), then idle until the clear sweep is done.
// Returns the cycles from the first beat to tready after the trailer.
uint64_t clock_frame(Hough& h, const std::vector<uint64_t>& edges, uint64_t trailer,
                     const HoughConfig& cfg, std::mt19937_64& rng, double gap_prob) {
  std::bernoulli_distribution gap(gap_prob);
  std::uniform_int_distribution<uint32_t> idx(0, (1u << h.shape().index_bits()) - 1);
  uint64_t cycles = 0;
  size_t i = 0;
  bool trailer_sent = false;
  while (!trailer_sent) {
    EdgeBeat b;
    if (!gap(rng)) {
      b.tvalid = true;
      b.tlast = i == edges.size();
      b.tdata = b.tlast ? trailer : edges[i];
    }
    const bool taken = b.tvalid && h.tready();
    h.clock(b, cfg, true, idx(rng));
    ++cycles;
    if (taken) {
      trailer_sent = b.tlast;
      ++i;
    }
  }
  while (!(h.state() == Hough::State::kIdle)) {
    h.clock(EdgeBeat{}, cfg);
    ++cycles;
  }
  return cycles;
}

void idle_until_ready(Hough& h) {
  while (h.state() != Hough::State::kIdle) {
    h.clock(EdgeBeat{}, HoughConfig{});
  }
}

std::vector<EdgePoint> random_points(std::mt19937_64& rng, int n, int w, int h) {
  std::uniform_int_distribution<int> ux(0, w - 1);
  std::uniform_int_distribution<int> uy(0, h - 1);
  std::vector<EdgePoint> p;
  for (int i = 0; i < n; ++i) {
    p.push_back({static_cast<uint16_t>(ux(rng)), static_cast<uint16_t>(uy(rng))});
    if (!p.empty() && i % 7 == 3) {
      p.push_back(p.back());  // repeated point: two votes into each of its cells
    }
  }
  return p;
}

HoughConfig random_config(std::mt19937_64& rng, const HoughShape& shape, int width) {
  HoughConfig cfg;
  cfg.unit_weight = std::bernoulli_distribution(0.3)(rng);
  cfg.weight_shift = static_cast<uint8_t>(std::uniform_int_distribution<int>(0, 6)(rng));
  cfg.rho_shift = static_cast<uint8_t>(std::uniform_int_distribution<int>(0, 4)(rng));
  cfg.theta_first =
      static_cast<uint8_t>(std::uniform_int_distribution<int>(0, shape.n_theta() + 2)(rng) % 256);
  cfg.theta_count = static_cast<uint8_t>(std::uniform_int_distribution<int>(0, 200)(rng));
  if (std::bernoulli_distribution(0.3)(rng)) {
    cfg.theta_count = static_cast<uint8_t>(std::uniform_int_distribution<int>(1, 3)(rng));
  }
  cfg.width = static_cast<uint16_t>(width);
  return cfg;
}

const HoughShape kShapes[] = {{4, 4, 6, 16}, {8, 1, 9, 20}, {2, 6, 7, 10}};

TEST(Hough, ClockedEqualsFastEqualsGoldenOnRandomFrames) {
  std::mt19937_64 rng(0x4A0F01);
  for (const HoughShape& shape : kShapes) {
    Hough clocked(shape);
    Hough fast(shape);
    idle_until_ready(clocked);
    for (int frame = 0; frame < 12; ++frame) {
      const int w = std::uniform_int_distribution<int>(1, 400)(rng);
      const int hh = std::uniform_int_distribution<int>(1, 300)(rng);
      const auto pts = random_points(rng, std::uniform_int_distribution<int>(0, 150)(rng), w, hh);
      HoughConfig cfg = random_config(rng, shape, w);
      const uint64_t trailer = trailer_word(static_cast<uint32_t>(pts.size()), 0x00050001u);
      clock_frame(clocked, words_of(pts), trailer, cfg, rng, frame % 3 == 0 ? 0.0 : 0.3);
      fast.process_frame(words_of(pts), trailer, cfg);
      const auto gold = clipped(shape, golden::hough_ref(shape, cfg, pts));
      ASSERT_EQ(clocked.results(), gold) << "frame " << frame;
      ASSERT_EQ(fast.results(), gold) << "frame " << frame;
      ASSERT_EQ(clocked.counters(), fast.counters());
      const HoughCounters& c = clocked.counters();
      const ThetaRange r = theta_range(shape, cfg);
      EXPECT_EQ(c.edges, pts.size());
      EXPECT_EQ(c.bad_edges, 0u);
      EXPECT_EQ(uint64_t{c.votes} + c.dropped, uint64_t{c.edges} * static_cast<uint64_t>(r.count));
      EXPECT_EQ(c.trailer_edges, pts.size());
      EXPECT_EQ(c.trailer_flags, 0x00050001u);
    }
  }
}

TEST(Hough, SaturatesCellsAndCountsIt) {
  const HoughShape shape{4, 4, 6, 6};  // cells saturate at 63
  Hough h(shape);
  idle_until_ready(h);
  std::vector<EdgePoint> pts(30, EdgePoint{10, 99});  // weight 100 each
  HoughConfig cfg;
  cfg.width = 160;
  cfg.rho_shift = 3;
  std::mt19937_64 rng(7);
  clock_frame(h, words_of(pts), trailer_word(30, 0), cfg, rng, 0.2);
  const auto gold = clipped(shape, golden::hough_ref(shape, cfg, pts));
  EXPECT_EQ(h.results(), gold);
  EXPECT_EQ(*std::max_element(gold.begin(), gold.end()), 63u);
  EXPECT_EQ(h.counters().saturated, h.counters().votes);  // each vote (w = 100) saturates
  EXPECT_GT(h.counters().votes, 0u);
}

TEST(Hough, DropsAndCountsOutOfRangeAndBadEdges) {
  const HoughShape shape{4, 4, 6, 16};
  Hough h(shape);
  idle_until_ready(h);
  HoughConfig cfg;
  cfg.width = 0;  // negative rho (theta > 90 deg) falls below bin 0
  std::vector<uint64_t> edges = {edge_word(100, 5), edge_word(2048, 0), edge_word(0, 4000)};
  std::mt19937_64 rng(9);
  clock_frame(h, edges, trailer_word(3, 0), cfg, rng, 0.0);
  const HoughCounters& c = h.counters();
  EXPECT_EQ(c.edges, 1u);
  EXPECT_EQ(c.bad_edges, 2u);
  EXPECT_GT(c.dropped, 0u);
  EXPECT_EQ(c.votes + c.dropped, 45u);
  const auto gold = clipped(shape, golden::hough_ref(shape, cfg, {{100, 5}}));
  EXPECT_EQ(h.results(), gold);
}

TEST(Hough, ThroughputLatencyAndDoubleBuffer) {
  for (const HoughShape& shape : kShapes) {
    Hough h(shape);
    // After reset: a clear sweep of lane_words cycles, then ready.
    int cycles = 0;
    while (!h.tready()) {
      h.clock(EdgeBeat{}, HoughConfig{});
      ++cycles;
    }
    EXPECT_EQ(cycles, static_cast<int>(h.clear_cycles()));
    HoughConfig cfg;
    cfg.width = 100;
    const int per_edge = h.cycles_per_edge(cfg);
    EXPECT_EQ(per_edge, (shape.n_theta() + shape.lanes - 1) / shape.lanes);
    // Edges back to back: one accepted every per_edge cycles.
    std::vector<int> accepted_at;
    const int n_edges = 5;
    int sent = 0;
    int t = 0;
    while (sent <= n_edges) {
      EdgeBeat b;
      b.tvalid = true;
      b.tlast = sent == n_edges;
      b.tdata = b.tlast ? trailer_word(n_edges, 0) : edge_word(static_cast<uint16_t>(sent), 7);
      const bool taken = h.tready();
      h.clock(b, cfg);
      if (taken) {
        accepted_at.push_back(t);
        ++sent;
      }
      ++t;
    }
    for (size_t i = 1; i < accepted_at.size(); ++i) {
      EXPECT_EQ(accepted_at[i] - accepted_at[i - 1], per_edge);
    }
    // Trailer accepted on the edge that issues the last slot: SWAP until the
    // vote pipeline (stages T, M, R, B after the slot) writes that slot's
    // votes and counts their clips, Hough::kSwapEdges (5) edges; done after
    // the last, then the clear sweep, then ready.
    EXPECT_EQ(Hough::kSwapEdges, 5);
    for (int k = 1; k < Hough::kSwapEdges; ++k) {
      EXPECT_FALSE(h.done());
      EXPECT_EQ(h.state(), Hough::State::kSwap);
      h.clock(EdgeBeat{}, cfg);
    }
    EXPECT_FALSE(h.done());
    EXPECT_EQ(h.state(), Hough::State::kSwap);
    h.clock(EdgeBeat{}, cfg);
    EXPECT_TRUE(h.done());
    EXPECT_TRUE(h.results_valid());
    cycles = 0;
    while (!h.tready()) {
      h.clock(EdgeBeat{}, cfg);
      ++cycles;
    }
    EXPECT_EQ(cycles, static_cast<int>(h.clear_cycles()));
  }
}

// A trailer after `gap` idle cycles behind the last slot: the pipeline has
// drained by gap edges, so the publication comes max(1, kSwapEdges - gap)
// edges after the trailer is accepted, the results equal the golden.
TEST(Hough, PublicationWaitsForTheVotePipeline) {
  const HoughShape shape{4, 4, 6, 16};
  HoughConfig cfg;
  cfg.width = 100;
  const std::vector<EdgePoint> pts{{10, 20}, {10, 20}, {30, 7}};
  const auto gold = clipped(shape, golden::hough_ref(shape, cfg, pts));
  for (int gap = 0; gap <= Hough::kSwapEdges + 1; ++gap) {
    Hough h(shape);
    idle_until_ready(h);
    for (const uint64_t w : words_of(pts)) {
      ASSERT_TRUE(h.tready());
      h.clock(EdgeBeat{true, false, w}, cfg);
      while (!h.tready()) {
        h.clock(EdgeBeat{}, cfg);
      }
    }
    // tready is high in the last slot: the trailer (or the first idle cycle)
    // comes on the edge that issues it.
    for (int g = 0; g < gap; ++g) {
      h.clock(EdgeBeat{}, cfg);
    }
    h.clock(EdgeBeat{true, true, trailer_word(3, 0)}, cfg);
    int edges = 0;
    while (!h.done()) {
      ASSERT_EQ(h.state(), Hough::State::kSwap) << "gap " << gap;
      h.clock(EdgeBeat{}, cfg);
      ++edges;
    }
    EXPECT_EQ(edges, std::max(1, Hough::kSwapEdges - gap)) << "gap " << gap;
    EXPECT_EQ(h.results(), gold) << "gap " << gap;
    EXPECT_EQ(h.counters().votes + h.counters().dropped, 3u * 45u);
  }
}

TEST(Hough, ReadoutOfOneFrameRacesTheNextFramesVoting) {
  const HoughShape shape{4, 4, 6, 16};
  Hough h(shape);
  idle_until_ready(h);
  std::mt19937_64 rng(11);
  HoughConfig cfg;
  cfg.width = 200;
  cfg.rho_shift = 3;
  const auto a = random_points(rng, 60, 200, 150);
  const auto b = random_points(rng, 60, 200, 150);
  clock_frame(h, words_of(a), trailer_word(60, 0), cfg, rng, 0.0);
  const auto gold_a = clipped(shape, golden::hough_ref(shape, cfg, a));
  ASSERT_EQ(h.results(), gold_a);
  // Frame b votes while the port reads frame a, cell by cell.
  const auto words_b = words_of(b);
  size_t i = 0;
  uint32_t index = 0;
  int reads = 0;
  while (i <= words_b.size()) {
    EdgeBeat beat;
    beat.tvalid = true;
    beat.tlast = i == words_b.size();
    beat.tdata = beat.tlast ? trailer_word(60, 0) : words_b[i];
    const bool taken = h.tready();
    const uint32_t j = index >> shape.rho_bits;
    const uint32_t want = j < static_cast<uint32_t>(shape.n_theta())
                              ? gold_a[j * shape.rho_bins() + (index & (shape.rho_bins() - 1))]
                              : 0u;
    // Up to the trailer's edge the port reads frame a.
    h.clock(beat, cfg, true, index);
    ASSERT_EQ(h.rd_data(), want) << "index " << index;
    ++reads;
    index = (index + 1) & ((1u << shape.index_bits()) - 1);
    if (taken) {
      ++i;
    }
  }
  EXPECT_GT(reads, 500);
  idle_until_ready(h);
  EXPECT_EQ(h.results(), clipped(shape, golden::hough_ref(shape, cfg, b)));
}

TEST(Hough, GoldenPeaksAgreeWithDoubleAndOpenCvWithinOneBin) {
  const HoughShape shape{4, 1, 10, 24};  // 1 degree, 1024 rho bins
  struct Line {
    double rho;
    double theta;
  };
  const Line lines[] = {{120.0, 0.0},  {80.5, 30.0},  {150.0, 90.0}, {-60.0, 120.0},
                        {200.0, 45.0}, {10.0, 170.0}, {100.0, 60.0}, {-20.0, 100.0}};
  const int w = 320;
  const int hh = 240;
  int compared = 0;
  for (const Line& line : lines) {
    auto pts = golden::line_points(line.rho, line.theta, w, hh);
    ASSERT_GT(pts.size(), 50u);
    HoughConfig cfg;
    cfg.unit_weight = true;
    cfg.width = w;
    cfg.rho_shift = 1;
    const auto q = golden::hough_ref(shape, cfg, pts);
    const auto d = golden::hough_ref_double(shape, cfg, pts);
    const golden::HoughPeak pq = golden::hough_peak(shape, cfg, q);
    const golden::HoughPeak pd = golden::hough_peak(shape, cfg, d);
    const double bin = std::ldexp(1.0, cfg.rho_shift);
    const double theta_bin = shape.theta_step * std::numbers::pi / 180.0;
    EXPECT_LE(std::abs(pq.rho - pd.rho), bin) << line.rho << " " << line.theta;
    EXPECT_LE(std::abs(pq.theta - pd.theta), theta_bin * 1.0001);
    EXPECT_GE(pq.votes + 2, pd.votes);
    // The cells differ by at most a few votes (points within 0.125 px of a
    // bin boundary move to the next bin).
    const golden::HoughPeak cv = golden::opencv_strongest_line(shape, cfg, pts, w, hh);
    // OpenCV's rho is signed without bias; its bins are centred on multiples
    // of the step, ours start at them: compare in pixels.
    double dtheta = std::abs(pq.theta - cv.theta);
    double cv_rho = cv.rho;
    if (dtheta > std::numbers::pi / 2) {  // theta near 0 vs near 180: rho flips
      dtheta = std::numbers::pi - dtheta;
      cv_rho = -cv_rho;
    }
    EXPECT_LE(dtheta, theta_bin * 1.0001) << line.rho << " " << line.theta;
    EXPECT_LE(std::abs(pq.rho - cv_rho), bin) << line.rho << " " << line.theta;
    EXPECT_NEAR(pq.theta, line.theta * std::numbers::pi / 180.0, theta_bin * 1.0001);
    EXPECT_LE(std::abs(pq.rho - line.rho), bin);
    ++compared;
  }
  EXPECT_EQ(compared, 8);
}

// docs/fixedpoint.md, "hough cos/sin table": the rho index from the s1.14
// table differs from round((x cos + y sin + W) / 2^s) in real arithmetic only
// where that value lies within (x + y) 2^-15 < 0.125 pixel of a bin edge, and
// then by one bin.
TEST(Hough, QuantisedRhoIndexWithinDerivedBound) {
  const HoughShape shape{4, 1, 12, 16};
  std::mt19937_64 rng(0x4A0F02);
  std::uniform_int_distribution<uint32_t> coord(0, 2047);
  std::uniform_int_distribution<int> deg(0, 179);
  std::uniform_int_distribution<int> shift(1, 3);  // 2^12 bins hold rho + W / 2
  int differ = 0;
  for (int n = 0; n < 200000; ++n) {
    HoughConfig cfg;
    cfg.width = 2048;
    cfg.rho_shift = static_cast<uint8_t>(shift(rng));
    const uint32_t x = coord(rng);
    const uint32_t y = coord(rng);
    const int k = deg(rng);
    uint32_t idx = 0;
    ASSERT_TRUE(hough_rho_index(shape, cfg, x, y, k, idx));
    const double t = k * std::numbers::pi / 180.0;
    const double exact = std::ldexp(x * std::cos(t) + y * std::sin(t) + cfg.width, -cfg.rho_shift);
    const double real_idx = std::floor(exact + 0.5);
    if (static_cast<double>(idx) != real_idx) {
      ++differ;
      ASSERT_LE(std::abs(static_cast<double>(idx) - real_idx), 1.0);
      // distance of the exact rho to the bin edge, in pixels
      const double edge_dist =
          std::ldexp(std::abs(exact + 0.5 - std::round(exact + 0.5)), cfg.rho_shift);
      ASSERT_LE(edge_dist, (x + y) * std::ldexp(1.0, -15) + 1e-9) << x << " " << y << " " << k;
    }
  }
  EXPECT_LT(differ, 200000 / 20);  // rare: only near bin edges
}

TEST(Hough, WeightFollowsEquation18) {
  HoughConfig cfg;
  // Row r counted from the bottom (0-based): row - r = y + 1.
  EXPECT_EQ(hough_weight(cfg, 0), 1u);
  EXPECT_EQ(hough_weight(cfg, 2047), 2048u);
  cfg.weight_shift = 3;
  EXPECT_EQ(hough_weight(cfg, 7), 1u);
  EXPECT_EQ(hough_weight(cfg, 6), 0u);
  EXPECT_EQ(hough_weight(cfg, 239), 30u);
  cfg.unit_weight = true;
  EXPECT_EQ(hough_weight(cfg, 239), 1u);
}

}  // namespace
}  // namespace ceilnav::stream
