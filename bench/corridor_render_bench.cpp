// The corridor renderer's speed (docs/renderer.md, "Corridor scenes"): a
// 640 x 480 frame of the built-in corridor from its default camera through
// golden::default_camera()'s lens (mild barrel distortion), one core. Args:
// supersample N. Variants: without distortion, with a 4-sub-exposure motion
// blur, and the frame's truth alone. Each frame gets a new noise seed (the
// golden noise field is kept per seed: a repeated seed would not pay for it).
#include <benchmark/benchmark.h>

#include <cstdint>

#include "golden/corridor/corridor.hpp"
#include "golden/corridor/render.hpp"
#include "golden/default_scene.hpp"

namespace {

using namespace ceilnav;
namespace gc = golden::corridor;

void BM_CorridorFrame(benchmark::State& state) {
  host::CameraConfig camera = golden::default_camera();
  if (state.range(1) == 0) camera.distortion_coefficients = {};
  const gc::Corridor corridor = gc::default_corridor();
  gc::RenderParams params;
  params.supersample = static_cast<int>(state.range(0));
  gc::RenderStats stats;
  uint64_t seed = 1;
  for (auto _ : state) {
    params.noise_seed = seed++;
    benchmark::DoNotOptimize(gc::render_frame(
        camera, corridor, gc::Exposure{gc::default_pose(), gc::default_pose(), 1}, params));
  }
  gc::render_float(camera, corridor, gc::default_pose(), params, &stats);
  state.counters["edge_px"] = static_cast<double>(stats.edge_pixels);
  state.counters["uniform_px"] = static_cast<double>(stats.uniform_pixels);
  state.SetLabel(state.range(1) == 0 ? "pinhole" : "distorted");
}
BENCHMARK(BM_CorridorFrame)
    ->Args({8, 1})
    ->Args({4, 1})
    ->Args({8, 0})
    ->Unit(benchmark::kMillisecond);

void BM_CorridorBlurredFrame(benchmark::State& state) {
  const host::CameraConfig camera = golden::default_camera();
  const gc::Corridor corridor = gc::default_corridor();
  gc::Pose end = gc::default_pose();
  end.x_m += 0.03;  // 1 m/s over a 30 ms exposure
  const gc::Exposure exposure{gc::default_pose(), end, static_cast<int>(state.range(0))};
  gc::RenderParams params;
  for (auto _ : state)
    benchmark::DoNotOptimize(gc::render_frame(camera, corridor, exposure, params));
}
BENCHMARK(BM_CorridorBlurredFrame)->Arg(4)->Unit(benchmark::kMillisecond);

void BM_CorridorTruth(benchmark::State& state) {
  const host::CameraConfig camera = golden::default_camera();
  const gc::Corridor corridor = gc::default_corridor();
  for (auto _ : state) {
    benchmark::DoNotOptimize(gc::truth_for(camera, corridor, gc::default_pose()));
  }
}
BENCHMARK(BM_CorridorTruth)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
