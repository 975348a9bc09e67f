// run_scanner: clocked == fast == golden (find_runs_ref), exactly; FIFO,
// back-pressure, trailers, aborts, zero blanking.
#include "stream/run_scanner.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <random>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "golden/run_scanner_ref.hpp"
#include "stream/tests/beat_source.hpp"

namespace ceilnav::stream {
namespace {

using test::LutFrame;

cv::Mat plane_mat(const std::vector<uint8_t>& v, uint16_t w, uint16_t h) {
  return cv::Mat(h, w, CV_8UC1, const_cast<uint8_t*>(v.data())).clone();
}

golden::RunScanParams params(const RunScanConfig& c) {
  return {c.background_level, c.min_run_length, c.max_runs_per_row};
}

struct FrameRuns {
  std::vector<RunRecord> runs;
  uint32_t dropped_row_limit = 0;
};

FrameRuns golden_runs(const LutFrame& f, const RunScanConfig& c) {
  FrameRuns r;
  r.runs =
      golden::find_runs_ref(plane_mat(f.remap, f.width, f.height),
                            plane_mat(f.mask, f.width, f.height), params(c), &r.dropped_row_limit);
  return r;
}

FrameRuns fast_runs(const LutFrame& f, const RunScanConfig& c) {
  FrameRuns r;
  for (uint32_t y = 0; y < f.height; ++y) {
    RunScanner::scan_row(c, static_cast<uint16_t>(y), f.remap_row(y), f.mask_row(y), f.width,
                         r.runs, r.dropped_row_limit);
  }
  return r;
}

// Everything the m_axis_runs consumer saw, split into frames at tlast.
struct Received {
  std::vector<std::vector<RunRecord>> runs;  // per trailer
  std::vector<RunRecord> trailers;
  std::vector<RunStats> stats;  // at every done pulse
  uint32_t max_occupancy = 0;
};

// Clocks the beats (then idle until the FIFO drains), with the consumer's
// tready from `ready` (called once per cycle). Checks the AXI-Stream rule
// that tvalid/tdata hold while tvalid && !tready.
// cfgs[k] is put on the config port before the k-th SOF beat.
Received run_clocked(RunScanner& rs, const std::vector<LutBeat>& beats,
                     const std::vector<RunScanConfig>& cfgs, const std::function<bool()>& ready,
                     size_t max_tail = 1000000) {
  size_t sof_count = 0;
  Received rx;
  std::vector<RunRecord> current;
  RunBeat prev{};
  bool prev_stalled = false;
  const LutBeat idle{};
  for (size_t i = 0; i < beats.size() + max_tail; ++i) {
    const bool done_feeding = i >= beats.size();
    const RunBeat out = rs.m_axis_runs();
    if (prev_stalled) {
      EXPECT_EQ(out, prev) << "m_axis changed while stalled, cycle " << i;
    }
    const bool tready = done_feeding || ready();
    if (out.tvalid && tready) {
      if (out.tlast) {
        rx.runs.push_back(current);
        rx.trailers.push_back(out.tdata);
        current.clear();
      } else {
        current.push_back(out.tdata);
      }
    }
    prev = out;
    prev_stalled = out.tvalid && !tready;
    const LutBeat& in = done_feeding ? idle : beats[i];
    if (in.pix.valid && in.pix.sof) rs.set_active_config(cfgs.at(sof_count++));
    rs.clock(in, tready);
    rx.max_occupancy = std::max(rx.max_occupancy, rs.fifo_occupancy());
    if (rs.done()) rx.stats.push_back(rs.last_frame_stats());
    if (done_feeding && rs.fifo_occupancy() == 0 && !rs.m_axis_runs().tvalid) break;
  }
  EXPECT_TRUE(current.empty()) << "runs after the last trailer";
  return rx;
}

RunScanConfig random_config(std::mt19937& rng) {
  std::uniform_int_distribution<int> bg(0, 255);
  std::uniform_int_distribution<int> min_len(0, 6);
  std::uniform_int_distribution<int> max_runs(0, 12);
  return {static_cast<uint8_t>(bg(rng) / 2), static_cast<uint16_t>(min_len(rng)),
          static_cast<uint16_t>(max_runs(rng) == 12 ? 0xFFFF : max_runs(rng))};
}

uint16_t flags_for(const RunStats& s) {
  uint16_t f = 0;
  if (s.runs_dropped_row_limit != 0) f |= kTrailerRowLimitHit;
  if (s.runs_dropped_overflow != 0) f |= kTrailerFifoOverflow;
  return f;
}

bool is_subsequence(const std::vector<RunRecord>& sub, const std::vector<RunRecord>& all) {
  size_t j = 0;
  for (const RunRecord& r : all) {
    if (j < sub.size() && sub[j] == r) ++j;
  }
  return j == sub.size();
}

// Mask = 1 with probability p per pixel: many short runs.
LutFrame salt_frame(std::mt19937& rng, uint16_t w, uint16_t h, double p) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::bernoulli_distribution on(p);
  LutFrame f{w, h, {}, {}, {}};
  for (size_t i = 0; i < f.pixels(); ++i) {
    f.remap.push_back(static_cast<uint8_t>(byte(rng)));
    f.mask.push_back(on(rng) ? 1 : 0);
  }
  return f;
}

bool always() {
  return true;
}

std::array<LutEntry, 256> random_lut(std::mt19937& rng) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::array<LutEntry, 256> lut{};
  const int threshold = std::uniform_int_distribution<int>(64, 192)(rng);  // inside photos' range
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = lut_entry(static_cast<uint8_t>(byte(rng)), g >= threshold);
  }
  return lut;
}

TEST(RunScanner, RandomSizesWithGapsClockedFastGolden) {
  std::mt19937 rng(424242);
  std::vector<std::pair<uint16_t, uint16_t>> sizes = {{1, 1},   {1, 37}, {53, 1},    {1, 200},
                                                      {640, 1}, {2, 2},  {640, 480}, {2, 9}};
  std::uniform_int_distribution<int> small(1, 80);
  for (int i = 0; i < 40; ++i) sizes.emplace_back(small(rng), small(rng));
  std::uniform_real_distribution<double> gap_p(0.0, 0.5);
  std::uniform_int_distribution<int> blank(0, 3);

  std::vector<LutBeat> beats;
  std::vector<FrameRuns> expected;
  std::vector<RunScanConfig> configs;
  for (const auto& [w, h] : sizes) {
    const LutFrame f = test::random_frame(rng, w, h);
    const RunScanConfig c = random_config(rng);
    const FrameRuns g = golden_runs(f, c);
    const FrameRuns fr = fast_runs(f, c);
    ASSERT_EQ(fr.runs, g.runs) << w << "x" << h;
    ASSERT_EQ(fr.dropped_row_limit, g.dropped_row_limit);
    expected.push_back(g);
    configs.push_back(c);
    test::append_frame(beats, f, rng, gap_p(rng));
    test::append_idle(beats, static_cast<size_t>(blank(rng)));  // often zero blanking
  }
  RunScanner rs;  // depth 1024 and a consumer that is always ready: nothing is lost
  const Received rx = run_clocked(rs, beats, configs, always);
  ASSERT_EQ(rx.trailers.size(), expected.size());
  ASSERT_EQ(rx.stats.size(), expected.size());
  size_t total = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    const FrameRuns& g = expected[i];
    total += g.runs.size();
    EXPECT_EQ(rx.runs[i], g.runs) << "frame " << i;
    EXPECT_EQ(rx.trailers[i].row, std::min<size_t>(g.runs.size(), 0xFFFF));
    EXPECT_EQ(rx.trailers[i].x_start, g.dropped_row_limit != 0 ? kTrailerRowLimitHit : 0);
    EXPECT_EQ(rx.stats[i].runs_emitted, g.runs.size());
    EXPECT_EQ(rx.stats[i].runs_dropped_row_limit, g.dropped_row_limit);
    EXPECT_EQ(rx.stats[i].runs_dropped_overflow, 0u);
    EXPECT_LE(rx.stats[i].fifo_high_water, rx.max_occupancy);
  }
  EXPECT_GT(total, 1000u);
  EXPECT_EQ(rs.trailers_lost(), 0u);
}

TEST(RunScanner, RealPhotosWithRandomLut) {
  const std::filesystem::path dir = "/usr/share/doc/opencv-doc/examples/data";
  std::mt19937 rng(77);
  for (const char* name : {"building.jpg", "baboon.jpg", "fruits.jpg"}) {
    const cv::Mat img = cv::imread((dir / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty()) << name;
    ASSERT_TRUE(img.isContinuous());
    const LutFrame f = LutFrame::from_grey(std::vector<uint8_t>(img.datastart, img.dataend),
                                           static_cast<uint16_t>(img.cols),
                                           static_cast<uint16_t>(img.rows), random_lut(rng));
    const RunScanConfig c{40, 2, 16};
    const FrameRuns g = golden_runs(f, c);
    const FrameRuns fr = fast_runs(f, c);
    EXPECT_EQ(fr.runs, g.runs) << name;
    EXPECT_EQ(fr.dropped_row_limit, g.dropped_row_limit) << name;
    std::vector<LutBeat> beats;
    test::append_frame(beats, f, rng, 0.1);
    RunScanner rs(4096);
    const Received rx = run_clocked(rs, beats, {c}, always);
    ASSERT_EQ(rx.trailers.size(), 1u) << name;
    EXPECT_EQ(rx.runs[0], g.runs) << name;
    EXPECT_GT(g.runs.size(), 100u) << name;
  }
}

TEST(RunScanner, MarginSumsAtLineEndsByHand) {
  // w = remap - 5: 5 15 25 35 45 55.
  LutFrame f{6, 1, {}, {10, 20, 30, 40, 50, 60}, {1, 1, 0, 0, 1, 1}};
  const RunScanConfig c{5, 1, 8};
  // Run 0..1: clipped on the left, right margin x = 2.
  // Run 4..5: left margin x = 3, clipped on the right.
  const std::vector<RunRecord> hand = {{0, 0, 1, 5 + 15 + 25, 0 * 5 + 1 * 15 + 2 * 25},
                                       {0, 4, 5, 35 + 45 + 55, 3 * 35 + 4 * 45 + 5 * 55}};
  EXPECT_EQ(golden_runs(f, c).runs, hand);
  EXPECT_EQ(fast_runs(f, c).runs, hand);
  std::mt19937 rng(0);
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, 0.5);
  RunScanner rs;
  const Received rx = run_clocked(rs, beats, {c}, always);
  ASSERT_EQ(rx.runs.size(), 1u);
  EXPECT_EQ(rx.runs[0], hand);
  // Background above every pixel: w = 0, the runs stay with zero sums.
  const RunScanConfig dark{200, 1, 8};
  const std::vector<RunRecord> zero = {{0, 0, 1, 0, 0}, {0, 4, 5, 0, 0}};
  EXPECT_EQ(golden_runs(f, dark).runs, zero);
  EXPECT_EQ(fast_runs(f, dark).runs, zero);
}

TEST(RunScanner, MinRunLengthAndRowLimitEdges) {
  // Row: runs of length 2, 3, 4, 1 (the last touches x = width-1).
  const std::vector<uint8_t> m = {1, 1, 0, 1, 1, 1, 0, 0, 1, 1, 1, 1, 0, 1};
  LutFrame f{static_cast<uint16_t>(m.size()), 3, {}, {}, {}};
  for (int r = 0; r < 3; ++r) {
    f.mask.insert(f.mask.end(), m.begin(), m.end());
    for (size_t x = 0; x < m.size(); ++x)
      f.remap.push_back(static_cast<uint8_t>(17 * x + static_cast<size_t>(r)));
  }
  struct Case {
    uint16_t min_len, max_runs;
    size_t runs_per_row;
    uint32_t dropped_per_row;
  };
  const uint16_t w = f.width;
  const std::vector<Case> cases = {{0, 0xFFFF, 4, 0}, {1, 0xFFFF, 4, 0},      {2, 0xFFFF, 3, 0},
                                   {3, 0xFFFF, 2, 0}, {4, 0xFFFF, 1, 0},      {5, 0xFFFF, 0, 0},
                                   {w, 0xFFFF, 0, 0}, {0xFFFF, 0xFFFF, 0, 0}, {1, 0, 0, 4},
                                   {1, 1, 1, 3},      {1, 4, 4, 0},           {3, 1, 1, 1},
                                   {2, 2, 2, 1}};
  for (const Case& k : cases) {
    const RunScanConfig c{0, k.min_len, k.max_runs};
    const FrameRuns g = golden_runs(f, c);
    EXPECT_EQ(g.runs.size(), 3 * k.runs_per_row) << k.min_len << " " << k.max_runs;
    EXPECT_EQ(g.dropped_row_limit, 3 * k.dropped_per_row) << k.min_len << " " << k.max_runs;
    const FrameRuns fr = fast_runs(f, c);
    EXPECT_EQ(fr.runs, g.runs);
    EXPECT_EQ(fr.dropped_row_limit, g.dropped_row_limit);
    std::mt19937 rng(k.min_len + 7u * k.max_runs);
    std::vector<LutBeat> beats;
    test::append_frame(beats, f, rng, 0.2);
    RunScanner rs;
    const Received rx = run_clocked(rs, beats, {c}, always);
    ASSERT_EQ(rx.runs.size(), 1u);
    EXPECT_EQ(rx.runs[0], g.runs);
    ASSERT_EQ(rx.stats.size(), 1u);
    EXPECT_EQ(rx.stats[0].runs_dropped_row_limit, g.dropped_row_limit);
    EXPECT_EQ(rx.trailers[0].x_start, g.dropped_row_limit ? kTrailerRowLimitHit : 0);
  }
}

TEST(RunScanner, BackPressureSmallFifoOverflowIsExact) {
  std::mt19937 rng(99);
  uint64_t total_overflow = 0;
  for (uint32_t depth : {2u, 3u, 5u, 16u}) {
    for (double p_ready : {0.05, 0.3, 0.9}) {
      std::bernoulli_distribution ready_coin(p_ready);
      std::vector<LutBeat> beats;
      std::vector<FrameRuns> expected;
      std::vector<RunScanConfig> configs;
      for (int i = 0; i < 6; ++i) {
        const LutFrame f = salt_frame(rng, 48, 12, 0.6);
        RunScanConfig c = random_config(rng);
        if (i % 2 == 0) c.max_runs_per_row = 0xFFFF;
        expected.push_back(golden_runs(f, c));
        configs.push_back(c);
        test::append_frame(beats, f, rng, 0.1);  // zero blanking between frames
      }
      RunScanner rs(depth);
      const Received rx = run_clocked(rs, beats, configs, [&] { return ready_coin(rng); });
      ASSERT_EQ(rs.trailers_lost(), 0u);
      ASSERT_EQ(rx.trailers.size(), expected.size());
      ASSERT_EQ(rx.stats.size(), expected.size());
      EXPECT_LE(rx.max_occupancy, depth);
      for (size_t i = 0; i < expected.size(); ++i) {
        const auto& got = rx.runs[i];
        const auto& want = expected[i].runs;
        const RunStats& s = rx.stats[i];
        EXPECT_TRUE(is_subsequence(got, want)) << depth << " " << p_ready << " frame " << i;
        EXPECT_EQ(s.runs_emitted, got.size());
        EXPECT_EQ(s.runs_dropped_overflow, want.size() - got.size());
        EXPECT_EQ(s.runs_dropped_row_limit, expected[i].dropped_row_limit);
        EXPECT_LE(s.fifo_high_water, depth);
        EXPECT_EQ(rx.trailers[i].row, got.size());
        EXPECT_EQ(rx.trailers[i].x_start, flags_for(s));
        total_overflow += s.runs_dropped_overflow;
      }
    }
  }
  EXPECT_GT(total_overflow, 100u);
}

TEST(RunScanner, StalledConsumerLosesTrailersCountedAndFlagged) {
  // tready = 0 for the first frames: the FIFO fills with runs, then with
  // trailers; a trailer that finds it full is lost, counted, and the next
  // stored trailer says overflow.
  std::mt19937 rng(4);
  const uint32_t depth = 4;
  const int frames = 12;
  std::vector<LutBeat> beats;
  std::vector<RunRecord> all_runs;
  std::vector<RunScanConfig> configs;
  for (int i = 0; i < frames; ++i) {
    const LutFrame f = test::random_frame(rng, 20, 6);
    const RunScanConfig c{0, 1, 0xFFFF};
    const FrameRuns g = golden_runs(f, c);
    all_runs.insert(all_runs.end(), g.runs.begin(), g.runs.end());
    configs.push_back(c);
    test::append_frame(beats, f, rng, 0.0);
  }
  size_t cycle = 0;
  const size_t stall_cycles = beats.size() * 3 / 4;
  RunScanner rs(depth);
  const Received rx = run_clocked(rs, beats, configs, [&] { return cycle++ >= stall_cycles; });
  EXPECT_GT(rs.trailers_lost(), 0u);
  EXPECT_EQ(rx.trailers.size() + rs.trailers_lost(), static_cast<size_t>(frames));
  std::vector<RunRecord> got;
  for (const auto& r : rx.runs) got.insert(got.end(), r.begin(), r.end());
  EXPECT_TRUE(is_subsequence(got, all_runs));
  // The first trailers fit; once one is lost every stored trailer until the
  // consumer catches up carries the overflow flag (its runs were dropped too).
  size_t flagged = 0;
  for (const auto& t : rx.trailers) flagged += (t.x_start & kTrailerFifoOverflow) != 0;
  EXPECT_GE(flagged, 1u);
  EXPECT_EQ(rx.stats.size(), static_cast<size_t>(frames));
}

TEST(RunScanner, LostTrailerFlagsTheNextStoredTrailer) {
  // Frames without runs: only trailers enter the FIFO, so an overflow flag can
  // come from a lost trailer only.
  const LutFrame f{3, 1, {}, {1, 2, 3}, {0, 0, 0}};
  const int frames = 20;
  std::vector<LutBeat> beats;
  std::mt19937 rng(0);
  for (int i = 0; i < frames; ++i) test::append_frame(beats, f, rng, 0.0);
  size_t cycle = 0;
  const size_t stall_cycles = 3 * 10;  // 10 frames with tready = 0
  RunScanner rs(2);
  const Received rx = run_clocked(rs, beats, std::vector<RunScanConfig>(frames),
                                  [&] { return cycle++ >= stall_cycles; });
  // Out register + 2 memory entries hold 3 trailers; 7 of the stalled frames lose theirs.
  EXPECT_EQ(rs.trailers_lost(), 7u);
  ASSERT_EQ(rx.trailers.size(), static_cast<size_t>(frames) - 7);
  for (size_t i = 0; i < rx.trailers.size(); ++i) {
    EXPECT_EQ(rx.trailers[i].row, 0);
    EXPECT_EQ(rx.trailers[i].x_start, i == 3 ? kTrailerFifoOverflow : 0) << i;
  }
}

// Golden runs of the pixels delivered before an abort after `a` pixels: whole
// rows, plus the part of the cut row up to the last run that ended there.
FrameRuns golden_prefix(const LutFrame& f, const RunScanConfig& c, size_t a) {
  const uint16_t rows = static_cast<uint16_t>(a / f.width);
  size_t cut = a % f.width;
  FrameRuns r;
  if (rows > 0) {
    LutFrame top{f.width, rows, {}, {}, {}};
    top.remap.assign(f.remap.begin(), f.remap.begin() + static_cast<ptrdiff_t>(rows * f.width));
    top.mask.assign(f.mask.begin(), f.mask.begin() + static_cast<ptrdiff_t>(rows * f.width));
    r = golden_runs(top, c);
  }
  const uint8_t* mrow = f.mask_row(rows);
  while (cut > 0 && mrow[cut - 1] != 0) --cut;  // a run still open at the abort is lost
  if (rows < f.height && cut > 0) {
    LutFrame part{static_cast<uint16_t>(cut), 1, {}, {}, {}};
    part.remap.assign(f.remap_row(rows), f.remap_row(rows) + cut);
    part.mask.assign(mrow, mrow + cut);
    FrameRuns pr = golden_runs(part, c);
    for (RunRecord& run : pr.runs) run.row = rows;
    r.runs.insert(r.runs.end(), pr.runs.begin(), pr.runs.end());
    r.dropped_row_limit += pr.dropped_row_limit;
  }
  return r;
}

TEST(RunScanner, BackToBackZeroBlankingWithAborts) {
  std::mt19937 rng(2718);
  std::uniform_int_distribution<int> dim(1, 40);
  std::bernoulli_distribution abort_frame(0.35);
  std::vector<LutBeat> beats;
  std::vector<FrameRuns> expected;
  std::vector<bool> aborted;
  std::vector<RunScanConfig> configs;
  for (int i = 0; i < 60; ++i) {
    const LutFrame f =
        test::random_frame(rng, static_cast<uint16_t>(dim(rng)), static_cast<uint16_t>(dim(rng)));
    const RunScanConfig c = random_config(rng);
    configs.push_back(c);
    if (abort_frame(rng)) {
      std::uniform_int_distribution<size_t> at(0, f.pixels() - 1);
      const size_t a = at(rng);
      test::append_frame(beats, f, rng, 0.0, static_cast<int64_t>(a));
      if (a == 0) {  // no SOF was sent: no frame, no trailer
        configs.pop_back();
        continue;
      }
      expected.push_back(golden_prefix(f, c, a));
      aborted.push_back(true);
    } else {
      test::append_frame(beats, f, rng, 0.0);
      expected.push_back(golden_runs(f, c));
      aborted.push_back(false);
    }
  }
  ASSERT_GT(std::count(aborted.begin(), aborted.end(), true), 5);
  RunScanner rs;
  const Received rx = run_clocked(rs, beats, configs, always);
  ASSERT_EQ(rx.trailers.size(), expected.size());
  size_t good = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(rx.runs[i], expected[i].runs) << "frame " << i << " aborted " << aborted[i];
    uint16_t flags = expected[i].dropped_row_limit != 0 ? kTrailerRowLimitHit : 0;
    if (aborted[i]) {
      flags |= kTrailerFrameAborted;
    } else {
      ASSERT_LT(good, rx.stats.size());
      EXPECT_EQ(rx.stats[good].runs_emitted, expected[i].runs.size());
      EXPECT_EQ(rx.stats[good].runs_dropped_row_limit, expected[i].dropped_row_limit);
      ++good;
    }
    EXPECT_EQ(rx.trailers[i].x_start, flags) << "frame " << i;
    EXPECT_EQ(rx.trailers[i].row, expected[i].runs.size());
  }
  EXPECT_EQ(rx.stats.size(), good);  // stats (and done) only for completed frames
}

TEST(RunScanner, LatencyRunEndToTvalidIsTwoCycles) {
  LutFrame f{5, 1, {}, {9, 9, 9, 9, 9}, {0, 1, 0, 0, 0}};
  std::vector<LutBeat> beats;
  std::mt19937 rng(0);
  test::append_frame(beats, f, rng, 0.0);
  test::append_idle(beats, 6);
  RunScanner rs;
  rs.set_active_config(RunScanConfig{0, 1, 8});
  std::vector<RunBeat> seen;  // m_axis in cycle i (before edge i)
  for (const LutBeat& b : beats) {
    seen.push_back(rs.m_axis_runs());
    rs.clock(b, true);
  }
  // Run ends on the mask-0 pixel x = 2 (cycle 2): FIFO write at its edge,
  // output register at the next, tvalid in cycle 4; the trailer (EOF pixel in
  // cycle 4) follows in cycle 6.
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].tvalid, i == 4 || i == 6) << i;
  }
  EXPECT_EQ(seen[4].tdata, (RunRecord{0, 1, 1, 27, 9 * (0 + 1 + 2)}));
  EXPECT_FALSE(seen[4].tlast);
  EXPECT_TRUE(seen[6].tlast);
  EXPECT_EQ(seen[6].tdata.row, 1);
}

TEST(RunScanner, ConfigLatchedAtSofOnly) {
  LutFrame f{4, 2, {}, {50, 50, 50, 50, 50, 50, 50, 50}, {1, 1, 0, 0, 1, 0, 1, 0}};
  std::vector<LutBeat> beats;
  std::mt19937 rng(0);
  test::append_frame(beats, f, rng, 0.0);
  RunScanner rs;
  rs.set_active_config(RunScanConfig{10, 1, 8});
  rs.clock(beats[0], true);
  rs.set_active_config(RunScanConfig{0, 2, 0});  // changes after SOF: not used
  for (size_t i = 1; i < beats.size(); ++i) rs.clock(beats[i], true);
  for (int i = 0; i < 10; ++i) rs.clock(LutBeat{}, true);
  EXPECT_EQ(rs.last_frame_stats().runs_emitted, golden_runs(f, {10, 1, 8}).runs.size());
  EXPECT_EQ(rs.last_frame_stats().runs_dropped_row_limit, 0u);
}

TEST(RunScanner, HighWaterExactWithStalledConsumer) {
  // 2 rows of 1 0 1 0 ...: 10 runs. tready = 0 all frame: the first run sits
  // in the output register, the other 9 and the trailer fill the memory.
  LutFrame f{10, 2, {}, std::vector<uint8_t>(20, 7), {}};
  for (int i = 0; i < 20; ++i) f.mask.push_back(i % 2 == 0 ? 1 : 0);
  std::vector<LutBeat> beats;
  std::mt19937 rng(0);
  test::append_frame(beats, f, rng, 0.0);
  const size_t frame_cycles = beats.size();
  size_t cycle = 0;
  RunScanner rs(64);
  const Received rx = run_clocked(rs, beats, {RunScanConfig{0, 1, 0xFFFF}},
                                  [&] { return cycle++ >= frame_cycles; });
  ASSERT_EQ(rx.stats.size(), 1u);
  EXPECT_EQ(rx.stats[0].fifo_high_water, 10u);
  EXPECT_EQ(rx.stats[0].runs_emitted, 10u);
  ASSERT_EQ(rx.runs.size(), 1u);
  EXPECT_EQ(rx.runs[0], golden_runs(f, {0, 1, 0xFFFF}).runs);
}

// The frame of the throughput benchmark (bench/block_bench.cpp, BM_RunScannerFastPath).
TEST(RunScanner, FastPathEqualsGoldenOnARandomVgaFrame) {
  std::mt19937 rng(3);
  const LutFrame f = test::random_frame(rng, 640, 480);
  const RunScanConfig c{20, 1, 64};
  const FrameRuns r = fast_runs(f, c);
  EXPECT_GT(r.runs.size(), 100u);
  EXPECT_EQ(r.runs, golden_runs(f, c).runs);
}

}  // namespace
}  // namespace ceilnav::stream
