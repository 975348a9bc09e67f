// `ceilnav accuracy`: random poses rendered and estimated, errors against truth.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/progress.hpp"
#include "apps/results_csv.hpp"
#include "common/csv.hpp"
#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/camera_config_io.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

int run_accuracy(const AccuracyOptions& o) {
  if (o.frames < 1) throw std::runtime_error("--frames must be at least 1");
  if (o.pitch_min_deg <= 0 || o.pitch_max_deg > 90 || o.pitch_min_deg > o.pitch_max_deg) {
    throw std::runtime_error("--pitch-min/--pitch-max must satisfy 0 < min <= max <= 90");
  }
  if (o.ceiling_height_m > 0 && o.ceiling_height_m <= golden::default_camera().camera_height_m) {
    throw std::runtime_error("--ceiling-m must be above the camera height");
  }
  std::mt19937_64 rng(o.seed);
  const double tape_width_m =
      o.tape_width_m > 0 ? o.tape_width_m : golden::default_camera().tape_width_m;
  const golden::CeilingScene scene = golden::single_tape_scene(tape_width_m);
  std::unique_ptr<AtomicFile> csv;
  if (!o.csv.empty()) {
    csv = std::make_unique<AtomicFile>(o.csv);
    CsvWriter(csv->stream())
        .row({"frame", "pitch_deg", "yaw_true_rad", "offset_true_m", "noise", "blur", "status",
              "yaw_err_deg", "offset_err_mm", "points_used"});
  }
  Rms yaw_all, off_all;
  std::map<int, std::pair<Rms, Rms>> by_pitch;  // 10-degree bins
  std::map<std::string, int> statuses;
  Progress progress("accuracy", static_cast<size_t>(o.frames));
  for (int i = 0; i < o.frames; ++i) {
    const SampledPose s = sample_pose(rng, o.pitch_min_deg, o.pitch_max_deg, o.yaw_max_deg,
                                      o.offset_max_m, o.noise_max, o.blur_max);
    host::CameraConfig camera = scaled_camera(o.width, o.height, o.distortion);
    camera.camera_pitch_deg = s.pitch_deg;
    camera.tape_width_m = tape_width_m;
    if (o.ceiling_height_m > 0) camera.ceiling_height_m = o.ceiling_height_m;
    golden::RenderParams params = golden::default_render_params();
    if (o.tape_gain >= 0) params.tape_gain = o.tape_gain;
    if (o.background_grey >= 0) params.background_grey = o.background_grey;
    params.noise_sigma_grey = s.noise;
    params.blur_sigma_px = s.blur;
    params.noise_seed = o.seed * 1000003u + static_cast<uint64_t>(i);
    const cv::Mat frame = golden::render_frame(camera, scene, s.pose, params);
    const golden::FrameTruth truth = golden::truth_for(camera, scene, s.pose);
    // Each frame is a new camera: a fresh navigator (first frame: two passes).
    host::Navigator nav(camera, drivers::make_device());
    const host::FrameOutcome r = nav.process(frame);
    const std::string status = frame_status(r);
    ++statuses[status];
    double ey = 0, eo = 0;
    if (status == "ok") {
      ey = wrap_angle(r.pose.yaw_rad - truth.yaw_rad);
      eo = r.pose.offset_m - truth.offset_m;
      yaw_all.add(ey);
      off_all.add(eo);
      auto& bin = by_pitch[static_cast<int>(s.pitch_deg / 10.0) * 10];
      bin.first.add(ey);
      bin.second.add(eo);
    }
    if (csv) {
      // Truth and sample columns: 6 significant digits; errors: 6 decimals.
      CsvWriter w(csv->stream());
      w.integer(i).general(s.pitch_deg, 6).general(truth.yaw_rad, 6).general(truth.offset_m, 6);
      w.general(s.noise, 6).general(s.blur, 6).text(status);
      if (status == "ok") {
        w.fixed(ey / kDeg, 6).fixed(eo * 1000.0, 6);
      } else {
        w.empty().empty();
      }
      w.integer(r.pose.points_used).end_row();
    }
    progress.update(static_cast<size_t>(i + 1));
  }
  progress.finish();
  if (csv) csv->commit();

  std::printf(
      "ceilnav accuracy: %d rendered frames %dx%d, pitch %.0f-%.0f deg, |yaw| <= %.0f deg,"
      " |offset| <= %.2f m, noise sigma <= %.1f, blur sigma <= %.1f px, distortion %s,"
      " seed %llu\n",
      o.frames, o.width, o.height, o.pitch_min_deg, o.pitch_max_deg, o.yaw_max_deg, o.offset_max_m,
      o.noise_max, o.blur_max, o.distortion ? "on" : "off",
      static_cast<unsigned long long>(o.seed));
  fmt::print("{:<10} {:>6} {:>14} {:>14} {:>14} {:>14}\n", "pitch", "frames", "yaw RMS deg",
             "yaw max deg", "offset RMS mm", "offset max mm");
  for (const auto& [p, bins] : by_pitch) {
    fmt::print("{:3}-{:<3}    {:6} {:14.5f} {:14.5f} {:14.4f} {:14.4f}\n", p, p + 10, bins.first.n,
               bins.first.rms() / kDeg, bins.first.max_abs / kDeg, bins.second.rms() * 1e3,
               bins.second.max_abs * 1e3);
  }
  fmt::print("{:<10} {:6} {:14.5f} {:14.5f} {:14.4f} {:14.4f}\n", "all", yaw_all.n,
             yaw_all.rms() / kDeg, yaw_all.max_abs / kDeg, off_all.rms() * 1e3,
             off_all.max_abs * 1e3);
  std::printf("statuses:");
  for (const auto& [st, n] : statuses) std::printf(" %s %d", st.c_str(), n);
  std::printf("\n");
  const bool pass = yaw_all.n == o.frames && yaw_all.rms() / kDeg <= o.yaw_rms_limit_deg &&
                    off_all.rms() <= o.offset_rms_limit_m;
  std::printf("targets: yaw RMS <= %.3f deg, offset RMS <= %.2f mm, every frame ok: %s\n",
              o.yaw_rms_limit_deg, o.offset_rms_limit_m * 1e3, pass ? "MET" : "NOT MET");
  return (o.require && !pass) ? 1 : 0;
}

}  // namespace ceilnav::app
