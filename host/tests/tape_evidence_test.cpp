// The evidence a tape result rests on (TapeEvidence, docs/host_maths.md
// section 4, "Evidence"): one rendered case per check that violates it and
// must not be `ok`, beside the tape that satisfies it and is; distractor
// ceilings without tape (lamp grids, bars, tubes) that must never be `ok`;
// the zenith band evidence; tracking between frames.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/navigator.hpp"

namespace ceilnav::host {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The demo camera (golden::default_camera: 640x480, mild barrel distortion,
// ceiling 2.3 m above the camera, tape 5 cm) at `pitch_deg`.
CameraConfig camera(double pitch_deg = 45.0) {
  CameraConfig c = golden::default_camera();
  c.camera_pitch_deg = pitch_deg;
  return c;
}

// The demo's rendering (noise 3, blur 0.7 px, background 18, tape 1200 / r^2).
golden::RenderParams render_params(uint64_t seed) {
  golden::RenderParams p = golden::default_render_params();
  p.noise_seed = seed;
  return p;
}

// Strips along X on y (tape if 5 cm wide; anything else otherwise).
golden::CeilingScene strips(const std::vector<std::pair<double, double>>& pieces, double y_m,
                            double width_m) {
  golden::CeilingScene s;
  for (const auto& [x0, x1] : pieces) s.tapes.push_back({x0, y_m, x1, y_m, width_m});
  return s;
}

FrameOutcome run(const CameraConfig& cam, const golden::CeilingScene& scene,
                 const golden::CameraPose& pose, uint64_t seed = 1) {
  Navigator nav(cam, drivers::make_device());
  return nav.process(golden::render_frame(cam, scene, pose, render_params(seed)));
}

void print(const std::string& what, const FrameOutcome& r) {
  const TapeEvidence& e = r.pose.evidence;
  std::printf(
      "  %-44s %-14s runs %3d width %2d/%2d (median ratio %.2f) visible %.2f m of %.2f m, "
      "pieces %d (dropped %d), border ends %d, contrast %.1f sigma",
      what.c_str(), std::string(to_string(r.pose.status)).c_str(), e.runs, e.width_consistent,
      e.width_sampled, e.width_ratio_median, e.visible_length_m, e.span_m, e.pieces,
      e.pieces_dropped, e.ends_at_border, e.contrast_sigma);
  if (r.zenith) {
    const TapeEvidence& z = r.zenith->evidence;
    std::printf("; zenith %s band %.1f px (predicted %.1f) length %.0f of chord %.0f, fill %.2f",
                std::string(to_string(r.zenith->status)).c_str(), z.band_width_px,
                z.band_width_predicted_px, z.band_length_px, z.band_chord_px, z.band_fill);
  }
  std::printf("\n");
}

// Visible length: pieces of 10, 14 and 20 cm (14 cm was `ok` before the
// check); the yaw standard-error gate alone depends on the noise.
TEST(TapeEvidence, ShortPiecesAreTooFewPoints) {
  const golden::CameraPose pose{0.0, 0.1, 3.0 * kDeg};
  for (double len : {0.10, 0.14, 0.20}) {
    const FrameOutcome r = run(camera(), strips({{2.2, 2.2 + len}}, 0.0, 0.05), pose, 15);
    print("piece of " + std::to_string(len) + " m", r);
    EXPECT_EQ(r.pose.status, Status::too_few_points) << len;
    EXPECT_EQ(r.pose.yaw_rad, 0.0);
  }
  // The same place with 0.6 m of tape reaching the image's top border: ok.
  const FrameOutcome r = run(camera(), strips({{-10.0, 2.8}}, 0.0, 0.05), pose, 15);
  print("tape ending 2.8 m ahead", r);
  ASSERT_EQ(r.pose.status, Status::ok);
  EXPECT_GE(r.pose.evidence.visible_length_m, TapePoseOptions{}.min_visible_length_m);
}

// Width: a strip along X crossing the image like a tape but twice its width
// (wider ones fail the centre-point width gate already: degenerate).
TEST(TapeEvidence, WideStripIsInconsistent) {
  const golden::CameraPose pose{0.0, 0.15, 4.0 * kDeg};
  for (double pitch : {45.0, 90.0}) {
    const FrameOutcome tape = run(camera(pitch), strips({{-10.0, 100.0}}, 0.0, 0.05), pose, 3);
    print("tape 5 cm, pitch " + std::to_string(pitch), tape);
    EXPECT_EQ(tape.pose.status, Status::ok);
    EXPECT_GT(tape.pose.evidence.width_consistent, tape.pose.evidence.width_sampled / 2);
    const FrameOutcome bar = run(camera(pitch), strips({{-10.0, 100.0}}, 0.0, 0.10), pose, 3);
    print("strip 10 cm, pitch " + std::to_string(pitch), bar);
    EXPECT_EQ(bar.pose.status, Status::inconsistent);
    EXPECT_LT(bar.pose.evidence.width_consistent, bar.pose.evidence.width_sampled / 2);
    EXPECT_GT(bar.pose.evidence.width_ratio_median, 1.6);
    if (pitch == 90.0) {
      ASSERT_TRUE(tape.zenith && bar.zenith);
      EXPECT_EQ(tape.zenith->status, Status::ok);
      EXPECT_EQ(bar.zenith->status, Status::inconsistent);
      EXPECT_GT(bar.zenith->evidence.band_width_px,
                1.6 * bar.zenith->evidence.band_width_predicted_px);
    }
  }
}

// Coverage: a dashed line (0.3 m pieces, 0.9 m gaps, each gap within
// max_gap_m) covers a quarter of its span: not laid tape.
TEST(TapeEvidence, DashedLineIsInconsistent) {
  std::vector<std::pair<double, double>> dashes;
  for (double x = -6.0; x < 40.0; x += 1.2) dashes.emplace_back(x, x + 0.3);
  const golden::CameraPose pose{0.0, 0.1, 2.0 * kDeg};
  for (double pitch : {30.0, 45.0, 90.0}) {
    const FrameOutcome r = run(camera(pitch), strips(dashes, 0.0, 0.05), pose, 4);
    print("dashes 0.3 m / 0.9 m, pitch " + std::to_string(pitch), r);
    EXPECT_NE(r.pose.status, Status::ok) << pitch;
    if (r.pose.evidence.span_m > 0.0) {
      EXPECT_LT(r.pose.evidence.visible_length_m, 0.5 * r.pose.evidence.span_m) << pitch;
    }
  }
}

// Gaps: tape up to 3.5 m ahead and a 0.5 m piece on the same line 2.5 m further:
// the far piece is dropped (its gap is beyond max_gap_m), the pose rests on
// the tape and stays within the accuracy bar. With max_gap_m <= 0 it joins.
TEST(TapeEvidence, FarPieceIsNotJoined) {
  const CameraConfig cam = camera(30.0);
  const golden::CeilingScene scene = strips({{-10.0, 3.5}, {6.0, 6.5}}, 0.0, 0.05);
  const golden::CameraPose pose{0.0, 0.12, 3.0 * kDeg};
  const FrameOutcome r = run(cam, scene, pose, 5);
  print("tape to 3.5 m + piece at 6 m", r);
  ASSERT_EQ(r.pose.status, Status::ok);
  EXPECT_GE(r.pose.evidence.pieces_dropped, 1);
  EXPECT_NEAR(r.pose.yaw_rad, 3.0 * kDeg, 0.05 * kDeg);
  EXPECT_NEAR(r.pose.offset_m, 0.12, 0.002);
  NavigatorOptions joined;
  joined.pose.max_gap_m = 0.0;
  Navigator nav(cam, drivers::make_device(), joined);
  const FrameOutcome j = nav.process(golden::render_frame(cam, scene, pose, render_params(5)));
  print("same, max_gap_m = 0", j);
  EXPECT_EQ(j.pose.evidence.pieces_dropped, 0);
  EXPECT_GT(j.pose.points_used, r.pose.points_used);
}

// Border: a 0.8 m piece wholly inside the zenith camera's view is no tape;
// the same line running out of the image is.
TEST(TapeEvidence, PieceInsideTheImageIsInconsistent) {
  const golden::CameraPose pose{0.0, 0.1, 5.0 * kDeg};
  const FrameOutcome inside = run(camera(90.0), strips({{-0.4, 0.4}}, 0.0, 0.05), pose, 6);
  print("0.8 m piece inside the view, pitch 90", inside);
  EXPECT_EQ(inside.pose.status, Status::inconsistent);
  EXPECT_EQ(inside.pose.evidence.ends_at_border, 0);
  ASSERT_TRUE(inside.zenith);
  EXPECT_NE(inside.zenith->status, Status::ok);  // the band does not cross the image
  const FrameOutcome out = run(camera(90.0), strips({{-0.4, 5.0}}, 0.0, 0.05), pose, 6);
  print("the line leaving the view, pitch 90", out);
  EXPECT_EQ(out.pose.status, Status::ok);
  EXPECT_GE(out.pose.evidence.ends_at_border, 1);
}

// Distractors: the ceiling with the tape removed, lamp grids (the real
// corpus' cycloid frames look like this), square panels, a row of wide bars
// end to end, dashes and a strip twice the tape's width, at pitch 30, 45, 68 and 90 deg and several
// poses: no centre-line and no zenith result is ok. (A bare tube as narrow as the tape that runs
// out of the image is accepted: docs/results.md, known false accepts.)
TEST(TapeEvidence, DistractorCeilingsAreNeverOk) {
  std::vector<std::pair<std::string, golden::CeilingScene>> scenes;
  scenes.emplace_back("empty ceiling", golden::CeilingScene{});
  for (auto& d : golden::distractor_scenes()) {
    if (d.first != "tubes 3 cm") scenes.push_back(std::move(d));
  }
  int frames = 0;
  for (const auto& [name, scene] : scenes) {
    for (double pitch : {30.0, 45.0, 68.0, 90.0}) {
      for (const golden::CameraPose& pose :
           {golden::CameraPose{0.0, 0.0, 0.0}, golden::CameraPose{0.7, 0.35, 8.0 * kDeg},
            golden::CameraPose{0.3, -0.5, -25.0 * kDeg}}) {
        const FrameOutcome r = run(camera(pitch), scene, pose, 100 + static_cast<uint64_t>(frames));
        ++frames;
        const std::string what = name + ", pitch " + std::to_string(static_cast<int>(pitch));
        EXPECT_NE(r.pose.status, Status::ok) << what;
        if (r.zenith) {
          EXPECT_NE(r.zenith->status, Status::ok) << what;
        }
        if (r.pose.status == Status::ok || (r.zenith && r.zenith->status == Status::ok) ||
            pose.x_m == 0.0) {
          print(what, r);
        }
      }
    }
  }
  EXPECT_EQ(frames, 72);
}

// Zenith evidence on the tape itself: band width as predicted, crossing the image, fill ~1.
TEST(TapeEvidence, ZenithBandOfTheTape) {
  CameraConfig cam = camera(90.0);
  cam.distortion_coefficients = {};  // the moments cannot be undistorted
  const FrameOutcome r =
      run(cam, strips({{-10.0, 100.0}}, 0.0, 0.05), golden::CameraPose{0.0, 0.2, 12.0 * kDeg}, 8);
  print("tape, zenith", r);
  ASSERT_TRUE(r.zenith);
  ASSERT_EQ(r.zenith->status, Status::ok);
  const TapeEvidence& z = r.zenith->evidence;
  EXPECT_NEAR(z.band_width_px, z.band_width_predicted_px, 3.0);
  EXPECT_GE(z.band_length_px, 0.8 * z.band_chord_px);
  EXPECT_NEAR(z.band_fill, 1.0, 0.35);
  // Two short pieces far apart on the line: long, but little area.
  const FrameOutcome two = run(cam, strips({{-0.9, -0.75}, {0.75, 0.9}}, 0.2, 0.05),
                               golden::CameraPose{0.0, 0.0, 12.0 * kDeg}, 8);
  print("two pieces 1.5 m apart, zenith", two);
  ASSERT_TRUE(two.zenith);
  EXPECT_NE(two.zenith->status, Status::ok);
}

// Tracking (TrackOptions): a pose that moved beyond a frame's worth of motion
// is `jump` and drops the track; the next frame locks again.
TEST(TapeEvidence, TrackingFlagsJumpsAndRelocks) {
  const CameraConfig cam = camera(45.0);
  const golden::CeilingScene scene = strips({{-10.0, 100.0}}, 0.0, 0.05);
  NavigatorOptions opt;
  opt.track.enabled = true;
  Navigator nav(cam, drivers::make_device(), opt);
  const auto frame = [&](double y, double yaw_deg) {
    return nav.process(golden::render_frame(cam, scene, golden::CameraPose{0.0, y, yaw_deg * kDeg},
                                            render_params(9)));
  };
  EXPECT_EQ(frame(0.10, 2.0).pose.status, Status::ok);      // first frame: locks
  EXPECT_EQ(frame(0.12, 2.5).pose.status, Status::ok);      // within a frame's motion
  EXPECT_EQ(frame(-0.30, 2.5).pose.status, Status::jump);   // 0.42 m sideways
  EXPECT_EQ(frame(-0.30, 2.5).pose.status, Status::ok);     // track was lost: locks again
  EXPECT_EQ(frame(-0.30, 12.0).pose.status, Status::jump);  // 9.5 deg turn
  // Without tracking every frame stands alone.
  Navigator plain(cam, drivers::make_device());
  for (double y : {0.1, -0.3, 0.4}) {
    EXPECT_EQ(plain
                  .process(golden::render_frame(cam, scene, golden::CameraPose{0.0, y, 0.0},
                                                render_params(9)))
                  .pose.status,
              Status::ok);
  }
}

}  // namespace
}  // namespace ceilnav::host
