// Throughput of the five ways ceilnav processes a frame, on the same rendered
// 640x480 frames of the demo corridor: the fast C++ path, the cycle-level C++
// model, the Verilated RTL top, the OpenCV golden path and the host pose
// maths. After the runs, main() prints the ratios and the performance targets
// of docs/performance.md.
// See docs/performance.md.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/core.hpp>

#include "common/pipeline_config.hpp"
#include "common/run_record.hpp"
#include "drivers/sim_bus.hpp"
#include "golden/default_scene.hpp"
#include "golden/pattern/pattern.hpp"
#include "golden/pipeline_ref.hpp"
#include "golden/renderer.hpp"
#include "host/auto_threshold.hpp"
#include "host/camera_model.hpp"
#include "host/driver.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/tape_pose.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/pipeline.hpp"
#include "stream/run_scanner.hpp"

#if CEILNAV_BENCH_RTL
#include "drivers/verilated_device.hpp"
#include "drivers/verilated_ports.hpp"
#include "drivers/verilated_top.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "Vceilnav_top_fast.h"
CEILNAV_VERILATOR_HEADERS_END
#endif

namespace {

using namespace ceilnav;

constexpr int kFrames = 4;  // poses of the demo drive

// The shared workload: frames, their video beats, one configuration chosen
// the way the host does (auto threshold on the first frame's histogram), and
// the fast path's results and runs of every frame as the reference.
struct Workload {
  host::CameraConfig camera;
  std::unique_ptr<host::CameraModel> camera_model;
  stream::PipelineConfig cfg;
  std::vector<cv::Mat> frames;
  std::vector<std::vector<stream::VideoBeat>> beats;
  std::vector<stream::FrameResults> results;
  std::vector<std::vector<stream::RunRecord>> runs;
  int64_t pixels_per_frame = 0;
};

std::vector<stream::VideoBeat> frame_beats(const cv::Mat& grey) {
  std::vector<stream::VideoBeat> beats;
  beats.reserve(grey.total());
  for (int y = 0; y < grey.rows; ++y) {
    const uint8_t* row = grey.ptr<uint8_t>(y);
    for (int x = 0; x < grey.cols; ++x) {
      beats.push_back({row[x], true, x == 0 && y == 0, x == grey.cols - 1});
    }
  }
  return beats;
}

const Workload& workload() {
  static const Workload w = [] {
    Workload r;
    r.camera = golden::default_camera();
    r.camera_model = std::make_unique<host::CameraModel>(r.camera);
    const golden::CeilingScene scene = golden::default_corridor(r.camera);
    golden::RenderParams params = golden::default_render_params();
    const std::vector<golden::DrivePose> drive = golden::default_drive(kFrames);
    for (int i = 0; i < kFrames; ++i) {
      params.noise_seed = 1000u + static_cast<uint64_t>(i);
      r.frames.push_back(
          golden::render_frame(r.camera, scene, drive[static_cast<size_t>(i)].pose, params));
    }
    stream::PipelineConfig base;
    base.width = static_cast<uint16_t>(r.camera.image_width);
    base.height = static_cast<uint16_t>(r.camera.image_height);
    const host::ThresholdSettings s =
        host::choose_threshold(golden::pipeline_ref(r.frames.front(), base).histogram);
    if (!s.usable) throw std::runtime_error("bench: no usable threshold on the first frame");
    r.cfg = host::apply_threshold(base, s);
    r.pixels_per_frame = int64_t{r.cfg.width} * r.cfg.height;

    stream::Pipeline p;
    p.set_config(r.cfg);
    for (const cv::Mat& f : r.frames) {
      r.beats.push_back(frame_beats(f));
      std::vector<stream::RunRecord> runs;
      r.results.push_back(p.process_frame(f.data, f.cols, f.rows, f.step, &runs));
      r.runs.push_back(std::move(runs));
    }
    return r;
  }();
  return w;
}

// (1) Fast path: Pipeline::process_frame.
void BM_FastPath(benchmark::State& state) {
  const Workload& w = workload();
  stream::Pipeline p;
  p.set_config(w.cfg);
  std::vector<stream::RunRecord> runs;
  size_t i = 0;
  for (auto _ : state) {
    const cv::Mat& f = w.frames[i];
    runs.clear();
    benchmark::DoNotOptimize(p.process_frame(f.data, f.cols, f.rows, f.step, &runs));
    i = (i + 1) % w.frames.size();
  }
  state.counters["pix/s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * w.pixels_per_frame), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_FastPath)->Unit(benchmark::kMillisecond);

// A non-owning SimDevice on a CeilnavTop, so the host Driver can configure it
// through AXI-Lite before the timed loop, as it does the RTL.
class ModelDeviceRef : public drivers::SimDevice {
 public:
  explicit ModelDeviceRef(stream::CeilnavTop& top) : top_(top) {}
  void reset() override { top_.reset(); }
  drivers::SimOutputs outputs() const override {
    drivers::SimOutputs o;
    o.s_axil = top_.s_axil_out();
    o.m_axis_runs = top_.m_axis_runs();
    o.irq = top_.irq();
    return o;
  }
  void clock(const drivers::SimInputs& in) override {
    top_.clock(in.s_axis_video, in.s_axil, in.m_axis_runs_tready);
  }

 private:
  stream::CeilnavTop& top_;
};

// Configures a device through AXI-Lite with the host Driver, streams the
// first frame and checks its readout against the fast path (untimed).
bool configure_and_check(std::unique_ptr<drivers::SimDevice> device, const Workload& w) {
  drivers::SimBus bus(std::move(device));
  host::Driver driver(bus);
  driver.identify();
  driver.configure(w.cfg);
  const cv::Mat& f = w.frames.front();
  bus.queue_frame(f.data, f.cols, f.rows, f.step, drivers::FrameFeed{});
  const host::FrameReadout r = driver.read_frame();
  return r.results.moments == w.results.front().moments &&
         r.results.histogram == w.results.front().histogram &&
         r.results.run_stats == w.results.front().run_stats && r.runs == w.runs.front();
}

// AXI-Lite inputs of the timed loops: idle, bready/rready high.
constexpr stream::AxiLiteIn kIdleAxi{.bready = true, .rready = true};

// (2) Cycle-level model of the device, stream::CeilnavTop::clock: configured
// through AXI-Lite, then the same loop as BM_Rtl (one beat per edge, frames
// back to back, AXI-Lite idle, m_axis_runs_tready = 1). One iteration = one
// frame of beats.
void BM_CycleModel(benchmark::State& state) {
  const Workload& w = workload();
  stream::CeilnavTop top;
  if (!configure_and_check(std::make_unique<ModelDeviceRef>(top), w)) {
    state.SkipWithError("cycle model results differ from the fast path");
    return;
  }
  size_t i = 0;
  int64_t cycles = 0;
  for (auto _ : state) {
    for (const stream::VideoBeat& b : w.beats[i]) top.clock(b, kIdleAxi, true);
    cycles += static_cast<int64_t>(w.beats[i].size());
    i = (i + 1) % w.frames.size();
  }
  // Check (untimed) that the last clocked frame gave the fast path's results.
  const stream::VideoBeat idle{};
  for (int c = 0; c < stream::CeilnavTop::kEofToIntrCycles + 1; ++c)
    top.clock(idle, kIdleAxi, true);
  const stream::FrameResults& got = top.pipeline().results();
  const stream::FrameResults& want = w.results[(i + w.frames.size() - 1) % w.frames.size()];
  if (!(got.moments == want.moments && got.histogram == want.histogram &&
        got.run_stats == want.run_stats)) {
    state.SkipWithError("cycle model results differ from the fast path");
  }
  state.counters["cycles/s"] =
      benchmark::Counter(static_cast<double>(cycles), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CycleModel)->Unit(benchmark::kMillisecond);

// (2b) The pipeline alone (no register file), stream::Pipeline::clock, for
// the share of the device's cost that the register file takes.
void BM_CycleModelPipeline(benchmark::State& state) {
  const Workload& w = workload();
  stream::Pipeline p;
  p.set_config(w.cfg);
  size_t i = 0;
  int64_t cycles = 0;
  for (auto _ : state) {
    for (const stream::VideoBeat& b : w.beats[i]) p.clock(b, true);
    cycles += static_cast<int64_t>(w.beats[i].size());
    i = (i + 1) % w.frames.size();
  }
  const stream::VideoBeat idle{};
  for (int c = 0; c < stream::Pipeline::kEofToFrameDoneCycles + 1; ++c) p.clock(idle, true);
  const stream::FrameResults& got = p.results();
  const stream::FrameResults& want = w.results[(i + w.frames.size() - 1) % w.frames.size()];
  if (!(got.moments == want.moments && got.histogram == want.histogram &&
        got.run_stats == want.run_stats)) {
    state.SkipWithError("pipeline results differ from the fast path");
  }
  state.counters["cycles/s"] =
      benchmark::Counter(static_cast<double>(cycles), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CycleModelPipeline)->Unit(benchmark::kMillisecond);

#if CEILNAV_BENCH_RTL
// The Verilated top as testbench/CMakeLists.txt builds it for speed
// (ceilnav_rtl_top_fast: no assertions, no trace support), in the harness of
// the co-simulations (drivers/verilated_top.hpp), reset once.
using Vtop = Vceilnav_top_fast;
class Rtl : public drivers::VerilatedTop<Vtop> {
 public:
  Rtl() : VerilatedTop(1, "ceilnav_top") { reset_cycle(); }

  // One edge with the video beat; the AXI-Lite and run-stream inputs as set
  // (idle, tready).
  void clock(const stream::VideoBeat& b) {
    drivers::drive_s_axis_video(dut(), b);
    edge();
  }
};

// A non-owning SimDevice on the Rtl (drivers/verilated_device.hpp), so the
// host Driver can configure it and read a frame back through AXI-Lite before
// the timed loop.
using RtlDeviceRef = drivers::VerilatedDevice<Vtop>;

// Leaves every AXI-Lite input idle and m_axis_runs_tready = 1.
void idle_axi(Vtop& t) {
  t.s_axil_awvalid_i = 0;
  t.s_axil_wvalid_i = 0;
  t.s_axil_bready_i = 1;
  t.s_axil_arvalid_i = 0;
  t.s_axil_rready_i = 1;
  t.m_axis_runs_tready_i = 1;
}

// (3) Verilated RTL top: the same loop as BM_CycleModel.
void BM_Rtl(benchmark::State& state) {
  const Workload& w = workload();
  Rtl rtl;
  if (!configure_and_check(std::make_unique<RtlDeviceRef>(rtl), w)) {
    state.SkipWithError("RTL results differ from the fast path");
    return;
  }
  idle_axi(rtl.dut());
  size_t i = 0;
  int64_t cycles = 0;
  for (auto _ : state) {
    for (const stream::VideoBeat& b : w.beats[i]) rtl.clock(b);
    cycles += static_cast<int64_t>(w.beats[i].size());
    i = (i + 1) % w.frames.size();
  }
  state.counters["cycles/s"] =
      benchmark::Counter(static_cast<double>(cycles), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Rtl)->Unit(benchmark::kMillisecond);
#endif

// (4) OpenCV golden path: golden::pipeline_ref.
void BM_Golden(benchmark::State& state) {
  const Workload& w = workload();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(golden::pipeline_ref(w.frames[i], w.cfg));
    i = (i + 1) % w.frames.size();
  }
  state.counters["pix/s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * w.pixels_per_frame), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Golden)->Unit(benchmark::kMillisecond);

// (5) Host pose maths on the runs of a frame: host::estimate_tape_pose.
void BM_HostPose(benchmark::State& state) {
  const Workload& w = workload();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(host::estimate_tape_pose(w.runs[i], *w.camera_model, w.camera));
    i = (i + 1) % w.frames.size();
  }
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  int64_t runs = 0;
  for (const auto& r : w.runs) runs += static_cast<int64_t>(r.size());
  state.counters["runs/frame"] = static_cast<double>(runs) / static_cast<double>(w.runs.size());
}
BENCHMARK(BM_HostPose)->Unit(benchmark::kMicrosecond);

// (6) Host maths of a pattern frame (seed 003) at D = state.range(0) m,
// theta 45 deg, beta 60 deg (640x480, noise 3, blur 0.5, the error study's
// camera): host::pattern::analyse_pattern on the device's class moments and
// runs (coverage fit, poses, bar code, refinement). docs/pattern.md.
void BM_PatternHost(benchmark::State& state) {
  namespace gp = golden::pattern;
  namespace hp = host::pattern;
  const double d = static_cast<double>(state.range(0));
  host::CameraConfig camera = golden::default_camera();
  const host::CameraModel model(camera);
  const gp::Radiometry radiometry;
  const gp::PatternView view =
      gp::spherical_view(d, 45.0 * std::numbers::pi / 180.0, 60.0 * std::numbers::pi / 180.0);
  gp::PatternRenderParams params;
  params.noise_sigma_grey = 3.0;
  const cv::Mat grey = gp::render_pattern(camera, {}, radiometry, 17, view, params);
  stream::Pipeline pipeline;
  pipeline.set_config(gp::device_config(grey.cols, grey.rows, radiometry));
  std::vector<stream::RunRecord> runs;
  const stream::FrameResults res =
      pipeline.process_frame(grey.data, grey.cols, grey.rows, grey.step, &runs);
  const hp::FrameMoments m = hp::device_moments(res.class_moments);
  hp::PoseOptions po;
  po.up_cam = view.rotation.col(1);
  hp::BarcodeOptions bo;
  bo.bar_contrast =
      radiometry.level(gp::PixelClass::background) - radiometry.level(gp::PixelClass::bar);
  bo.min_bar_run_weight = gp::bar_run_min_weight(radiometry);
  const hp::DiscCoverageModel cov = gp::disc_coverage_model(radiometry, 3.0, 0.5, true);
  int iterations = 0;
  for (auto _ : state) {
    const hp::PatternAnalysis a =
        hp::analyse_pattern(runs, m, model, grey.cols, grey.rows, po, bo, cov);
    if (a.code.identity != 17 || !a.fit) state.SkipWithError("pattern not read");
    iterations = a.fit ? a.fit->iterations : 0;
    benchmark::DoNotOptimize(a);
  }
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["runs/frame"] = static_cast<double>(runs.size());
  state.counters["fit_iterations"] = iterations;
}
BENCHMARK(BM_PatternHost)->Arg(1)->Arg(3)->Arg(5)->Unit(benchmark::kMillisecond);

// Console output plus the finished counters of every run, by benchmark name.
class RecordingReporter : public benchmark::ConsoleReporter {
 public:
  explicit RecordingReporter(bool color) : ConsoleReporter(color ? OO_ColorTabular : OO_Tabular) {}
  // With --benchmark_repetitions the median of the repetitions is kept,
  // else the one run's value.
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.error_occurred) ++errors_;
      if (r.error_occurred) continue;
      const std::string name = r.run_name.function_name;
      const bool median = r.run_type == Run::RT_Aggregate && r.aggregate_name == "median";
      if (median || (r.run_type == Run::RT_Iteration && medians_.count(name) == 0)) {
        for (const auto& [counter, c] : r.counters) values_[name][counter] = c.value;
        if (median) medians_.insert(name);
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  std::optional<double> get(const std::string& bench, const std::string& counter) const {
    const auto b = values_.find(bench);
    if (b == values_.end()) return std::nullopt;
    const auto c = b->second.find(counter);
    if (c == b->second.end()) return std::nullopt;
    return c->second;
  }
  int errors() const { return errors_; }

 private:
  std::map<std::string, std::map<std::string, double>> values_;
  std::set<std::string> medians_;
  int errors_ = 0;
};

void print_ratio(const char* what, std::optional<double> num, std::optional<double> den) {
  if (num && den && *den > 0.0) {
    std::printf("  %-34s %10.2f\n", what, *num / *den);
  } else {
    std::printf("  %-34s %10s\n", what, "n/a");
  }
}

void print_target(const char* what, std::optional<double> value, double target, bool at_least,
                  const char* unit) {
  if (!value) {
    std::printf("  %-34s %10s   (target %s %g %s)\n", what, "n/a", at_least ? ">=" : "<=", target,
                unit);
    return;
  }
  const bool met = at_least ? *value >= target : *value <= target;
  std::printf("  %-34s %10.2f %s (target %s %g): %s\n", what, *value, unit,
              at_least ? ">=" : "<=", target, met ? "met" : "NOT met");
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RecordingReporter reporter(isatty(fileno(stdout)) != 0);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();

  const auto mega = [](std::optional<double> v) -> std::optional<double> {
    if (v) return *v / 1e6;
    return std::nullopt;
  };
  const auto fast = mega(reporter.get("BM_FastPath", "pix/s"));
  const auto model = mega(reporter.get("BM_CycleModel", "cycles/s"));
  const auto pipeline = mega(reporter.get("BM_CycleModelPipeline", "cycles/s"));
  const auto rtl = mega(reporter.get("BM_Rtl", "cycles/s"));
  const auto golden = mega(reporter.get("BM_Golden", "pix/s"));
  std::optional<double> host_us;
  if (const auto fps = reporter.get("BM_HostPose", "frames/s"); fps && *fps > 0.0) {
    host_us = 1e6 / *fps;
  }

  std::printf("\nceilnav bench: %d frames of %dx%d (demo corridor), rates per CPU second%s\n",
              kFrames, workload().cfg.width, workload().cfg.height,
              CEILNAV_BENCH_RTL ? "" : " (no RTL in this build)");
  std::printf("ratios (1 pixel = 1 cycle):\n");
  print_ratio("fast path / golden", fast, golden);
  print_ratio("fast path / cycle model", fast, model);
  print_ratio("cycle model / RTL", model, rtl);
  print_ratio("cycle model pipeline / RTL", pipeline, rtl);
  print_ratio("fast path / RTL", fast, rtl);
  print_ratio("golden / RTL", golden, rtl);
  std::printf("targets (docs/performance.md):\n");
  print_target("fast path [Mpix/s]", fast, 100.0, true, "Mpix/s");
  print_target("cycle model / RTL",
               model && rtl && *rtl > 0.0 ? std::optional(*model / *rtl) : std::nullopt, 10.0, true,
               "x");
  print_target("RTL [Mcycles/s]", rtl, 5.0, true, "Mcycles/s");
  print_target("host pose [us/frame]", host_us, 20.0, false, "us/frame");
  // A failed check (results differing from the fast path) fails the program.
  if (reporter.errors() > 0) {
    std::printf("%d benchmark(s) failed their check\n", reporter.errors());
    return 1;
  }
  return 0;
}
