// Host and scene faults: frames that the golden renderer
// makes with a known pose, each of one fault class, through the Navigator
// (the path of `ceilnav run`, fast backend). For every class: the documented
// status (docs/scene_faults.md), no NaN or inf in any output, the pose against
// truth where the class still allows one, and then a good frame on the same
// navigator that gives what a fresh navigator gives, within the accuracy bar.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "drivers/device.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/navigator.hpp"

namespace ceilnav::host {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// docs/results.md accuracy bar (an RMS bar; here it bounds single good frames).
constexpr double kYawBarDeg = 0.02;
constexpr double kOffsetBarM = 0.001;

// The demo camera (golden/default_scene.cpp): 640x480, mild barrel distortion,
// ceiling 2.3 m above the camera.
CameraConfig camera(double pitch_deg = 45.0) {
  CameraConfig c;
  c.image_width = 640;
  c.image_height = 480;
  c.camera_matrix = {520.0, 0.0, 321.7, 0.0, 518.5, 238.2, 0.0, 0.0, 1.0};
  c.distortion_coefficients = {-0.08, 0.015, 0.0004, -0.0003, 0.0};
  c.camera_pitch_deg = pitch_deg;
  c.camera_height_m = 0.5;
  c.ceiling_height_m = 2.8;
  c.tape_width_m = 0.05;
  return c;
}

// The demo's rendering: noise 3 grey, blur 0.7 px, background 18, tape 1200 / r^2.
golden::RenderParams render_params(uint64_t seed) {
  golden::RenderParams p;
  p.blur_sigma_px = 0.7;
  p.noise_sigma_grey = 3.0;
  p.noise_seed = seed;
  p.background_grey = 18.0;
  p.tape_gain = 1200.0;
  return p;
}

bool finite_pose(const TapePose& p) {
  return std::isfinite(p.yaw_rad) && std::isfinite(p.offset_m) && std::isfinite(p.pitch_rad) &&
         std::isfinite(p.pitch_est_rad) && std::isfinite(p.vp_u_px) && std::isfinite(p.vp_v_px) &&
         std::isfinite(p.residual_rms_px) && p.line_norm.allFinite();
}

// Every output field is finite; a failed pose leaves yaw and offset at 0.
void expect_sane(const FrameOutcome& r, const std::string& what) {
  EXPECT_TRUE(finite_pose(r.pose)) << what;
  if (r.zenith) {
    EXPECT_TRUE(finite_pose(*r.zenith)) << what;
  }
  if (r.pose.status != Status::ok) {
    EXPECT_EQ(r.pose.yaw_rad, 0.0) << what;
    EXPECT_EQ(r.pose.offset_m, 0.0) << what;
  }
  EXPECT_TRUE(r.results.valid) << what;
  EXPECT_GE(r.passes, 1) << what;
}

struct Frame {
  CameraConfig cam;
  golden::CeilingScene scene;
  golden::CameraPose pose;
  golden::RenderParams params;
  cv::Mat grey;
};

Frame render(const CameraConfig& cam, const golden::CeilingScene& scene,
             const golden::CameraPose& pose, const golden::RenderParams& params) {
  return {cam, scene, pose, params, golden::render_frame(cam, scene, pose, params)};
}

// Yaw and offset errors against truth (offset relative to the tape on y = tape_y_m).
struct Error {
  double yaw_deg, offset_mm;
};
Error error_of(const FrameOutcome& r, const Frame& f, double tape_y_m = 0.0) {
  return {(r.pose.yaw_rad - f.pose.yaw_rad) / kDeg,
          1e3 * (r.pose.offset_m - (f.pose.y_m - tape_y_m))};
}

// The pose is ok and within (yaw_deg, offset_m) of truth.
void expect_pose(const FrameOutcome& r, const Frame& f, double yaw_deg, double offset_m,
                 const std::string& what, double tape_y_m = 0.0) {
  ASSERT_EQ(r.pose.status, Status::ok) << what;
  const Error e = error_of(r, f, tape_y_m);
  std::printf("  %-44s ok  yaw err %8.4f deg  offset err %7.3f mm  points %d/%d  sigma %.4f\n",
              what.c_str(), e.yaw_deg, e.offset_mm, r.pose.points_used, r.pose.points_total,
              r.pose.yaw_sigma_rad / kDeg);
  EXPECT_LE(std::abs(e.yaw_deg), yaw_deg) << what;
  EXPECT_LE(std::abs(e.offset_mm), 1e3 * offset_m) << what;
}

FrameOutcome process(Navigator& nav, const Frame& f, Status expected, const std::string& what) {
  const FrameOutcome r = nav.process(f.grey);
  expect_sane(r, what);
  EXPECT_EQ(r.pose.status, expected)
      << what << ": " << to_string(r.pose.status) << " instead of " << to_string(expected);
  if (expected != Status::ok) {
    std::printf("  %-44s %s (runs %zu, threshold %d)\n", what.c_str(),
                std::string(to_string(r.pose.status)).c_str(), r.runs.size(), r.settings.threshold);
  }
  return r;
}

// After the fault frames, a good frame through the same navigator: the only
// state a navigator keeps is the previous frame's threshold, used when this
// frame's histogram asks for one within threshold_tolerance_grey of it
// (navigator.hpp). So the result equals a fresh navigator's whenever the
// settings are the same, and is within the bar of truth either way.
void expect_recovers(Navigator& nav, const std::string& what) {
  const CameraConfig& cam = nav.camera();
  const golden::CameraPose pose{3.0, 0.15, 4.0 * kDeg};
  const Frame good =
      render(cam, golden::single_tape_scene(cam.tape_width_m), pose, render_params(4242));
  const FrameOutcome after = nav.process(good.grey);
  Navigator fresh_nav(cam, drivers::make_device(), nav.options());
  const FrameOutcome fresh = fresh_nav.process(good.grey);
  expect_sane(after, what + ", next good frame");
  ASSERT_EQ(after.pose.status, Status::ok) << what;
  ASSERT_EQ(fresh.pose.status, Status::ok) << what;
  const Error e = error_of(after, good);
  EXPECT_LE(std::abs(e.yaw_deg), kYawBarDeg) << what;
  EXPECT_LE(std::abs(e.offset_mm), 1e3 * kOffsetBarM) << what;
  if (after.settings == fresh.settings) {
    EXPECT_EQ(after.runs, fresh.runs) << what;
    EXPECT_EQ(after.results.moments, fresh.results.moments) << what;
    EXPECT_EQ(after.pose.yaw_rad, fresh.pose.yaw_rad) << what;
    EXPECT_EQ(after.pose.offset_m, fresh.pose.offset_m) << what;
    EXPECT_EQ(after.pose.points_used, fresh.pose.points_used) << what;
  } else {
    // Kept the previous threshold (one pass): within the tolerance of the fresh one.
    EXPECT_EQ(after.passes, 1) << what;
    EXPECT_LE(std::abs(after.settings.threshold - fresh.settings.threshold),
              nav.options().threshold_tolerance_grey)
        << what;
    EXPECT_NEAR(after.pose.yaw_rad, fresh.pose.yaw_rad, 0.01 * kDeg) << what;
    EXPECT_NEAR(after.pose.offset_m, fresh.pose.offset_m, 0.0005) << what;
  }
}

golden::CeilingScene no_scene() {
  return golden::CeilingScene{};
}

// A tape from x0 to x1 along +X on y = 0.
golden::CeilingScene tape_piece(double x0_m, double x1_m) {
  golden::CeilingScene s;
  s.tapes.push_back({x0_m, 0.0, x1_m, 0.0, 0.05});
  return s;
}

// ---------------------------------------------------------------------------

TEST(SceneFaults, NoTape) {
  Navigator nav(camera(), drivers::make_device());
  // Bare ceiling at several noise levels: the 4.5-sigma threshold admits no
  // two-pixel run, or only isolated specks.
  for (double noise : {1.0, 2.0, 3.0, 5.0}) {
    golden::RenderParams p = render_params(7);
    p.noise_sigma_grey = noise;
    const std::string what = "bare ceiling, noise " + std::to_string(noise);
    process(nav, render(camera(), no_scene(), {}, p), Status::no_tape, what);
  }
  // The tape is there but out of view (heading 60 deg away from it).
  process(
      nav,
      render(camera(), golden::single_tape_scene(0.05), {0.0, 0.1, 60.0 * kDeg}, render_params(8)),
      Status::no_tape, "tape out of view");
  expect_recovers(nav, "no tape");
}

TEST(SceneFaults, BlackFrames) {
  Navigator nav(camera(), drivers::make_device());
  golden::RenderParams p = render_params(9);
  p.background_grey = 0.0;
  p.tape_gain = 0.0;  // flash off
  p.noise_sigma_grey = 0.0;
  const FrameOutcome r = process(nav, render(camera(), golden::single_tape_scene(0.05), {}, p),
                                 Status::no_tape, "black frame");
  EXPECT_TRUE(r.runs.empty());
  // Black with noise clipped at 0: the median is 0 and so is the median
  // deviation, the threshold is 3 grey and ~10 % of the pixels pass it —
  // thousands of runs, all specks (no chain spans min_row_span_px rows or columns).
  p.noise_sigma_grey = 2.0;
  const FrameOutcome rn = process(nav, render(camera(), golden::single_tape_scene(0.05), {}, p),
                                  Status::no_tape, "black frame with noise");
  EXPECT_GT(rn.runs.size(), 1000u);
  expect_recovers(nav, "black frames");
}

TEST(SceneFaults, SaturatedFrames) {
  Navigator nav(camera(), drivers::make_device());
  const golden::CameraPose pose{1.0, 0.1, 5.0 * kDeg};
  const auto scene = golden::single_tape_scene(0.05);
  // Everything at 255: no threshold can rise above the background -> no_tape.
  golden::RenderParams white = render_params(10);
  white.background_grey = 400.0;
  process(nav, render(camera(), scene, pose, white), Status::no_tape, "white frame");
  // The tape return clips at 255 over most of its length: the clipped runs are
  // still symmetric about the centre line.
  for (double gain : {5000.0, 100000.0}) {
    golden::RenderParams p = render_params(11);
    p.tape_gain = gain;
    const Frame f = render(camera(), scene, pose, p);
    const FrameOutcome r = process(nav, f, Status::ok, "saturated tape");
    expect_pose(r, f, kYawBarDeg, kOffsetBarM, "tape saturated, gain " + std::to_string(gain));
  }
  // Over-exposed ceiling (background 250, noise 3) with the tape at 255: the
  // threshold is 255; background noise adds specks.
  golden::RenderParams bright = render_params(12);
  bright.background_grey = 250.0;
  const Frame fb = render(camera(), scene, pose, bright);
  const FrameOutcome rb = process(nav, fb, Status::ok, "background 250");
  expect_pose(rb, fb, kYawBarDeg, kOffsetBarM, "background 250, tape at 255");
  expect_recovers(nav, "saturated frames");
}

TEST(SceneFaults, TapePartlyVisible) {
  Navigator nav(camera(), drivers::make_device());
  const golden::CameraPose pose{0.0, 0.1, 5.0 * kDeg};
  // The tape ends ahead of the camera: only its near part is seen.
  for (double end : {2.0, 3.0, 5.0}) {
    const Frame f = render(camera(), tape_piece(-10.0, end), pose, render_params(13));
    const FrameOutcome r = process(nav, f, Status::ok, "tape ends");
    expect_pose(r, f, kYawBarDeg, kOffsetBarM, "tape ends " + std::to_string(end) + " m ahead");
  }
  // Only the far part is seen (the tape starts ahead): fewer, dimmer rows
  // near the horizon, a longer lever.
  for (double start : {2.0, 3.0, 5.0}) {
    const Frame f = render(camera(), tape_piece(start, 100.0), pose, render_params(14));
    const FrameOutcome r = process(nav, f, Status::ok, "tape starts");
    expect_pose(r, f, 0.1, 0.01, "tape starts " + std::to_string(start) + " m ahead");
  }
  // Short pieces: 10 and 20 cm span 14 and 25 rows, enough points, but the
  // yaw's standard error (0.28 and 0.095 deg) is beyond max_yaw_sigma_deg
  // (0.05): too_few_points. 3 cm is a speck: no_tape.
  for (double len : {0.1, 0.2}) {
    const Frame f = render(camera(), tape_piece(2.2, 2.2 + len), pose, render_params(15));
    const FrameOutcome r =
        process(nav, f, Status::too_few_points, std::to_string(len) + " m of tape");
    EXPECT_GE(r.pose.points_used, nav.options().pose.min_points);
    EXPECT_GT(r.pose.yaw_sigma_rad, nav.options().pose.max_yaw_sigma_deg * kDeg);
  }
  const Frame stub = render(camera(), tape_piece(2.2, 2.23), pose, render_params(15));
  process(nav, stub, Status::no_tape, "3 cm of tape");
  expect_recovers(nav, "tape partly visible");
}

TEST(SceneFaults, TapeAtTheImageEdge) {
  // Zenith camera, the tape band straddling the right image border over its
  // whole length: every run touches the border (no unbiased centre).
  {
    Navigator nav(camera(90.0), drivers::make_device());
    const auto scene = golden::single_tape_scene(0.05);
    process(nav, render(camera(90.0), scene, {0.0, 1.45, 0.0}, render_params(16)),
            Status::too_few_points, "band on the right border");
    // The band leaves through the side: the rows inside the image are used.
    for (double yaw_deg : {2.0, 5.0, 10.0}) {
      const Frame f = render(camera(90.0), scene, {0.0, 1.45, yaw_deg * kDeg}, render_params(17));
      const FrameOutcome r = process(nav, f, Status::ok, "band leaves through the side");
      expect_pose(r, f, kYawBarDeg, kOffsetBarM,
                  "zenith, band leaves the side, yaw " + std::to_string(yaw_deg));
    }
    expect_recovers(nav, "tape at the image edge (zenith)");
  }
  // Pitch 45: the tape far to the side, crossing the image corner.
  Navigator nav(camera(), drivers::make_device());
  for (double y : {2.6, -2.6, 3.0}) {
    const Frame f =
        render(camera(), golden::single_tape_scene(0.05), {0.0, y, 0.0}, render_params(18));
    const FrameOutcome r = process(nav, f, Status::ok, "tape in the corner");
    expect_pose(r, f, 0.03, 0.002, "pitch 45, tape " + std::to_string(y) + " m to the side");
  }
  expect_recovers(nav, "tape at the image edge");
}

TEST(SceneFaults, SeveralParallelTapes) {
  Navigator nav(camera(), drivers::make_device());
  golden::CorridorOptions o;
  o.gaps_m.clear();
  o.branch_length_m = 0.0;
  o.second_tape = true;
  o.second_tape_y_m = 1.0;
  golden::CeilingScene scene = golden::corridor_scene(0.05, o);
  scene.tapes.push_back({-5.0, -1.0, 60.0, -1.0, 0.05});  // tapes on y = -1, 0, 1
  // The main tape is the best-supported line; lines within 10 % of its support
  // are tied and the one nearest the principal point wins. The principal ray
  // meets the ceiling at y + c cot(p) sin(psi).
  const double c = camera().ceiling_above_camera_m();
  for (double y : {0.1, -0.2, 0.7, -0.75}) {
    const golden::CameraPose pose{0.0, y, 5.0 * kDeg};
    const double y_pp = y + c * std::sin(pose.yaw_rad);  // cot 45 deg = 1
    const double tape_y = std::round(y_pp);
    const Frame f = render(camera(), scene, pose, render_params(19));
    const FrameOutcome r = process(nav, f, Status::ok, "three tapes");
    expect_pose(r, f, kYawBarDeg, kOffsetBarM,
                "three tapes, camera y " + std::to_string(y) + ", tape y " + std::to_string(tape_y),
                tape_y);
  }
  expect_recovers(nav, "several tapes");
}

TEST(SceneFaults, TBranch) {
  Navigator nav(camera(), drivers::make_device());
  golden::CorridorOptions o;
  o.gaps_m.clear();  // the branch at x = 10 m, 3 m to the right
  const auto scene = golden::corridor_scene(0.05, o);
  for (const golden::CameraPose pose :
       {golden::CameraPose{6.0, 0.1, 5.0 * kDeg}, golden::CameraPose{8.0, 0.1, 5.0 * kDeg},
        golden::CameraPose{9.0, -0.3, -8.0 * kDeg}, golden::CameraPose{7.0, -0.5, 40.0 * kDeg}}) {
    const Frame f = render(camera(), scene, pose, render_params(20));
    const FrameOutcome r = process(nav, f, Status::ok, "T-branch");
    expect_pose(r, f, kYawBarDeg, kOffsetBarM,
                "T-branch, camera x " + std::to_string(pose.x_m) + " yaw " +
                    std::to_string(pose.yaw_rad / kDeg));
    EXPECT_LT(r.pose.points_used, r.pose.points_total);  // the crossing rows are gated out
  }
  expect_recovers(nav, "T-branch");
}

TEST(SceneFaults, Gaps) {
  Navigator nav(camera(), drivers::make_device());
  golden::CorridorOptions o;  // gaps at 6-6.8, 15-16.2, 27-27.5 m
  o.branch_length_m = 0.0;
  const auto scene = golden::corridor_scene(0.05, o);
  for (double x : {3.0, 4.0, 5.0, 12.0, 14.0, 24.0}) {
    const Frame f = render(camera(), scene, {x, 0.1, 5.0 * kDeg}, render_params(21));
    const FrameOutcome r = process(nav, f, Status::ok, "gaps");
    expect_pose(r, f, kYawBarDeg, kOffsetBarM, "gaps, camera x " + std::to_string(x));
  }
  expect_recovers(nav, "gaps");
}

// Large yaw: the tape crosses the image, its vanishing point (tan psi / cos p)
// lies far outside it (yaw 80: ~4200 px to the side). The pose holds up to
// max_abs_yaw_deg (80); beyond, the tape runs along the horizon: degenerate.
TEST(SceneFaults, VanishingPointFarOutsideTheImage) {
  Navigator nav(camera(), drivers::make_device());
  const auto scene = golden::single_tape_scene(0.05);
  for (double yaw_deg : {60.0, 70.0, 75.0, 80.0, -70.0}) {
    for (double y : {1.0, 2.0}) {
      const double off = yaw_deg > 0 ? -y : y;  // the tape ahead of the camera
      const Frame f = render(camera(), scene, {0.0, off, yaw_deg * kDeg}, render_params(22));
      const FrameOutcome r = process(nav, f, Status::ok, "large yaw");
      expect_pose(r, f, 0.03, kOffsetBarM,
                  "yaw " + std::to_string(yaw_deg) + ", offset " + std::to_string(off));
      EXPECT_TRUE(r.pose.vp_finite);
      EXPECT_GT(std::abs(r.pose.vp_u_px - 320.0), 1000.0);
    }
  }
  for (double yaw_deg : {82.0, 85.0, 90.0, -90.0}) {
    for (double y : {1.0, 2.0, 3.0}) {
      const double off = yaw_deg > 0 ? -y : y;
      process(nav, render(camera(), scene, {0.0, off, yaw_deg * kDeg}, render_params(23)),
              Status::degenerate,
              "yaw " + std::to_string(yaw_deg) + ", offset " + std::to_string(off));
    }
  }
  expect_recovers(nav, "vanishing point far outside");
}

TEST(SceneFaults, NearZenithPitch) {
  const auto scene = golden::single_tape_scene(0.05);
  for (double pitch : {85.0, 87.0, 89.0, 89.9, 89.99, 89.9999, 90.0}) {
    Navigator nav(camera(pitch), drivers::make_device());
    const Frame f = render(camera(pitch), scene, {0.0, 0.1, 5.0 * kDeg}, render_params(24));
    const FrameOutcome r = process(nav, f, Status::ok, "near zenith");
    expect_pose(r, f, kYawBarDeg, kOffsetBarM, "pitch " + std::to_string(pitch));
    EXPECT_EQ(r.zenith.has_value(), pitch >= 89.999);
    // The vanishing point v = cy + fy tan p goes to infinity; it is reported
    // while it stays below 1e9 px, never as inf or NaN.
    if (r.pose.vp_finite) {
      EXPECT_GT(r.pose.vp_v_px, 238.2 + 518.5 * std::tan(pitch * kDeg) - 1.0);
    }
    if (pitch == 90.0) {
      EXPECT_FALSE(r.pose.vp_finite);
    }
    expect_recovers(nav, "pitch " + std::to_string(pitch));
  }
}

}  // namespace
}  // namespace ceilnav::host
