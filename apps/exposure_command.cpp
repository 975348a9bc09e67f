// `ceilnav exposure`: seed 000's histogram correction table on an exposure
// sweep. A camera drives along a single tape while the exposure steps by
// x0.5 .. x2 between frames; the same frames go through the navigator under
// each threshold policy (host::ThresholdPolicy), errors against truth.

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/results_csv.hpp"
#include "common/csv.hpp"
#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {

namespace {

// Exposure levels of one cycle: every step between neighbours (the last back
// to the first included) is one of x2, x0.5, x1.41, x0.71; the cycle spans
// x0.5 .. x2 of the nominal exposure.
constexpr std::array<double, 12> kExposureCycle{
    1.0, 2.0,           1.0, 0.5, 1.0, std::sqrt(2.0), 2.0, std::sqrt(2.0), 1.0, std::sqrt(0.5),
    0.5, std::sqrt(0.5)};

// The steps into a frame (exposure ratio to the previous frame), in the
// order of the summary's columns.
constexpr std::array<double, 4> kSteps{0.5, std::sqrt(0.5), std::sqrt(2.0), 2.0};
int step_index(double ratio) {
  for (size_t k = 0; k < kSteps.size(); ++k) {
    if (std::abs(ratio - kSteps[k]) < 1e-9) return static_cast<int>(k);
  }
  return -1;  // the first frame, or a ratio outside the cycle
}

struct PolicyStats {
  const char* name;
  host::ThresholdPolicy policy;
  int ok = 0, passes = 0;
  Rms yaw, offset;
  std::array<int, kSteps.size()> ok_by_step{}, frames_by_step{};
};

}  // namespace

double exposure_of_frame(int i) {
  return kExposureCycle[static_cast<size_t>(i) % kExposureCycle.size()];
}

int run_exposure(const ExposureOptions& o) {
  if (o.frames < 2) throw std::runtime_error("--frames must be at least 2");
  if (!(o.pitch_deg > 0.0 && o.pitch_deg <= 90.0)) {
    throw std::runtime_error("--pitch must be in (0, 90] degrees");
  }
  host::CameraConfig camera = golden::default_camera();
  camera.camera_pitch_deg = o.pitch_deg;
  const golden::CeilingScene scene = golden::single_tape_scene(camera.tape_width_m);
  const std::vector<golden::DrivePose> drive = golden::default_drive(o.frames, o.step_m);
  golden::RenderParams nominal = golden::default_render_params();
  if (o.tape_gain >= 0) nominal.tape_gain = o.tape_gain;
  if (o.background_grey >= 0) nominal.background_grey = o.background_grey;
  if (o.noise_sigma >= 0) nominal.noise_sigma_grey = o.noise_sigma;

  std::array<PolicyStats, 3> stats{{
      {"first_frame", host::ThresholdPolicy::first_frame, 0, 0, {}, {}, {}, {}},
      {"previous_frame", host::ThresholdPolicy::previous_frame, 0, 0, {}, {}, {}, {}},
      {"previous_frame_rerun", host::ThresholdPolicy::previous_frame_rerun, 0, 0, {}, {}, {}, {}},
  }};
  std::vector<std::unique_ptr<host::Navigator>> navs;
  for (const PolicyStats& s : stats) {
    host::NavigatorOptions opt;
    opt.threshold_policy = s.policy;
    navs.push_back(std::make_unique<host::Navigator>(
        camera, drivers::make_device(device_options(o.backend)), opt));
  }

  std::unique_ptr<AtomicFile> csv;
  if (!o.csv.empty()) {
    csv = std::make_unique<AtomicFile>(o.csv);
    CsvWriter(csv->stream())
        .row({"frame", "exposure", "policy", "status", "threshold", "background_level", "passes",
              "yaw_err_deg", "offset_err_mm"});
  }
  for (int i = 0; i < o.frames; ++i) {
    const double exposure = exposure_of_frame(i);
    const int step = i == 0 ? -1 : step_index(exposure / exposure_of_frame(i - 1));
    golden::RenderParams params = nominal;
    // Exposure scales the light collected (ceiling and tape); the read noise
    // stays: it is the sensor's, not the scene's.
    params.background_grey = nominal.background_grey * exposure;
    params.tape_gain = nominal.tape_gain * exposure;
    params.noise_seed = o.seed * 1000003u + static_cast<uint64_t>(i);
    const cv::Mat frame =
        golden::render_frame(camera, scene, drive[static_cast<size_t>(i)].pose, params);
    const golden::FrameTruth truth =
        golden::truth_for(camera, scene, drive[static_cast<size_t>(i)].pose);
    for (size_t k = 0; k < stats.size(); ++k) {
      const host::FrameOutcome r = navs[k]->process(frame);
      PolicyStats& s = stats[k];
      const std::string status = frame_status(r);
      s.passes += r.passes;
      if (step >= 0) ++s.frames_by_step[static_cast<size_t>(step)];
      double ey = 0.0, eo = 0.0;
      if (status == "ok") {
        ++s.ok;
        if (step >= 0) ++s.ok_by_step[static_cast<size_t>(step)];
        ey = wrap_angle(r.pose.yaw_rad - truth.yaw_rad);
        eo = r.pose.offset_m - truth.offset_m;
        s.yaw.add(ey);
        s.offset.add(eo);
      }
      if (csv) {
        CsvWriter w(csv->stream());
        w.integer(i).general(exposure, 6).text(s.name).text(status);
        w.integer(r.settings.threshold).integer(r.settings.background_level).integer(r.passes);
        if (status == "ok") {
          w.fixed(ey / kDeg, 6).fixed(eo * 1000.0, 6);
        } else {
          w.empty().empty();
        }
        w.end_row();
      }
    }
  }
  if (csv) csv->commit();

  fmt::print(
      "ceilnav exposure: {} frames, pitch {:.1f} deg, single tape, exposure cycling x0.5-x2 of "
      "nominal with steps of x0.5, x0.71, x1.41, x2 between frames; at nominal: background {:.0f}, "
      "tape gain {:.0f}, noise sigma {:.1f}; seed {}\n",
      o.frames, o.pitch_deg, nominal.background_grey, nominal.tape_gain, nominal.noise_sigma_grey,
      o.seed);
  fmt::print("{:<22} {:>8} {:>12} {:>12} {:>12} {:>14} {:>14}\n", "policy", "ok", "passes/frame",
             "yaw RMS deg", "yaw max deg", "offset RMS mm", "offset max mm");
  for (const PolicyStats& s : stats) {
    fmt::print("{:<22} {:>4}/{:<3} {:12.2f} {:12.4f} {:12.4f} {:14.3f} {:14.3f}\n", s.name, s.ok,
               o.frames, static_cast<double>(s.passes) / o.frames, s.yaw.rms() / kDeg,
               s.yaw.max_abs / kDeg, s.offset.rms() * 1e3, s.offset.max_abs * 1e3);
  }
  fmt::print("ok frames by the exposure step into the frame:\n{:<22}", "policy");
  for (double st : kSteps) fmt::print(" {:>9}", fmt::format("x{:.2f}", st));
  fmt::print("\n");
  for (const PolicyStats& s : stats) {
    fmt::print("{:<22}", s.name);
    for (size_t k = 0; k < kSteps.size(); ++k) {
      fmt::print(" {:>9}", fmt::format("{}/{}", s.ok_by_step[k], s.frames_by_step[k]));
    }
    fmt::print("\n");
  }
  return 0;
}

}  // namespace ceilnav::app
