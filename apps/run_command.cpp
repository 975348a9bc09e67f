// `ceilnav run`: every PNG of a folder through the device and the host, one CSV row each.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/odometry_height.hpp"
#include "apps/overlay.hpp"
#include "apps/progress.hpp"
#include "apps/results_csv.hpp"
#include "drivers/device.hpp"
#include "host/camera_config_io.hpp"
#include "host/frame_io.hpp"
#include "host/junction.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

int run_frames(const RunOptions& o) {
  check_overlay_every(o.overlay_every);
  const host::CameraConfig camera = host::load_camera_config(o.scene_file);
  const std::vector<fs::path> frames = host::list_png_frames(o.frames_dir);
  check_writable(o.out_csv);

  // --odometry: every file read and every frame's time checked before any output.
  std::optional<nav::OdometryTrack> odometry;
  std::vector<double> times;
  if (!o.odometry_file.empty()) {
    std::optional<nav::RobotParams> robot;
    if (!o.robot_file.empty()) robot = nav::load_robot_params(o.robot_file);
    odometry = nav::OdometryTrack::load(o.odometry_file, robot ? &*robot : nullptr);
    std::vector<std::string> names;
    for (const auto& f : frames) names.push_back(f.filename().string());
    times = frame_times(names, o.frame_times_file, o.fps, *odometry);
  } else if (!o.robot_file.empty() || !o.frame_times_file.empty() || o.fps > 0.0) {
    throw std::runtime_error("--robot, --frame-times and --fps need --odometry");
  }
  std::optional<OdometryHeight> heights;
  if (odometry) heights.emplace(camera);

  drivers::DeviceOptions device = device_options(o.backend);
  device.gap_probability = o.gap_probability;
  device.backpressure_probability = o.backpressure_probability;
  device.seed = o.seed;
  host::NavigatorOptions nav_options;
  nav_options.track.enabled = o.track;
  host::Navigator nav(camera, drivers::make_device(device), nav_options);

  // --overlay-every: overlays/ beside the CSV, staged and committed just
  // before the CSV, so a failed run leaves neither.
  std::unique_ptr<OutputFolder> overlays;
  if (o.overlay_every > 0) {
    const fs::path parent = fs::path(o.out_csv).parent_path();
    overlays =
        std::make_unique<OutputFolder>((parent.empty() ? fs::path(".") : parent) / "overlays");
  }
  AtomicFile csv(o.out_csv);
  write_results_header(csv.stream());
  Progress progress("frames", frames.size());
  int ok = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat grey = host::read_grey_frame(frames[i], camera.image_width, camera.image_height);
    const host::FrameOutcome r = nav.process(grey);
    OdometryColumns odo;
    if (heights) odo = heights->add(odometry->pose_at(times[i]), grey, r, nav.camera_model());
    write_results_row(csv.stream(), frames[i].filename().string(), r,
                      host::detect_junctions(r, nav.camera_model(), camera), odo);
    if (overlays && overlay_due(o.overlay_every, i)) {
      write_png(*overlays, overlay_file_name(frames[i].filename().string()),
                draw_overlay(grey, r, nav.camera_model()));
    }
    if (frame_status(r) == "ok") ++ok;
    progress.update(i + 1);
  }
  progress.finish();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (overlays) overlays->commit();
  csv.commit();
  std::fprintf(stderr, "ceilnav run: %zu frames (%d ok) in %.3f s = %.1f frames/s -> %s\n",
               frames.size(), ok, s, s > 0 ? static_cast<double>(frames.size()) / s : 0.0,
               o.out_csv.c_str());
  if (heights) {
    const OdometryHeightSummary h = heights->summary();
    std::fprintf(stderr,
                 "ceilnav run: ceiling above camera from the tape width %.5f m (%d frames), from "
                 "flow with the odometry %.5f m (%d tracks); odometry scale %s\n",
                 h.width_ceiling_m, h.width_frames, h.flow_ceiling_m, h.tracks,
                 h.odometry_scale ? std::to_string(*h.odometry_scale).c_str() : "unknown");
  }
  return 0;
}

}  // namespace ceilnav::app
