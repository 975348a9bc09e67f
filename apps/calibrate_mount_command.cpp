// `ceilnav calibrate-mount`: the mount calibration drive (sim::calibration_drive)
// with chosen true mount errors; the estimated mounting yaw, roll and pitch
// against the truth (docs/navigation.md, "Mount calibration").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "apps/progress.hpp"
#include "golden/default_scene.hpp"
#include "sim/calibration_drive.hpp"

namespace ceilnav::app {
namespace {

constexpr double kYawGoalDeg = 0.05;

// The drive of one seed: the robot's slip, wheel scale errors (0.15 %
// sigma), start pose (lateral sigma 2 cm, heading sigma 1 deg) and the
// frames' noise follow the seed; the mount is the same in every run.
sim::CalibrationDriveConfig calibration_config(const CalibrateMountOptions& o, uint64_t seed) {
  sim::CalibrationDriveConfig c;
  c.course = sim::calibration_course(o.run_length_m, o.ceiling_height_m);
  c.camera = scaled_camera(o.width, o.height, true);
  c.camera.camera_pitch_deg = o.pitch_deg;
  c.device = device_options(o.backend);
  c.render.render = golden::default_render_params();
  c.render.render.noise_seed = seed;
  c.robot.seed = seed;
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 7);
  std::normal_distribution<double> g(0.0, 1.0);
  c.robot.left_scale = 1.0 + 0.0015 * g(rng);
  c.robot.right_scale = 1.0 + 0.0015 * g(rng);
  c.course.start = {0.0, 0.02 * g(rng), 1.0 * kDeg * g(rng)};
  c.mount.forward_m = c.drawing_forward_m = o.forward_m;
  c.mount.left_m = o.left_m;
  c.drawing_left_m = o.left_m + 1e-3 * o.left_error_mm;
  c.drawing_left_sigma_m = 1e-3 * o.left_sigma_mm;
  c.mount.yaw_error_rad = o.yaw_deg * kDeg;
  c.mount.roll_error_rad = o.roll_deg * kDeg;
  c.mount.pitch_error_rad = o.pitch_error_deg * kDeg;
  c.run_length_m = o.run_length_m;
  c.speed_mps = o.speed_mps;
  c.heading_rad = o.heading_deg * kDeg;
  c.fit_pitch = o.fit_pitch;
  return c;
}

nlohmann::json result_json(const sim::CalibrationDriveConfig& c,
                           const sim::CalibrationDriveResult& r) {
  const nav::MountCalibration& k = r.calibration;
  const nav::MountErrors& e = r.errors;
  nlohmann::json j;
  j["ok"] = k.ok;
  j["samples"] = {r.runs[0].samples.size(), r.runs[1].samples.size()};
  j["frames"] = r.frames.size();
  j["frames_ok"] = r.frames_ok;
  j["max_abs_heading_deg"] = r.max_abs_true_heading_rad / kDeg;
  j["sim_time_s"] = r.sim_time_s;
  j["wall_time_s"] = r.wall_time_s;
  nlohmann::json est;
  est["yaw_deg"] = e.yaw_rad / kDeg;
  est["roll_deg"] = e.roll_rad / kDeg;
  est["pitch_deg"] = e.pitch_rad / kDeg;
  est["effective_yaw_deg"] = k.yaw_rad / kDeg;
  est["lateral_mm"] = k.lateral_m * 1e3;
  est["offset_scale"] = k.offset_scale;
  j["estimate"] = est;
  nlohmann::json sig;
  sig["yaw_deg"] = std::sqrt(e.covariance(0, 0)) / kDeg;
  sig["roll_deg"] = std::sqrt(e.covariance(1, 1)) / kDeg;
  sig["pitch_deg"] = std::sqrt(e.covariance(2, 2)) / kDeg;
  sig["effective_yaw_deg"] = std::sqrt(k.covariance(0, 0)) / kDeg;
  sig["lateral_mm"] = std::sqrt(k.covariance(1, 1)) * 1e3;
  sig["offset_scale"] = std::sqrt(k.covariance(2, 2));
  j["sigma"] = sig;
  nlohmann::json truth;
  truth["yaw_deg"] = c.mount.yaw_error_rad / kDeg;
  truth["roll_deg"] = c.mount.roll_error_rad / kDeg;
  truth["pitch_deg"] = c.mount.pitch_error_rad / kDeg;
  truth["effective_yaw_deg"] = r.true_effective_yaw_rad / kDeg;
  truth["lateral_mm"] = r.true_effective_lateral_m * 1e3;
  truth["offset_scale"] = 1.0;
  truth["forward_m"] = c.mount.forward_m;
  truth["left_m"] = c.mount.left_m;
  j["truth"] = truth;
  nlohmann::json err;
  err["yaw_deg"] = (e.yaw_rad - c.mount.yaw_error_rad) / kDeg;
  err["roll_deg"] = (e.roll_rad - c.mount.roll_error_rad) / kDeg;
  err["pitch_deg"] = (e.pitch_rad - c.mount.pitch_error_rad) / kDeg;
  err["effective_yaw_deg"] = (k.yaw_rad - r.true_effective_yaw_rad) / kDeg;
  err["lateral_mm"] = (k.lateral_m - r.true_effective_lateral_m) * 1e3;
  j["error"] = err;
  j["drawing_left_m"] = c.drawing_left_m;
  j["rms_residual_mm"] = k.rms_residual_m * 1e3;
  // What the filter takes as its camera mount (nav::CameraMount).
  nlohmann::json filter;
  filter["forward_m"] = c.drawing_forward_m;
  filter["left_m"] = k.offset_scale != 0.0 ? k.lateral_m / k.offset_scale : 0.0;
  filter["yaw_deg"] = k.yaw_rad / kDeg;
  j["filter_mount"] = filter;
  j["yaw_within_goal"] = k.ok && std::abs(e.yaw_rad - c.mount.yaw_error_rad) <= kYawGoalDeg * kDeg;
  return j;
}

void write_frames_csv(const std::string& path, const sim::CalibrationDriveResult& r) {
  std::ofstream f(path);
  f << "run,t_s,distance_m,ok,yaw_rad,offset_m,true_yaw_rad,true_offset_m,x_m,y_m,robot_yaw_rad\n";
  for (const sim::CalibrationFrame& s : r.frames) {
    f << fmt::format("{},{:.4f},{:.5f},{},{:.7f},{:.6f},{:.7f},{:.6f},{:.5f},{:.5f},{:.7f}\n",
                     s.run, s.t_s, s.distance_m, s.ok ? 1 : 0, s.yaw_rad, s.offset_m,
                     s.true_yaw_rad, s.true_offset_m, s.truth.x_m, s.truth.y_m, s.truth.yaw_rad);
  }
  if (!f.flush()) throw std::runtime_error("calibrate-mount: cannot write " + path);
}

}  // namespace

int run_calibrate_mount(const CalibrateMountOptions& o) {
  if (o.monte_carlo < 1) throw std::runtime_error("calibrate-mount: --monte-carlo must be >= 1");
  OutputFolder out(o.out_dir);  // every file appears together, or none
  std::vector<nlohmann::json> runs;
  Progress bar("calibration drives", static_cast<std::size_t>(o.monte_carlo), !o.quiet);
  for (int i = 0; i < o.monte_carlo; ++i) {
    const uint64_t seed = o.seed + static_cast<uint64_t>(i);
    const sim::CalibrationDriveConfig cfg = calibration_config(o, seed);
    const sim::CalibrationDriveResult r = sim::calibration_drive(cfg);
    bar.update(static_cast<std::size_t>(i + 1));
    nlohmann::json j = result_json(cfg, r);
    j["seed"] = seed;
    if (i == 0) write_frames_csv(out.path("frames.csv").string(), r);
    runs.push_back(std::move(j));
  }
  nlohmann::json j = runs.front();
  int within = 0, failed = 0;
  for (const auto& r : runs) {
    within += r["yaw_within_goal"].get<bool>();
    failed += !r["ok"].get<bool>();
  }
  if (o.monte_carlo > 1) {
    // Distribution over the runs that gave a calibration.
    auto dist = [&](auto value) {
      std::vector<double> v;
      for (const auto& r : runs)
        if (r["ok"].get<bool>()) v.push_back(value(r));
      nlohmann::json d;
      if (v.empty()) return d;
      std::sort(v.begin(), v.end());
      double ss = 0.0;
      for (double x : v) ss += x * x;
      const auto p95 =
          static_cast<std::size_t>(std::lround(0.95 * static_cast<double>(v.size() - 1)));
      d["min"] = v.front();
      d["median"] = v[v.size() / 2];
      d["p95"] = v[p95];
      d["max"] = v.back();
      d["rms"] = std::sqrt(ss / static_cast<double>(v.size()));
      return d;
    };
    auto abs_error = [](const char* key) {
      return [key](const nlohmann::json& r) { return std::abs(r["error"][key].get<double>()); };
    };
    nlohmann::json mc;
    mc["runs"] = o.monte_carlo;
    mc["failed"] = failed;
    mc["yaw_within_goal"] = within;
    mc["abs_yaw_error_deg"] = dist(abs_error("yaw_deg"));
    mc["yaw_error_deg"] =
        dist([](const nlohmann::json& r) { return r["error"]["yaw_deg"].get<double>(); });
    mc["abs_effective_yaw_error_deg"] = dist(abs_error("effective_yaw_deg"));
    mc["abs_roll_error_deg"] = dist(abs_error("roll_deg"));
    mc["abs_pitch_error_deg"] = dist(abs_error("pitch_deg"));
    mc["abs_lateral_error_mm"] = dist(abs_error("lateral_mm"));
    mc["rms_residual_mm"] =
        dist([](const nlohmann::json& r) { return r["rms_residual_mm"].get<double>(); });
    mc["seeds"] = nlohmann::json::array();
    for (const auto& r : runs) {
      mc["seeds"].push_back({{"seed", r["seed"]},
                             {"ok", r["ok"]},
                             {"yaw_error_deg", r["error"]["yaw_deg"]},
                             {"roll_error_deg", r["error"]["roll_deg"]},
                             {"pitch_error_deg", r["error"]["pitch_deg"]}});
    }
    j["monte_carlo"] = mc;
  }
  {
    std::ofstream f(out.path("calibration.json"));
    f << j.dump(2) << "\n";
    if (!f.flush()) throw std::runtime_error("calibrate-mount: cannot write calibration.json");
  }
  out.commit();
  const nlohmann::json& e = j["estimate"];
  const nlohmann::json& s = j["sigma"];
  const nlohmann::json& t = j["truth"];
  std::printf(
      "calibrate-mount (seed %llu): yaw %+.4f deg (sigma %.4f, truth %+.4f), roll %+.4f deg "
      "(sigma %.4f, truth %+.4f), pitch %+.4f deg (sigma %.4f, truth %+.4f); lateral %.2f mm, "
      "scale %.4f, rms residual %.3f mm\n",
      static_cast<unsigned long long>(o.seed), e["yaw_deg"].get<double>(),
      s["yaw_deg"].get<double>(), t["yaw_deg"].get<double>(), e["roll_deg"].get<double>(),
      s["roll_deg"].get<double>(), t["roll_deg"].get<double>(), e["pitch_deg"].get<double>(),
      s["pitch_deg"].get<double>(), t["pitch_deg"].get<double>(), e["lateral_mm"].get<double>(),
      e["offset_scale"].get<double>(), j["rms_residual_mm"].get<double>());
  if (o.monte_carlo > 1) {
    const nlohmann::json& d = j["monte_carlo"]["abs_yaw_error_deg"];
    std::printf(
        "%d runs: |yaw error| median %.4f, p95 %.4f, max %.4f deg; %d of %d within %.2f deg\n",
        o.monte_carlo, d.value("median", 0.0), d.value("p95", 0.0), d.value("max", 0.0), within,
        o.monte_carlo, kYawGoalDeg);
  }
  return within == o.monte_carlo || !o.require ? 0 : 1;
}

}  // namespace ceilnav::app
