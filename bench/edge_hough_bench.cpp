// The edge -> hough path on 640 x 480 frames of seed 002's corridor
// (golden::corridor::render_frame of default_corridor(), default_pose() and
// four more poses), the default Hough shape (4 lanes, 4 degree theta step,
// 64 rho bins of 32 pixels: every rho of the frame lands in a bin), one core:
//   BM_EdgeHoughFast        stream::EdgeHoughFast::run (pixels in ->
//                           accumulator out)
//   BM_EdgeHoughCycleModels EdgeDetector::scan_frame + pack_edge_beat +
//                           Hough::process_frame (the cycle models' fast
//                           paths, saturating 16-bit cells)
//   BM_EdgeHoughGolden      golden::find_edges_ref + golden::hough_ref
//   BM_EdgeFast / BM_HoughVoteFast, BM_EdgeScanFrame / BM_HoughProcessFrame:
//                           the two halves alone.
//   BM_CorridorDeviceFrame  sim::CorridorDevice::process in the guidance's
//                           shape (1-deg thetas, 512 rho bins, 12-bit cells):
//                           the threshold rule, the fast path, the clipped
//                           cells, the next weight shift
//   BM_CorridorGuideFrame   the host's work on that accumulator:
//                           CorridorGuide::process (lines, undistortion, pan,
//                           shift against a model learnt from the learning
//                           drive of sim::learning_drive, turn)
// Args: pose (0 .. 4) and the edge density: 0 = the realistic threshold
// kRealisticThreshold (eq. 17, horizontal differences), else the target in
// per mille (the threshold giving the density nearest to it on that frame:
// 10, 30, 100 and 150 per mille on the default pose).
// Counters: pixels/s (rate), edges and votes per frame, edges per pixel,
// the threshold. Before any timing, main() checks that the fast path equals
// golden (edge list and every cell) and the cycle models on every frame and
// density used; a mismatch exits 1. Figures: docs/performance.md, "Corridor
// edge and Hough fast path".
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

#include "golden/corridor/corridor.hpp"
#include "golden/corridor/render.hpp"
#include "golden/default_scene.hpp"
#include "golden/edge_ref.hpp"
#include "golden/hough_ref.hpp"
#include "host/corridor/corridor_guide.hpp"
#include "sim/corridor_device.hpp"
#include "sim/corridor_drive.hpp"
#include "stream/edge.hpp"
#include "stream/edge_hough_fast.hpp"
#include "stream/hough.hpp"

namespace {

using namespace ceilnav;  // NOLINT(google-build-using-namespace)
namespace gc = golden::corridor;

constexpr int kPoses = 5;
// t = 12: on the default pose 2.0 % of the pixels, the corridor's own edges
// (lamps, seams, cornice, doors): the same frame rendered without noise has
// 6 132 of them, with the render's noise (sigma 2 grey levels) 6 211. Below
// t = 8 the noise takes over (t = 5: 8.4 %, t = 4: 14 %).
constexpr uint16_t kRealisticThreshold = 12;

gc::Pose pose(int i) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  switch (i) {
    case 1:  // centred, straight along the axis
      return {6.0, 0.0, 1.0, 0.0, 35.0 * kDeg, 0.0};
    case 2:  // turned toward the right wall
      return {12.0, -0.4, 1.0, -15.0 * kDeg, 35.0 * kDeg, 0.0};
    case 3:  // looking up more steeply
      return {20.0, 0.2, 1.0, 6.0 * kDeg, 60.0 * kDeg, 0.0};
    case 4:  // higher, rolled
      return {30.0, 0.0, 1.3, 2.0 * kDeg, 35.0 * kDeg, 5.0 * kDeg};
    default:
      return gc::default_pose();
  }
}

const cv::Mat& frame(int i) {
  static const std::array<cv::Mat, kPoses> frames = [] {
    std::array<cv::Mat, kPoses> f;
    const host::CameraConfig camera = golden::default_camera();
    const gc::Corridor corridor = gc::default_corridor();
    gc::RenderParams params;
    for (int k = 0; k < kPoses; ++k) {
      params.noise_seed = static_cast<uint64_t>(k + 1);
      f[static_cast<size_t>(k)] = gc::render_frame(camera, corridor, pose(k), params);
    }
    return f;
  }();
  return frames[static_cast<size_t>(i)];
}

// The threshold whose horizontal-difference density is nearest `per_mille`.
uint16_t threshold_for(const cv::Mat& f, int64_t per_mille) {
  std::array<int64_t, 256> hist{};
  for (int y = 0; y < f.rows; ++y) {
    const auto* r = f.ptr<uint8_t>(y);
    for (int x = 1; x < f.cols; ++x) ++hist[static_cast<size_t>(std::abs(r[x] - r[x - 1]))];
  }
  const double pixels = static_cast<double>(f.total());
  const double target = static_cast<double>(per_mille) / 1000.0;
  int64_t above = 0;  // pixels with magnitude > t
  for (size_t m = 1; m < 256; ++m) above += hist[m];
  uint16_t best = 0;
  double best_err = 2.0;
  for (int t = 0; t < 255; ++t) {
    const double err = std::abs(static_cast<double>(above) / pixels - target);
    if (err < best_err) {
      best_err = err;
      best = static_cast<uint16_t>(t);
    }
    above -= hist[static_cast<size_t>(t + 1)];
  }
  return best;
}

// One benchmarked frame and its configurations: the pose's frame, the
// horizontal-difference threshold (per_mille 0: kRealisticThreshold, else
// the density nearest per_mille), the Hough configuration.
struct Case {
  const cv::Mat& f;
  stream::EdgeConfig ec;
  stream::HoughConfig hc;

  auto w() const { return static_cast<uint32_t>(f.cols); }
  auto h() const { return static_cast<uint32_t>(f.rows); }
};

Case case_of(int pose_index, int64_t per_mille) {
  Case c{frame(pose_index), {}, {}};
  c.ec.enable = true;
  c.ec.mode = stream::EdgeMode::kHorizontal;
  c.ec.threshold = per_mille == 0 ? kRealisticThreshold : threshold_for(c.f, per_mille);
  c.hc.enable = true;
  c.hc.rho_shift = 5;  // 64 bins x 32 px = 2048 >= W + the diagonal (640 + 800)
  c.hc.width = static_cast<uint16_t>(c.w());
  return c;
}
Case case_of(const benchmark::State& state) {
  return case_of(static_cast<int>(state.range(0)), state.range(1));
}

// The cycle models' input: scan_frame's records and their beats.
void scan(const Case& c, std::vector<stream::EdgeRecord>& edges) {
  edges.clear();
  stream::EdgeDetector::scan_frame(c.ec, c.f.data, c.w(), c.h(), edges);
}
void beats_of(const std::vector<stream::EdgeRecord>& edges, std::vector<uint64_t>& beats) {
  beats.clear();
  for (const stream::EdgeRecord& e : edges) beats.push_back(stream::pack_edge_beat(e));
}
uint64_t trailer_of(const std::vector<stream::EdgeRecord>& edges) {
  return stream::pack_edge_trailer(edges.size(), 0, 0);
}

std::vector<golden::EdgePoint> points_of(std::span<const stream::EdgeRecord> edges) {
  std::vector<golden::EdgePoint> p;
  p.reserve(edges.size());
  for (const stream::EdgeRecord& e : edges) p.push_back({e.x, e.y});
  return p;
}

void set_counters(benchmark::State& state, const Case& c, size_t edges, uint64_t votes) {
  const double pixels = static_cast<double>(c.f.total());
  state.counters["pix/s"] = benchmark::Counter(pixels * static_cast<double>(state.iterations()),
                                               benchmark::Counter::kIsRate);
  state.counters["edges"] = static_cast<double>(edges);
  state.counters["edges/px"] = static_cast<double>(edges) / pixels;
  state.counters["votes"] = static_cast<double>(votes);
  state.counters["t"] = c.ec.threshold;
}

void BM_EdgeHoughFast(benchmark::State& state) {
  const Case c = case_of(state);
  stream::EdgeHoughFast fast;
  for (auto _ : state) {
    benchmark::DoNotOptimize(fast.run(c.ec, c.hc, c.f.data, c.w(), c.h(), c.f.step[0]).data());
  }
  set_counters(state, c, fast.edges().size(), fast.votes());
}

void BM_EdgeFast(benchmark::State& state) {
  const Case c = case_of(state);
  stream::EdgeHoughFast fast;
  for (auto _ : state) {
    benchmark::DoNotOptimize(fast.find_edges(c.ec, c.f.data, c.w(), c.h(), c.f.step[0]).data());
  }
  set_counters(state, c, fast.edges().size(), 0);
}

void BM_HoughVoteFast(benchmark::State& state) {
  const Case c = case_of(state);
  stream::EdgeHoughFast fast;
  fast.find_edges(c.ec, c.f.data, c.w(), c.h(), c.f.step[0]);
  for (auto _ : state) benchmark::DoNotOptimize(fast.vote(c.hc).data());
  set_counters(state, c, fast.edges().size(), fast.votes());
}

// The cycle models' frame paths, end to end: edge records, their beats, the
// voter (one Hough object: process_frame leaves it idle for the next frame).
void BM_EdgeHoughCycleModels(benchmark::State& state) {
  const Case c = case_of(state);
  stream::Hough hough;
  std::vector<stream::EdgeRecord> edges;
  std::vector<uint64_t> beats;
  for (auto _ : state) {
    scan(c, edges);
    beats_of(edges, beats);
    hough.process_frame(beats, trailer_of(edges), c.hc);
    benchmark::DoNotOptimize(hough.counters().votes);
  }
  set_counters(state, c, edges.size(), hough.counters().votes);
}

void BM_EdgeScanFrame(benchmark::State& state) {
  const Case c = case_of(state);
  std::vector<stream::EdgeRecord> edges;
  for (auto _ : state) {
    scan(c, edges);
    benchmark::DoNotOptimize(edges.data());
  }
  set_counters(state, c, edges.size(), 0);
}

void BM_HoughProcessFrame(benchmark::State& state) {
  const Case c = case_of(state);
  std::vector<stream::EdgeRecord> edges;
  std::vector<uint64_t> beats;
  scan(c, edges);
  beats_of(edges, beats);
  stream::Hough hough;
  for (auto _ : state) {
    hough.process_frame(beats, trailer_of(edges), c.hc);
    benchmark::DoNotOptimize(hough.counters().votes);
  }
  set_counters(state, c, edges.size(), hough.counters().votes);
}

void BM_EdgeHoughGolden(benchmark::State& state) {
  const Case c = case_of(state);
  size_t n = 0;
  for (auto _ : state) {
    const auto edges = golden::find_edges_ref(c.f, {c.ec.mode, c.ec.threshold});
    n = edges.size();
    benchmark::DoNotOptimize(
        golden::hough_ref(stream::HoughShape{}, c.hc, points_of(edges)).data());
  }
  set_counters(state, c, n, 0);
}

void BM_CorridorDeviceFrame(benchmark::State& state) {
  const cv::Mat& f = frame(static_cast<int>(state.range(0)));
  sim::CorridorDevice device(sim::corridor_hough_shape(), f.cols, f.rows);
  for (auto _ : state) benchmark::DoNotOptimize(device.process(f).acc.cells.data());
  state.counters["pixels"] = benchmark::Counter(static_cast<double>(f.total()),
                                                benchmark::Counter::kIsIterationInvariantRate);
  state.counters["edges"] = static_cast<double>(device.process(f).edges);
}

// The model of the default corridor from the learning drive at the default
// pose (as ceilnav corridor learns it).
const host::corridor::CorridorModel& learnt_model() {
  static const host::corridor::CorridorModel model = [] {
    const host::CameraConfig camera = golden::default_camera();
    const gc::Pose base = gc::default_pose();
    host::corridor::GuideParams gp;
    gp.mount = {base.tilt_rad, base.swing_rad, base.pan_rad};
    gp.initial_pan_rad = base.pan_rad;
    sim::CorridorDevice device(sim::corridor_hough_shape(), camera.image_width,
                               camera.image_height);
    host::corridor::CorridorGuide learner(camera, gp);
    std::vector<host::corridor::LearningImage> images;
    gc::RenderParams rp;
    rp.supersample = 4;
    for (const gc::Pose& p : sim::learning_drive(base)) {
      const host::corridor::GuideFrame g = learner.process(
          device.process(gc::render_frame(camera, gc::default_corridor(), p, rp)).acc);
      if (auto li = host::corridor::learning_image(g)) images.push_back(*li);
    }
    host::corridor::LearnOptions lo;
    lo.line_height_m = gc::default_corridor().ceiling_height_m - base.height_m;
    return host::corridor::learn_model(images, host::corridor::model_camera(camera, gp.mount), lo);
  }();
  return model;
}

void BM_CorridorGuideFrame(benchmark::State& state) {
  const int i = static_cast<int>(state.range(0));
  const cv::Mat& f = frame(i);
  const host::CameraConfig camera = golden::default_camera();
  const gc::Pose p = pose(i);
  sim::CorridorDevice device(sim::corridor_hough_shape(), f.cols, f.rows);
  const host::corridor::Accumulator acc = device.process(f).acc;
  host::corridor::GuideParams gp;
  gp.mount = {p.tilt_rad, p.swing_rad, 0.0};
  gp.initial_pan_rad = p.pan_rad;
  gp.initial_shift_m.reset();
  host::corridor::GuideFrame g;
  for (auto _ : state) {
    // A fresh guide each frame: no prediction (the acquisition window, no
    // prior on the shift: the most work a frame can take).
    state.PauseTiming();
    host::corridor::CorridorGuide guide(camera, gp, i == 0 ? &learnt_model() : nullptr);
    state.ResumeTiming();
    g = guide.process(acc);
    benchmark::DoNotOptimize(g.lines.data());
  }
  state.counters["lines"] = static_cast<double>(g.lines.size());
  state.counters["axis_lines"] = static_cast<double>(g.pan.axis.inliers.size());
  state.counters["ok"] = g.status == host::corridor::GuideStatus::ok ? 1.0 : 0.0;
}

// Every pose at the realistic threshold, the default pose at 1 %, 3 %, 10 %
// and 15 % (integer thresholds: t = 5 gives 8.4 %, t = 4 14.3 %).
constexpr int64_t kDensities[] = {10, 30, 100, 150};
void corridor_args(benchmark::internal::Benchmark* b) {
  for (int p = 0; p < kPoses; ++p) b->Args({p, 0});
  for (const int64_t d : kDensities) b->Args({0, d});
}
// The slow paths: the default pose, realistic and 10 %.
void few_args(benchmark::internal::Benchmark* b) {
  b->Args({0, 0})->Args({0, 100});
}

BENCHMARK(BM_EdgeHoughFast)->Apply(corridor_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CorridorDeviceFrame)->DenseRange(0, kPoses - 1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CorridorGuideFrame)->DenseRange(0, kPoses - 1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EdgeFast)->Apply(corridor_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HoughVoteFast)->Apply(corridor_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EdgeHoughCycleModels)->Apply(corridor_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EdgeScanFrame)->Apply(few_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HoughProcessFrame)->Apply(few_args)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EdgeHoughGolden)->Apply(few_args)->Unit(benchmark::kMicrosecond);

// The fast path == golden (edges, every cell) == the cycle models (edges;
// cells clipped at the 16-bit maximum, vote and drop counts), on every frame
// and density benchmarked.
bool fast_matches_golden() {
  bool ok = true;
  stream::EdgeHoughFast fast;
  const stream::HoughShape shape;
  auto check = [&](int p, int64_t per_mille) {
    const Case c = case_of(p, per_mille);
    const auto acc = fast.run(c.ec, c.hc, c.f.data, c.w(), c.h(), c.f.step[0]);
    const auto edges = golden::find_edges_ref(c.f, {c.ec.mode, c.ec.threshold});
    const auto cells = golden::hough_ref(shape, c.hc, points_of(edges));
    std::vector<stream::EdgeRecord> scanned;
    std::vector<uint64_t> beats;
    scan(c, scanned);
    beats_of(scanned, beats);
    if (!std::equal(fast.edges().begin(), fast.edges().end(), edges.begin(), edges.end()) ||
        scanned != edges) {
      std::fprintf(stderr, "pose %d, density %lld: edge lists differ\n", p,
                   static_cast<long long>(per_mille));
      ok = false;
    }
    stream::Hough hough(shape);
    hough.process_frame(beats, trailer_of(scanned), c.hc);
    const std::vector<uint32_t> model = hough.results();
    bool model_ok = model.size() == cells.size();
    for (size_t i = 0; model_ok && i < cells.size(); ++i) {
      model_ok = model[i] == std::min<uint64_t>(cells[i], shape.acc_max());
    }
    if (!std::equal(acc.begin(), acc.end(), cells.begin(), cells.end()) || !model_ok ||
        hough.counters().votes != fast.votes() || hough.counters().dropped != fast.dropped()) {
      std::fprintf(stderr, "pose %d, density %lld: accumulators or vote counts differ\n", p,
                   static_cast<long long>(per_mille));
      ok = false;
    }
  };
  for (int p = 0; p < kPoses; ++p) check(p, 0);
  for (const int64_t d : kDensities) check(0, d);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!fast_matches_golden()) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
