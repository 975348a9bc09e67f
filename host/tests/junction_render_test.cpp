// host::detect_junctions on rendered frames (junction_scenes.hpp): every
// scene's junction found at one distance per pitch with its kind, side,
// distance and angle; nothing on straight tape; nothing on the distractor
// ceilings (golden::distractor_scenes); nothing without an ok centre line.
// The sweep over distances is junction_sweep_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "junction_scenes.hpp"

namespace ceilnav::host {
namespace {

using namespace junction_test;

std::string describe(const std::vector<Junction>& js) {
  std::string s;
  for (const Junction& j : js) {
    s += std::string(to_string(j.kind)) + " " + std::string(to_string(j.side)) + " at " +
         std::to_string(j.distance_m) + " m (end width ratio " +
         std::to_string(j.evidence.end_width_ratio) + "); ";
  }
  return s.empty() ? "none" : s;
}

// Each scene with the camera 2.5 m before its junction at pitch 45 deg, 4 m
// at 30 deg, 1.5 m at 60 deg and 0.2 m past it at the zenith.
TEST(JunctionRender, EachSceneFoundWithKindSideAndDistance) {
  for (const TruthScene& ts : scenes()) {
    const TruthJunction& t = ts.junctions.front();
    for (const auto& [pitch, d] : {std::pair{30.0, 4.0}, std::pair{45.0, 2.5}, std::pair{60.0, 1.5},
                                   std::pair{90.0, -0.2}}) {
      const double x = t.x_m - d;
      const Frame f = run(camera(pitch), ts.scene, {x, 0.1, 5.0 * kDeg}, 7);
      const std::string what = ts.name + ", pitch " + std::to_string(pitch);
      ASSERT_EQ(f.outcome.pose.status, Status::ok) << what;
      int unknown = 0;
      const Junction* j = find_match(f, ts, t, x, unknown);
      EXPECT_EQ(unknown, 0) << what << ": " << describe(f.junctions);
      ASSERT_NE(j, nullptr) << what << ": " << describe(f.junctions);
      EXPECT_NEAR(j->distance_m, d, 0.03) << what;
      const JunctionEvidence& e = j->evidence;
      if (t.kind == JunctionKind::tape_end) {
        EXPECT_EQ(j->side, JunctionSide::none);
        EXPECT_EQ(j->branch_angle_rad, 0.0);
        EXPECT_EQ(e.branch_runs, 0);
      } else {
        EXPECT_NEAR(j->branch_angle_rad / kDeg, 90.0, 5.0) << what;
        EXPECT_GT(e.branch_runs, 0) << what;
        EXPECT_LE(std::abs(e.branch_thickness_m - kW), e.thickness_allowance_m) << what;
        EXPECT_GE(e.branch_length_m, JunctionOptions{}.min_branch_length_m) << what;
      }
      if (t.kind != JunctionKind::t_branch) {
        // The line's end is the junction's, bright, with the band seen empty beyond.
        EXPECT_NEAR(e.line_end_m, d, 0.05) << what;
        EXPECT_NEAR(e.end_width_ratio, 1.0, 0.3) << what;
        EXPECT_GE(e.empty_beyond_m, JunctionOptions{}.min_empty_beyond_m) << what;
        EXPECT_GE(e.end_contrast_sigma, JunctionOptions{}.min_end_contrast_sigma) << what;
        EXPECT_LT(e.line_end_m + e.empty_beyond_m, e.view_end_m + 1e-9) << what;
      } else {
        EXPECT_GT(e.line_end_m, d + kW) << what;  // the line continues past the branch
      }
    }
  }
}

// Unbroken straight tape: no junction at any pitch, offset or yaw.
TEST(JunctionRender, StraightTapeHasNone) {
  const golden::CeilingScene tape = golden::single_tape_scene(kW);
  int frames = 0;
  for (double pitch : {30.0, 45.0, 60.0, 75.0, 90.0}) {
    for (const golden::CameraPose& pose :
         {golden::CameraPose{0.0, 0.0, 0.0}, golden::CameraPose{3.0, 0.3, 10.0 * kDeg},
          golden::CameraPose{7.0, -0.4, -20.0 * kDeg}, golden::CameraPose{1.0, 0.1, 35.0 * kDeg}}) {
      const Frame f = run(camera(pitch), tape, pose, 50 + static_cast<uint64_t>(frames++));
      ASSERT_EQ(f.outcome.pose.status, Status::ok) << pitch;
      EXPECT_TRUE(f.junctions.empty())
          << "pitch " << pitch << ", camera x " << pose.x_m << ": " << describe(f.junctions);
    }
  }
}

// Ceilings without tape (lamps, panels, tubes, bars, dashes, a 10 cm strip):
// no junction. Where the centre line is not ok (all but the tubes, a known
// false accept of the tape evidence) the detector claims nothing; on the
// tubes it must not read their ends as tape ends.
TEST(JunctionRender, DistractorsHaveNone) {
  int frames = 0, pose_ok = 0;
  for (const auto& [name, scene] : golden::distractor_scenes()) {
    for (double pitch : {30.0, 45.0, 68.0, 90.0}) {
      for (const golden::CameraPose& pose :
           {golden::CameraPose{0.0, 0.0, 0.0}, golden::CameraPose{0.7, 0.35, 8.0 * kDeg},
            golden::CameraPose{0.3, -0.5, -25.0 * kDeg}}) {
        const Frame f = run(camera(pitch), scene, pose, 300 + static_cast<uint64_t>(frames++));
        if (f.outcome.pose.status == Status::ok) ++pose_ok;
        EXPECT_TRUE(f.junctions.empty())
            << name << ", pitch " << pitch << ": " << describe(f.junctions);
      }
    }
  }
  std::printf("distractors: %d frames, %d with an ok centre line, no junction\n", frames, pose_ok);
}

// Without an ok centre-line pose there is nothing to measure along.
TEST(JunctionRender, NeedsAnOkCentreLine) {
  const std::vector<TruthScene> all = scenes();
  const TruthScene& t_left = all[2];
  const CameraConfig cam = camera(45.0);
  Navigator nav(cam, drivers::make_device());
  const FrameOutcome o =
      nav.process(golden::render_frame(cam, t_left.scene, {kJx - 2.5, 0.1, 0.0}, render_params(9)));
  ASSERT_EQ(o.pose.status, Status::ok);
  ASSERT_FALSE(detect_junctions(o, nav.camera_model(), cam).empty());
  for (Status st :
       {Status::too_few_points, Status::inconsistent, Status::degenerate, Status::jump}) {
    TapePose p = o.pose;
    p.status = st;
    EXPECT_TRUE(detect_junctions(o.runs, o.settings, nav.camera_model(), cam, p).empty())
        << to_string(st);
  }
  TapePose zenith = o.pose;
  zenith.method = "zenith_moments";
  EXPECT_TRUE(detect_junctions(o.runs, o.settings, nav.camera_model(), cam, zenith).empty());
  EXPECT_TRUE(detect_junctions({}, o.settings, nav.camera_model(), cam, o.pose).empty());
}

TEST(JunctionRender, Names) {
  EXPECT_EQ(to_string(JunctionKind::none), "none");
  EXPECT_EQ(to_string(JunctionKind::t_branch), "t_branch");
  EXPECT_EQ(to_string(JunctionKind::l_turn), "l_turn");
  EXPECT_EQ(to_string(JunctionKind::tape_end), "tape_end");
  EXPECT_EQ(to_string(JunctionSide::none), "none");
  EXPECT_EQ(to_string(JunctionSide::left), "left");
  EXPECT_EQ(to_string(JunctionSide::right), "right");
  EXPECT_EQ(to_string(JunctionSide::both), "both");
}

}  // namespace
}  // namespace ceilnav::host
