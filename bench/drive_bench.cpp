// Closed-loop simulation speed (docs/navigation.md, "Closed loop"): the
// default course driven for 5 simulated seconds (150 frames at 30 fps, 500
// odometry ticks) on the fast backend, one core, as `ceilnav drive` runs it:
// the counter x_realtime is simulated seconds per second of CPU time (Google
// Benchmark divides rate counters by CPU time; on an idle core, wall time).
// The second benchmark splits a frame's cost: rendering it, and the device
// plus host.
#include <benchmark/benchmark.h>

#include <chrono>

#include "apps/commands.hpp"
#include "golden/default_scene.hpp"
#include "host/navigator.hpp"
#include "sim/drive.hpp"

namespace {

using namespace ceilnav;

sim::DriveConfig config(int width, int height) {
  sim::DriveConfig c;
  c.camera = app::scaled_camera(width, height, true);  // as ceilnav drive
  c.camera.camera_pitch_deg = 60.0;
  c.render.render = golden::default_render_params();
  c.ekf.odometry.yaw_scale_sigma = 1e-6;
  c.max_time_s = 5.0;
  return c;
}

void BM_DriveSimulation(benchmark::State& state) {
  const sim::DriveConfig c =
      config(static_cast<int>(state.range(0)), static_cast<int>(state.range(0)) * 3 / 4);
  double simulated = 0.0;
  for (auto _ : state) {
    sim::Drive d(c);
    d.run();
    simulated += d.summary().sim_time_s;
  }
  state.counters["x_realtime"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["frames_per_s"] =
      benchmark::Counter(simulated * c.frame_rate_hz, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DriveSimulation)->Arg(320)->Arg(640)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// One frame of the default course at its start: rendered (arg 0) or through
// the device and the host (arg 1).
void BM_DriveFrame(benchmark::State& state) {
  const sim::DriveConfig c = config(320, 240);
  const sim::CameraMount mount{0.1, 0.0, 0.0, 0.0, 0.0};
  const nav::Pose2 start = c.course.start;
  const sim::PoseAt at = [&start](double) { return start; };
  sim::DriveConfig cc = c;
  cc.camera.ceiling_height_m = c.course.ceiling_height_m;
  cc.camera.camera_height_m = c.camera_height_m;
  const cv::Mat frame =
      sim::render_drive_frame(cc.camera, c.course, mount, at, 0.0, c.exposure_s, c.render);
  host::Navigator nav(cc.camera, drivers::make_device());
  for (auto _ : state) {
    if (state.range(0) == 0) {
      benchmark::DoNotOptimize(
          sim::render_drive_frame(cc.camera, c.course, mount, at, 0.0, c.exposure_s, c.render));
    } else {
      benchmark::DoNotOptimize(nav.process(frame));
    }
  }
  state.SetLabel(state.range(0) == 0 ? "render" : "device + host");
}
BENCHMARK(BM_DriveFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
