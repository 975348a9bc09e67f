// Seed 004's tracking on one core (docs/homing.md, "Tracking"): a 640 x 480
// frame of the built-in office ceiling, the site recorded beside its first
// grille, the frame taken 0.25 m off the site and turned by 35 deg:
//   BM_TrackFullSearch  SiteTracker::track over the whole frame (orientation
//                       -> four quadrant candidates -> refinement)
//   BM_TrackFastMode    the seed's fast mode (three templates 10 deg apart
//                       about a predicted gamma)
//   BM_TrackNear        the full search in a 60 px radius about the
//                       predicted site point (servoing: the site moves
//                       little between frames)
//   BM_OrientationRef   golden::orientation_histogram_ref of the frame (the
//                       orientation block's work, on the host)
// The frame and its histogram are made once; the histogram comes from the
// device in the system, so the tracking benchmarks do not include it.
// One core: OpenCV's own threads are off (cv::setNumThreads(0): its
// functions run on the calling thread), and the CPU time is the process's
// (all threads), so a CPU time above the wall time would show parallel work.
#include <benchmark/benchmark.h>

#include <numbers>

#include <opencv2/core/utility.hpp>

#include "golden/ceiling/ceiling.hpp"
#include "golden/ceiling/render.hpp"
#include "golden/orientation_ref.hpp"
#include "host/homing/tracker.hpp"

namespace {

using namespace ceilnav;  // NOLINT(google-build-using-namespace)
namespace gc = golden::ceiling;

struct Setup {
  host::homing::Site site;
  cv::Mat frame;
  std::vector<double> histogram;
  cv::Point2d predicted;
  Setup() {
    const gc::Ceiling c = gc::office_ceiling();
    gc::Pose at;
    at.x_m = 1.65;
    at.y_m = 0.15;
    gc::RenderParams rp;
    const cv::Mat rec = gc::render_frame(host::CameraConfig{}, c, {}, at, rp);
    site = host::homing::record_site(rec, golden::orientation_histogram_ref(rec),
                                     host::CameraConfig{});
    gc::Pose p = at;
    p.x_m += 0.25;
    p.y_m -= 0.1;
    p.yaw_rad = 35.0 * std::numbers::pi / 180.0;
    rp.noise_seed = 2;
    frame = gc::render_frame(host::CameraConfig{}, c, {}, p, rp);
    histogram = golden::orientation_histogram_ref(frame);
    const auto px = gc::project(host::CameraConfig{}, c, p, at.x_m, at.y_m);
    predicted = cv::Point2d(px->x() + 7.0, px->y() - 5.0);
  }
};
const Setup& setup() {
  static const Setup s;
  return s;
}

void BM_TrackFullSearch(benchmark::State& state) {
  const Setup& s = setup();
  const host::homing::SiteTracker tracker(s.site);
  for (auto _ : state) benchmark::DoNotOptimize(tracker.track(s.frame, s.histogram).x_px);
  state.counters["ok"] =
      tracker.track(s.frame, s.histogram).status == host::homing::TrackStatus::ok;
}

void BM_TrackFastMode(benchmark::State& state) {
  const Setup& s = setup();
  const host::homing::SiteTracker tracker(s.site);
  for (auto _ : state) {
    benchmark::DoNotOptimize(tracker.track(s.frame, s.histogram, std::nullopt, -33.0).x_px);
  }
}

void BM_TrackNear(benchmark::State& state) {
  const Setup& s = setup();
  host::homing::TrackerOptions o;
  o.search_radius_px = 60.0;
  const host::homing::SiteTracker tracker(s.site, o);
  for (auto _ : state) {
    benchmark::DoNotOptimize(tracker.track(s.frame, s.histogram, s.predicted).x_px);
  }
}

void BM_OrientationRef(benchmark::State& state) {
  const Setup& s = setup();
  for (auto _ : state) benchmark::DoNotOptimize(golden::orientation_histogram_ref(s.frame).data());
}

BENCHMARK(BM_TrackFullSearch)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrackFastMode)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrackNear)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OrientationRef)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(0);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
