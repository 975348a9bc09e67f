// Per-block throughput of the bit-true C++ models on a random 640x480 frame
// (stream/tests/beat_source.hpp): the run scanner's and moment generator's
// frame-at-a-time paths and the moment generator's cycle model. Before any
// timing, main() checks each model's result against the golden reference; a
// mismatch exits 1. Figures: docs/performance.md.
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>

#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "golden/moment_gen_ref.hpp"
#include "golden/run_scanner_ref.hpp"
#include "stream/moment_gen.hpp"
#include "stream/run_scanner.hpp"
#include "stream/tests/beat_source.hpp"

namespace ceilnav::stream {
namespace {

constexpr uint16_t kWidth = 640;
constexpr uint16_t kHeight = 480;

const test::LutFrame& frame() {
  static const test::LutFrame f = [] {
    std::mt19937 rng(3);
    return test::random_frame(rng, kWidth, kHeight);
  }();
  return f;
}

MomentResults moments_fast(const test::LutFrame& f) {
  MomentGen::FrameSums sums;
  for (uint32_t y = 0; y < f.height; ++y) {
    MomentGen::accumulate_row(sums, y, f.remap_row(y), f.mask_row(y), f.width);
  }
  return MomentGen::finish(sums);
}

cv::Mat plane(const std::vector<uint8_t>& v, const test::LutFrame& f) {
  return cv::Mat(f.height, f.width, CV_8UC1, const_cast<uint8_t*>(v.data())).clone();
}

MomentResults moments_golden(const test::LutFrame& f) {
  return golden::moments_ref(plane(f.remap, f), plane(f.mask, f));
}

std::vector<RunRecord> runs_fast(const test::LutFrame& f, const RunScanConfig& c) {
  std::vector<RunRecord> runs;
  uint32_t dropped = 0;
  for (uint32_t y = 0; y < f.height; ++y) {
    RunScanner::scan_row(c, static_cast<uint16_t>(y), f.remap_row(y), f.mask_row(y), f.width, runs,
                         dropped);
  }
  return runs;
}

constexpr RunScanConfig kRunScan{20, 1, 64};

std::vector<LutBeat> moment_beats(const test::LutFrame& f) {
  std::mt19937 rng(4);
  std::vector<LutBeat> beats;
  test::append_frame(beats, f, rng, 0.0);
  test::append_idle(beats, MomentGen::kCombineCycles);
  return beats;
}

// Items = pixels (fast paths) or clock cycles (cycle model) per second.
void set_items(benchmark::State& state, size_t items_per_iteration) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(items_per_iteration));
}

// The three models against golden on the benchmark frame.
bool models_match_golden() {
  const test::LutFrame& f = frame();
  const golden::RunScanParams p{kRunScan.background_level, kRunScan.min_run_length,
                                kRunScan.max_runs_per_row};
  bool ok = true;
  if (runs_fast(f, kRunScan) != golden::find_runs_ref(plane(f.remap, f), plane(f.mask, f), p)) {
    std::fprintf(stderr, "run scanner fast path differs from golden\n");
    ok = false;
  }
  const MomentResults g = moments_golden(f);
  if (!(moments_fast(f) == g)) {
    std::fprintf(stderr, "moment_gen fast path differs from golden\n");
    ok = false;
  }
  MomentGen gen;
  for (const LutBeat& b : moment_beats(f)) gen.clock(b);
  if (!(gen.results() == g)) {
    std::fprintf(stderr, "moment_gen cycle model differs from golden\n");
    ok = false;
  }
  return ok;
}

void BM_RunScannerFastPath(benchmark::State& state) {
  const test::LutFrame& f = frame();
  for (auto _ : state) benchmark::DoNotOptimize(runs_fast(f, kRunScan));
  set_items(state, f.pixels());
}
BENCHMARK(BM_RunScannerFastPath)->Unit(benchmark::kMillisecond);

void BM_MomentGenFastPath(benchmark::State& state) {
  const test::LutFrame& f = frame();
  for (auto _ : state) benchmark::DoNotOptimize(moments_fast(f));
  set_items(state, f.pixels());
}
BENCHMARK(BM_MomentGenFastPath)->Unit(benchmark::kMillisecond);

// One frame plus the combine's idle cycles through MomentGen::clock per iteration.
void BM_MomentGenClocked(benchmark::State& state) {
  const std::vector<LutBeat> beats = moment_beats(frame());
  MomentGen gen;
  for (auto _ : state) {
    for (const LutBeat& b : beats) gen.clock(b);
    benchmark::DoNotOptimize(gen.results());
  }
  set_items(state, beats.size());
}
BENCHMARK(BM_MomentGenClocked)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ceilnav::stream

int main(int argc, char** argv) {
  if (!ceilnav::stream::models_match_golden()) return 1;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
