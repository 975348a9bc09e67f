#include "apps/commands.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "apps/atomic_file.hpp"
#include "apps/overlay.hpp"
#include "apps/progress.hpp"
#include "apps/results_csv.hpp"
#include "apps/rtl_backend.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/camera_config_io.hpp"
#include "host/csv.hpp"
#include "host/flow_height.hpp"
#include "host/frame_io.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double wrap_angle(double a) {
  return std::remainder(a, 2.0 * std::numbers::pi);
}

struct Rms {
  double sum2 = 0.0, max_abs = 0.0;
  int n = 0;
  void add(double e) {
    sum2 += e * e;
    max_abs = std::max(max_abs, std::abs(e));
    ++n;
  }
  double rms() const { return n > 0 ? std::sqrt(sum2 / n) : 0.0; }
};

// `relative` in the output folder's staging area. Encoded in memory, then
// written with every error checked (a full disk or a file size limit is an
// error, not a truncated PNG).
void write_png(const OutputFolder& folder, const fs::path& relative, const cv::Mat& img) {
  const fs::path shown = folder.folder() / relative;
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", img, bytes)) {
    throw std::runtime_error("cannot encode image '" + shown.string() + "'");
  }
  std::ofstream out(folder.path(relative), std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("error while writing '" + shown.string() + "'");
}

// scene.yaml, read back: cv::FileStorage does not report every write error.
void write_scene(const OutputFolder& folder, const host::CameraConfig& camera) {
  const std::string path = folder.path("scene.yaml").string();
  host::save_camera_config(camera, path);
  host::load_camera_config(path);
}

void configure_backend(host::NavigatorOptions& opt, const std::string& name) {
  const host::DeviceOptions d = device_options(name);
  opt.backend = d.backend;
  opt.bus_factory = d.bus_factory;
}

std::string frame_name(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%04d.png", i);
  return buf;
}

}  // namespace

host::DeviceOptions device_options(const std::string& backend) {
  host::DeviceOptions opt;
  if (backend == "fast") {
    opt.backend = host::Backend::fast;
  } else if (backend == "model") {
    opt.backend = host::Backend::model;
  } else if (backend == "rtl") {
    opt.backend = host::Backend::rtl;
    opt.bus_factory = rtl_bus_factory();
    if (!opt.bus_factory) {
      throw std::runtime_error("this ceilnav was built without the Verilated RTL backend");
    }
  } else {
    throw std::runtime_error("unknown backend '" + backend + "' (fast, model or rtl)");
  }
  if (opt.backend != host::Backend::fast) {  // exercise the stream handshakes, as demo does
    opt.gap_probability = 0.1;
    opt.backpressure_probability = 0.3;
  }
  return opt;
}

// ---------------------------------------------------------------- demo

int run_demo(const DemoOptions& o) {
  if (o.frames < 2) throw std::runtime_error("--frames must be at least 2");
  const fs::path out = o.out_dir;

  const host::CameraConfig camera = golden::default_camera();
  const golden::CeilingScene scene = golden::default_corridor(camera);
  golden::RenderParams params = golden::default_render_params();
  const std::vector<golden::DrivePose> drive = golden::default_drive(o.frames);

  host::NavigatorOptions nav_opt;
  configure_backend(nav_opt, o.backend);
  const bool bus = nav_opt.backend != host::Backend::fast;
  nav_opt.gap_probability = bus ? 0.1 : 0.0;
  nav_opt.backpressure_probability = bus ? 0.3 : 0.0;
  host::Navigator nav(camera, nav_opt);

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
    write_results_row(csv.stream(), name, r);
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

// ---------------------------------------------------------------- run

int run_frames(const RunOptions& o) {
  const host::CameraConfig camera = host::load_camera_config(o.scene_file);
  const std::vector<fs::path> frames = host::list_png_frames(o.frames_dir);
  check_writable(o.out_csv);

  host::NavigatorOptions nav_opt;
  configure_backend(nav_opt, o.backend);
  nav_opt.gap_probability = o.gap_probability;
  nav_opt.backpressure_probability = o.backpressure_probability;
  nav_opt.seed = o.seed;
  host::Navigator nav(camera, nav_opt);

  AtomicFile csv(o.out_csv);
  write_results_header(csv.stream());
  Progress progress("frames", frames.size());
  int ok = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat grey = host::read_grey_frame(frames[i], camera.image_width, camera.image_height);
    const host::FrameOutcome r = nav.process(grey);
    write_results_row(csv.stream(), frames[i].filename().string(), r);
    if (frame_status(r) == "ok") ++ok;
    progress.update(i + 1);
  }
  progress.finish();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  csv.commit();
  std::fprintf(stderr, "ceilnav run: %zu frames (%d ok) in %.3f s = %.1f frames/s -> %s\n",
               frames.size(), ok, s, s > 0 ? static_cast<double>(frames.size()) / s : 0.0,
               o.out_csv.c_str());
  return 0;
}

// ---------------------------------------------------------------- render

namespace {

struct SampledPose {
  golden::CameraPose pose;
  double pitch_deg, noise, blur;
};

SampledPose sample_pose(std::mt19937_64& rng, double pitch_min, double pitch_max, double yaw_max,
                        double offset_max, double noise_max, double blur_max) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  SampledPose s;
  s.pitch_deg = pitch_min + (pitch_max - pitch_min) * u01(rng);
  s.pose.yaw_rad = (2.0 * u01(rng) - 1.0) * yaw_max * kDeg;
  s.pose.y_m = (2.0 * u01(rng) - 1.0) * offset_max;
  s.pose.x_m = 10.0 * u01(rng);
  s.noise = noise_max * u01(rng);
  s.blur = blur_max * u01(rng);
  return s;
}

}  // namespace

host::CameraConfig scaled_camera(int width, int height, bool distortion) {
  host::CameraConfig c = golden::default_camera();
  const double sx = width / 640.0, sy = height / 480.0;
  c.image_width = width;
  c.image_height = height;
  c.camera_matrix = {520.0 * sx, 0.0,        (321.7 + 0.5) * sx - 0.5,
                     0.0,        518.5 * sy, (238.2 + 0.5) * sy - 0.5,
                     0.0,        0.0,        1.0};
  if (!distortion) c.distortion_coefficients = {};
  return c;
}

int run_render(const RenderOptions& o) {
  if (o.frames < 1) throw std::runtime_error("--frames must be at least 1");
  const fs::path out = o.out_dir;
  host::CameraConfig camera = scaled_camera(o.width, o.height, o.distortion);
  camera.camera_pitch_deg = o.pitch_deg;
  host::validate_camera_config(camera, "--width/--height/--pitch-deg");
  // Everything goes into a staging folder, renamed into place at the end.
  OutputFolder folder(out);
  const golden::CeilingScene scene = o.random_poses ? golden::single_tape_scene(camera.tape_width_m)
                                                    : golden::default_corridor(camera);
  golden::RenderParams params = golden::default_render_params();
  if (o.noise_sigma >= 0) params.noise_sigma_grey = o.noise_sigma;
  if (o.blur_sigma >= 0) params.blur_sigma_px = o.blur_sigma;

  std::mt19937_64 rng(o.seed);
  const std::vector<golden::DrivePose> drive = golden::default_drive(o.frames);
  std::vector<std::pair<std::string, golden::FrameTruth>> truth_rows;
  Progress progress("render", static_cast<size_t>(o.frames));
  for (int i = 0; i < o.frames; ++i) {
    golden::CameraPose pose = drive[static_cast<size_t>(i)].pose;
    if (o.random_poses) {
      pose = sample_pose(rng, o.pitch_deg, o.pitch_deg, 15.0, 0.5, 0.0, 0.0).pose;
    }
    params.noise_seed = o.seed * 7919u + static_cast<uint64_t>(i);
    const cv::Mat frame = golden::render_frame(camera, scene, pose, params);
    const std::string name = frame_name(i);
    write_png(folder, name, frame);
    truth_rows.emplace_back(name, golden::truth_for(camera, scene, pose));
    progress.update(static_cast<size_t>(i + 1));
  }
  progress.finish();
  golden::write_truth_csv(folder.path("truth.csv").string(), truth_rows);
  write_scene(folder, camera);
  folder.commit();
  std::printf("wrote %d frames, truth.csv and scene.yaml to %s\n", o.frames, out.string().c_str());
  return 0;
}

// ---------------------------------------------------------------- accuracy

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
    host::CsvWriter(csv->stream())
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
    host::Navigator nav(camera);
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
      host::CsvWriter w(csv->stream());
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
