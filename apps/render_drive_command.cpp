// `ceilnav render-drive`: a rendered drive over the default corridor with the wheel
// odometry the robot logs, the input of `ceilnav run --odometry`.

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "common/csv.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;
namespace {

// The camera's (= the robot's) pose at time t: x advances at `speed`, the
// heading follows the path's tangent (a differential drive cannot move sideways).
golden::CameraPose pose_at(const RenderDriveOptions& o, double t) {
  const double x = o.speed_mps * t;
  if (o.path == "straight") {
    // A straight line at a small angle to the tape.
    const double slope = std::tan(0.02);
    return {x, -0.1 + slope * x, std::atan(slope)};
  }
  // Gentle S-curves: 0.3 m either side of the tape, 14 m period.
  const double k = 2.0 * std::numbers::pi / 14.0;
  return {x, 0.3 * std::sin(k * x), std::atan(0.3 * k * std::cos(k * x))};
}

void write_text(const OutputFolder& folder, const fs::path& relative, const std::string& text) {
  std::ofstream out(folder.path(relative), std::ios::binary);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error("cannot write " + (folder.folder() / relative).string());
}

}  // namespace

int run_render_drive(const RenderDriveOptions& o) {
  const host::CameraConfig camera = golden::default_camera();
  const golden::CeilingScene scene = golden::default_corridor(camera);
  golden::RenderParams params = golden::default_render_params();
  const double duration = o.length_m / o.speed_mps;
  OutputFolder folder(o.out_dir);

  // Wheel odometry: the true travel of each wheel per tick, reported (1 + e)
  // times, as cumulative counts rounded to whole counts.
  std::string odo = "t_s,left_ticks,right_ticks\n";
  const int ticks = static_cast<int>(std::floor(duration * o.tick_hz));
  double left_m = 0.0, right_m = 0.0;
  golden::CameraPose prev = pose_at(o, 0.0);
  for (int k = 0; k <= ticks; ++k) {
    const double t = k / o.tick_hz;
    const golden::CameraPose p = pose_at(o, t);
    if (k > 0) {
      const double dyaw = p.yaw_rad - prev.yaw_rad;
      const double half = 0.5 * dyaw;
      const double sinc = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
      const double ds = std::hypot(p.x_m - prev.x_m, p.y_m - prev.y_m) / sinc;
      left_m += ds - 0.5 * o.wheel_base_m * dyaw;
      right_m += ds + 0.5 * o.wheel_base_m * dyaw;
    }
    prev = p;
    const auto counts = [&](double m) {
      return static_cast<long long>(std::llround((1.0 + o.scale_error) * m / o.m_per_count));
    };
    odo += fmt::format("{:.6f},{},{}\n", t, counts(left_m), counts(right_m));
  }
  write_text(folder, "odometry.csv", odo);
  write_text(folder, "robot.yaml",
             fmt::format("# Differential-drive robot of `ceilnav render-drive`\nwheel_base_m: {}\n"
                         "left_m_per_count: {}\nright_m_per_count: {}\n",
                         o.wheel_base_m, o.m_per_count, o.m_per_count));

  // Frames at mid-exposure times 0.01 + i / fps s, rendered at the true pose.
  std::string times = "frame,t_s\n";
  std::string truth = "frame,t_s,x_m,y_m,yaw_rad,ceiling_above_camera_m\n";
  const double last_tick = ticks / o.tick_hz;
  int n = 0;
  for (int i = 0;; ++i) {
    const double t = 0.01 + i / o.fps;
    if (t > last_tick) break;
    const golden::CameraPose p = pose_at(o, t);
    params.noise_seed = o.seed * 100003u + static_cast<uint64_t>(i);
    const std::string name = frame_name(i);
    write_png(folder, fs::path("frames") / name, golden::render_frame(camera, scene, p, params));
    times += fmt::format("{},{:.6f}\n", name, t);
    truth += fmt::format("{},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f}\n", name, t, p.x_m, p.y_m,
                         p.yaw_rad, camera.ceiling_above_camera_m());
    ++n;
  }
  write_text(folder, "frame_times.csv", times);
  write_text(folder, "truth.csv", truth);
  write_scene(folder, camera);
  folder.commit();
  std::printf(
      "ceilnav render-drive: %d frames along a %s path of %.2f m, odometry scale error %+.3f %%"
      " -> %s\n",
      n, o.path.c_str(), o.length_m, 100.0 * o.scale_error, o.out_dir.c_str());
  return 0;
}

}  // namespace ceilnav::app
