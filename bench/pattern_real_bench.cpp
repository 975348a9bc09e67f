// Time of `ceilnav pattern`'s per-frame work (sim::analyse_pattern_frame on
// the fast backend: the device's passes, the photometric self-calibration and
// the host's whole analysis) on real frames
// that hold no standard pattern: by default the real-image corpus
// (testdata/real/README.md: cycloid's ceiling recording and opencv-doc's
// photos, 640x480 grey); --raw=FILE reads a recording in the cycloid format
// instead, --images=DIR the photos of a folder (scaled to cover 640x480 and
// centre-cropped). Per frame the best of the benchmark's iterations (at
// least 3 s of them) is kept; the counters give the max and median over the frames and how many
// frames the reader would have called `ok` (must be 0: none has a pattern).
// Usage:
//   ceilnav_pattern_bench [--raw=/path/data.raw.gz] [--images=/path/to/photos]
//   [--only=TEXT] (frames whose name contains TEXT)
// CEILNAV_PATTERN_BENCH_LIST=1 also prints every frame's time.
// See docs/performance.md ("Pattern reader on real frames") and
// docs/pattern.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/pattern/pattern.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "real_corpus.hpp"
#include "sim/pattern_analysis.hpp"

namespace {

using namespace ceilnav;
namespace gp = golden::pattern;
namespace hp = host::pattern;
namespace fs = std::filesystem;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

struct Frame {
  std::string name;
  cv::Mat grey;  // kWidth x kHeight, CV_8UC1
};

std::vector<Frame>& frames() {
  static std::vector<Frame> f;
  return f;
}

// Set when a frame read ok: the program then exits 1 (the library's errors
// do not change its exit code).
bool& any_ok() {
  static bool b = false;
  return b;
}

// The corpus loader's frames (testdata/real_corpus.hpp).
void add_frames(const std::vector<ceilnav::test_support::RealFrame>& corpus) {
  for (const auto& f : corpus) frames().push_back({f.name, f.grey});
}

// The device (fast backend) and the host on every frame; per frame the best
// time over the iterations.
void BM_PatternRealFrames(benchmark::State& state) {
  if (frames().empty()) {
    state.SkipWithError("no frames");
    return;
  }
  const host::CameraConfig camera = golden::default_camera();
  const host::CameraModel model(camera);
  const gp::Radiometry radiometry;
  drivers::Device device(drivers::DeviceOptions{});  // the fast backend
  hp::PoseOptions po = sim::pose_options_for(gp::PatternGeometry{});
  po.up_cam = Eigen::Vector3d(0.0, -1.0, 0.0);
  // Kept across the library's calls (its estimate run and the timed run).
  static std::vector<double> best(frames().size(), std::numeric_limits<double>::infinity());
  int ok = 0;
  for (auto _ : state) {
    ok = 0;
    for (size_t i = 0; i < frames().size(); ++i) {
      const cv::Mat& g = frames()[i].grey;
      const auto t0 = std::chrono::steady_clock::now();
      const sim::PatternFrameAnalysis a =
          sim::analyse_pattern_frame(device, g, radiometry, model, po);
      const auto t1 = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(a);
      best[i] = std::min(best[i], std::chrono::duration<double, std::milli>(t1 - t0).count());
      if (a.code.status == hp::PatternStatus::ok || a.conic_bars.status == hp::PatternStatus::ok) {
        ++ok;
      }
    }
  }
  std::vector<double> sorted = best;
  std::sort(sorted.begin(), sorted.end());
  const size_t worst =
      static_cast<size_t>(std::max_element(best.begin(), best.end()) - best.begin());
  state.counters["frames"] = static_cast<double>(best.size());
  state.counters["max_ms"] = sorted.back();
  state.counters["median_ms"] = sorted[sorted.size() / 2];
  state.counters["ok_frames"] = ok;
  std::printf("pattern on %zu real frames: max %.2f ms (%s), median %.2f ms, ok %d\n", best.size(),
              sorted.back(), frames()[worst].name.c_str(), sorted[sorted.size() / 2], ok);
  if (std::getenv("CEILNAV_PATTERN_BENCH_LIST") != nullptr) {
    for (size_t i = 0; i < best.size(); ++i) {
      std::printf("  %-28s %8.2f ms\n", frames()[i].name.c_str(), best[i]);
    }
  }
  if (ok > 0) {
    any_ok() = true;
    state.SkipWithError("a frame without a pattern read as ok");
  }
}
BENCHMARK(BM_PatternRealFrames)->Unit(benchmark::kMillisecond)->MinTime(3.0);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::vector<char*> rest;
  std::string only;
  bool chosen = false;
  namespace ts = ceilnav::test_support;
  for (int i = 0; i < argc; ++i) {
    const char* a = argv[i];
    if (std::strncmp(a, "--raw=", 6) == 0) {
      add_frames(ts::cycloid_ceiltrack_frames(a + 6));
      chosen = true;
    } else if (std::strncmp(a, "--images=", 9) == 0) {
      add_frames(ts::photo_frames(a + 9, "photos", kWidth, kHeight));
      chosen = true;
    } else if (std::strncmp(a, "--only=", 7) == 0) {
      only = a + 7;
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (!chosen) add_frames(ts::load_real_corpus());
  // --only=TEXT keeps the frames whose name contains TEXT (for profiling).
  if (!only.empty()) {
    std::erase_if(frames(), [&](const Frame& f) { return f.name.find(only) == std::string::npos; });
  }
  int n = static_cast<int>(rest.size());
  if (benchmark::ReportUnrecognizedArguments(n, rest.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return any_ok() ? 1 : 0;
}
