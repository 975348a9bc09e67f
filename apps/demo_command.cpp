// `ceilnav demo`: a rendered drive down the corridor through the device and the host.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/overlay.hpp"
#include "apps/results_csv.hpp"
#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/camera_config_io.hpp"
#include "host/flow_height.hpp"
#include "host/junction.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

int run_demo(const DemoOptions& o) {
  if (o.frames < 2) throw std::runtime_error("--frames must be at least 2");
  const fs::path out = o.out_dir;

  const host::CameraConfig camera = golden::default_camera();
  const golden::CeilingScene scene = golden::default_corridor(camera);
  golden::RenderParams params = golden::default_render_params();
  const std::vector<golden::DrivePose> drive = golden::default_drive(o.frames);

  // device_options: on the bus backends, tvalid gaps and back-pressure.
  host::Navigator nav(camera, drivers::make_device(device_options(o.backend)));

  // Everything goes into a staging folder, renamed into place at the end.
  OutputFolder folder(out);
  AtomicFile csv(folder.path("results.csv"));
  write_results_header(csv.stream());
  std::vector<std::pair<std::string, golden::FrameTruth>> truth_rows;

  std::printf(
      "ceilnav demo: %d frames of a drive down a taped corridor (%dx%d, pitch %.0f deg,"
      " %s)\n",
      o.frames, camera.image_width, camera.image_height, camera.camera_pitch_deg,
      (o.backend + " backend").c_str());
  fmt::print("{:>5} {:<14} {:>9} {:>9} {:>8} {:>9} {:>9} {:>8} {:>4}\n", "frame", "status",
             "yaw_true", "yaw_est", "err_deg", "off_true", "off_est", "err_mm", "thr");

  Rms yaw_err, off_err;
  std::map<std::string, int> statuses;
  std::vector<double> heights;
  std::optional<Eigen::Vector2d> prev_end;
  cv::Mat overlay_grey;
  host::FrameOutcome overlay_outcome;
  int overlay_frame = -1;
  const auto t0 = std::chrono::steady_clock::now();
  double pipeline_s = 0.0;

  for (int i = 0; i < o.frames; ++i) {
    params.noise_seed = 1000u + static_cast<uint64_t>(i);
    const auto& d = drive[static_cast<size_t>(i)];
    const cv::Mat frame = golden::render_frame(camera, scene, d.pose, params);
    const golden::FrameTruth truth = golden::truth_for(camera, scene, d.pose);
    const std::string name = frame_name(i);
    write_png(folder, fs::path("frames") / name, frame);
    truth_rows.emplace_back(name, truth);

    const auto p0 = std::chrono::steady_clock::now();
    host::FrameOutcome r = nav.process(frame);
    pipeline_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
    write_results_row(csv.stream(), name, r, host::detect_junctions(r, nav.camera_model(), camera));
    const std::string status = frame_status(r);
    ++statuses[status];

    if (status == "ok") {
      const double ey = wrap_angle(r.pose.yaw_rad - truth.yaw_rad);
      const double eo = r.pose.offset_m - truth.offset_m;
      yaw_err.add(ey);
      off_err.add(eo);
      fmt::print("{:5} {:<14} {:9.4f} {:9.4f} {:8.4f} {:9.4f} {:9.4f} {:8.3f} {:4}\n", i, status,
                 truth.yaw_rad / kDeg, r.pose.yaw_rad / kDeg, ey / kDeg, truth.offset_m,
                 r.pose.offset_m, eo * 1000.0, r.settings.threshold);
      if (overlay_frame < 0 || i == o.frames / 2) {
        overlay_grey = frame;
        overlay_outcome = r;
        overlay_frame = i;
      }
      // Ceiling height from optic flow: the tape end at a gap, tracked from the
      // previous frame, with the odometry distance (seed 000 eq. 44).
      const auto end = host::find_tape_end(r.runs, nav.camera_model(), camera, r.pose);
      if (end && prev_end && end->y() < prev_end->y()) {  // features ahead move up the image
        const double motion = std::atan2(d.pose.y_m - drive[static_cast<size_t>(i - 1)].pose.y_m,
                                         d.pose.x_m - drive[static_cast<size_t>(i - 1)].pose.x_m) -
                              d.pose.yaw_rad;
        const auto h = host::ceiling_height_from_flow(
            prev_end->y(), end->y(), camera.camera_pitch_deg * kDeg, d.odometry_m, motion);
        if (h.status == host::Status::ok) heights.push_back(h.ceiling_above_camera_m);
      }
      prev_end = end;
    } else {
      fmt::print("{:5} {:<14} {:9.4f} {:>9} {:>8} {:9.4f} {:>9} {:>8} {:4}\n", i, status,
                 truth.yaw_rad / kDeg, "-", "-", truth.offset_m, "-", "-", r.settings.threshold);
      prev_end.reset();
    }
  }
  const double total_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  csv.commit();
  golden::write_truth_csv(folder.path("truth.csv").string(), truth_rows);
  write_scene(folder, camera);
  if (overlay_frame >= 0) {
    write_png(folder, "overlay.png",
              draw_overlay(overlay_grey, overlay_outcome, nav.camera_model()));
  }
  folder.commit();

  std::printf("\nsummary: %d frames;", o.frames);
  for (const auto& [s, n] : statuses) std::printf(" %s %d;", s.c_str(), n);
  std::printf("\n  yaw error    RMS %.4f deg, max %.4f deg (%d frames)\n", yaw_err.rms() / kDeg,
              yaw_err.max_abs / kDeg, yaw_err.n);
  std::printf("  offset error RMS %.3f mm, max %.3f mm\n", off_err.rms() * 1000.0,
              off_err.max_abs * 1000.0);
  if (!heights.empty()) {
    std::sort(heights.begin(), heights.end());
    std::printf(
        "  ceiling above camera from optic flow: median %.3f m over %zu frame pairs "
        "(truth %.3f m)\n",
        heights[heights.size() / 2], heights.size(), camera.ceiling_above_camera_m());
  } else {
    std::printf("  ceiling above camera from optic flow: no tape end tracked\n");
  }
  std::printf("  pipeline + host: %.1f ms/frame (rendering included in total %.1f s)\n",
              1000.0 * pipeline_s / o.frames, total_s);
  std::printf("wrote %s/results.csv, truth.csv, scene.yaml, overlay.png (frame %d), frames/\n",
              out.string().c_str(), overlay_frame);
  return 0;
}

}  // namespace ceilnav::app
