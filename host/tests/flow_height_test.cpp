#include "host/flow_height.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <opencv2/core.hpp>

#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/run_scanner_ref.hpp"
#include "golden/scene.hpp"

namespace ceilnav::host {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

CameraConfig make_config(double pitch_deg, bool distorted) {
  CameraConfig c;
  c.camera_matrix = {500.0, 0.0, 322.0, 0.0, 500.0, 238.0, 0.0, 0.0, 1.0};
  if (distorted) c.distortion_coefficients = {-0.2, 0.05, 5e-4, -3e-4, 0.0};
  c.camera_pitch_deg = pitch_deg;
  c.camera_height_m = 0.5;
  c.ceiling_height_m = 3.0;
  return c;
}

// Normalised coordinates of a world point through the golden projection and
// this camera model's undistortion.
Eigen::Vector2d seen_at(const CameraConfig& c, const golden::CameraPose& pose,
                        const Eigen::Vector3d& pt, bool distorted) {
  const auto px = golden::project_point(c, pose, pt, distorted);
  EXPECT_TRUE(px.has_value());
  return CameraModel(c).normalise(px->x(), px->y());
}

TEST(FlowHeight, ExactProjectionsAnyPitchAndYaw) {
  for (bool distorted : {false, true}) {
    for (double pitch_deg : {20.0, 35.0, 50.0, 70.0, 90.0}) {
      const CameraConfig c = make_config(pitch_deg, distorted);
      for (double yaw_deg : {-15.0, 0.0, 15.0}) {
        for (double d : {0.1, 0.5}) {
          // The robot moves along +X (along the tape) with heading yaw: the
          // motion is at -yaw from the heading.
          const golden::CameraPose p1{0.0, 0.2, yaw_deg * kDeg}, p2{d, 0.2, yaw_deg * kDeg};
          // A ceiling point in view of both frames: ahead by an amount that
          // keeps it inside the field of view for this pitch.
          const double ahead =
              c.ceiling_above_camera_m() / std::tan((pitch_deg + 5.0) * kDeg) + 0.6;
          const Eigen::Vector3d pt(ahead, 0.1, c.ceiling_height_m);
          const Eigen::Vector2d a = seen_at(c, p1, pt, distorted);
          const Eigen::Vector2d b = seen_at(c, p2, pt, distorted);
          const HeightEstimate h =
              ceiling_height_from_flow(a.y(), b.y(), pitch_deg * kDeg, d, -yaw_deg * kDeg);
          ASSERT_EQ(h.status, Status::ok) << pitch_deg << " " << yaw_deg;
          EXPECT_NEAR(h.ceiling_above_camera_m, c.ceiling_above_camera_m(), 1e-9)
              << pitch_deg << " " << yaw_deg << " " << distorted;
          // Range: the point's horizontal distance along the heading at frame 1.
          const double range =
              (pt.x() - p1.x_m) * std::cos(p1.yaw_rad) + (pt.y() - p1.y_m) * std::sin(p1.yaw_rad);
          EXPECT_NEAR(h.range_m, range, 1e-9);
        }
      }
    }
  }
}

// Seed 000 eq. 44 (cos^2) agrees with the general form; eq. 55 (cos) does not.
TEST(FlowHeight, Eq44HoldsEq55DoesNot) {
  for (double pitch_deg : {20.0, 45.0, 70.0}) {
    const CameraConfig c = make_config(pitch_deg, false);
    const double p = pitch_deg * kDeg, d = 0.4;
    const Eigen::Vector3d pt(4.0, 0.0, c.ceiling_height_m);
    const Eigen::Vector2d a = seen_at(c, {0.0, 0.0, 0.0}, pt, false);
    const Eigen::Vector2d b = seen_at(c, {d, 0.0, 0.0}, pt, false);
    // Seed coordinates: v up, v' = v - vv = tan p - y.
    const double v1 = std::tan(p) - a.y(), v2 = std::tan(p) - b.y();
    const double eq44 = d * v1 * v2 * std::cos(p) * std::cos(p) / (v2 - v1);
    const double eq55 = d * v1 * v2 * std::cos(p) / (v2 - v1);
    const double eq57 = d * v2 * (1.0 - v1 * std::sin(p) * std::cos(p)) / (v2 - v1);
    EXPECT_NEAR(eq44, c.ceiling_above_camera_m(), 1e-9);
    EXPECT_GT(std::abs(eq55 - c.ceiling_above_camera_m()), 0.05);
    EXPECT_NEAR(eq55 * std::cos(p), c.ceiling_above_camera_m(), 1e-9);
    EXPECT_NEAR(eq57, 4.0, 1e-9);  // eq. 57 (range) is right
    const HeightEstimate h = ceiling_height_from_flow(a.y(), b.y(), p, d);
    EXPECT_NEAR(h.ceiling_above_camera_m, eq44, 1e-9);
  }
}

TEST(FlowHeight, DegenerateInputsAreStatuses) {
  const double p = 45 * kDeg;
  EXPECT_EQ(ceiling_height_from_flow(-0.3, -0.35, p, 0.0).status, Status::degenerate);  // no motion
  EXPECT_EQ(ceiling_height_from_flow(-0.3, -0.35, p, -0.2).status, Status::degenerate);
  EXPECT_EQ(ceiling_height_from_flow(-0.3, -0.3, p, 0.2).status,
            Status::degenerate);  // no parallax
  EXPECT_EQ(ceiling_height_from_flow(-0.3, -0.25, p, 0.2).status, Status::degenerate);  // wrong way
  EXPECT_EQ(ceiling_height_from_flow(1.0, -0.3, p, 0.2).status, Status::degenerate);    // horizon
  EXPECT_EQ(ceiling_height_from_flow(1.5, -0.3, p, 0.2).status, Status::degenerate);    // below it
  EXPECT_EQ(ceiling_height_from_flow(NAN, -0.3, p, 0.2).status, Status::degenerate);
  EXPECT_EQ(ceiling_height_from_flow(-0.3, -0.35, p, 0.2, 90 * kDeg).status, Status::degenerate);
  const HeightEstimate ok = ceiling_height_from_flow(-0.3, -0.35, p, 0.2);
  EXPECT_EQ(ok.status, Status::ok);
  EXPECT_GT(ok.ceiling_above_camera_m, 0.0);
}

std::vector<stream::RunRecord> runs_of(const cv::Mat& grey, int threshold, int background) {
  cv::Mat mask = grey >= threshold;
  return golden::find_runs_ref(
      grey, mask,
      {static_cast<uint8_t>(background), static_cast<uint16_t>(2), static_cast<uint16_t>(16)});
}

// Two rendered frames of the corridor: the end of the first tape piece (x = 6 m)
// is tracked while the robot moves 1 m along the tape.
TEST(FlowHeight, RenderedTapeEndGivesCeilingHeight) {
  for (double pitch_deg : {30.0, 45.0}) {
    for (double yaw_deg : {-8.0, 0.0, 8.0}) {
      CameraConfig c = make_config(pitch_deg, true);
      const CameraModel cam(c);
      golden::CorridorOptions co;
      co.branch_length_m = 0.0;
      const golden::CeilingScene scene = golden::corridor_scene(c.tape_width_m, co);
      const double d = 1.0;
      const golden::CameraPose p1{0.5, 0.1, yaw_deg * kDeg}, p2{0.5 + d, 0.1, yaw_deg * kDeg};
      golden::RenderParams rp;
      rp.noise_sigma_grey = 2.0;
      rp.blur_sigma_px = 0.7;
      std::optional<Eigen::Vector2d> ends[2];
      int k = 0;
      for (const auto& pose : {p1, p2}) {
        rp.noise_seed = static_cast<uint64_t>(k + 5);
        const cv::Mat f = golden::render_frame(c, scene, pose, rp);
        const auto runs = runs_of(f, 16 + 12, 16 + 4);
        const TapePose tp = estimate_tape_pose(runs, cam, c);
        ASSERT_EQ(tp.status, Status::ok);
        ends[k] = find_tape_end(runs, cam, c, tp);
        ASSERT_TRUE(ends[k].has_value()) << pitch_deg << " " << yaw_deg << " frame " << k;
        // Against the projected truth of the tape end (6, 0, ceiling).
        const Eigen::Vector2d truth =
            seen_at(c, pose, Eigen::Vector3d(6.0, 0.0, c.ceiling_height_m), true);
        // Bound: the threshold drops end rows covered less than threshold / peak.
        EXPECT_NEAR(ends[k]->y() * c.fy(), truth.y() * c.fy(), 1.5) << pitch_deg << " " << yaw_deg;
        EXPECT_NEAR(ends[k]->x() * c.fx(), truth.x() * c.fx(), 1.0) << pitch_deg << " " << yaw_deg;
        std::printf("  frame %d: end row error %+.3f px, column error %+.3f px\n", k,
                    (ends[k]->y() - truth.y()) * c.fy(), (ends[k]->x() - truth.x()) * c.fx());
        ++k;
      }
      const HeightEstimate h = ceiling_height_from_flow(ends[0]->y(), ends[1]->y(),
                                                        pitch_deg * kDeg, d, -yaw_deg * kDeg);
      ASSERT_EQ(h.status, Status::ok);
      std::printf("pitch %.0f yaw %+.0f: c = %.4f m (truth %.4f)\n", pitch_deg, yaw_deg,
                  h.ceiling_above_camera_m, c.ceiling_above_camera_m());
      EXPECT_NEAR(h.ceiling_above_camera_m, c.ceiling_above_camera_m(),
                  0.05 * c.ceiling_above_camera_m());
    }
  }
}

TEST(FlowHeight, NoEndWhenTheTapeIsUnbroken) {
  const CameraConfig c = make_config(45.0, false);
  const CameraModel cam(c);
  const golden::CeilingScene scene = golden::single_tape_scene(c.tape_width_m);
  golden::RenderParams rp;
  rp.noise_sigma_grey = 1.0;
  const cv::Mat f = golden::render_frame(c, scene, {0.0, 0.0, 0.05}, rp);
  const auto runs = runs_of(f, 28, 18);
  const TapePose tp = estimate_tape_pose(runs, cam, c);
  ASSERT_EQ(tp.status, Status::ok);
  EXPECT_FALSE(find_tape_end(runs, cam, c, tp).has_value());
  EXPECT_FALSE(find_tape_end({}, cam, c, tp).has_value());
}

// A track of exact projections along a curving path: the least-squares fit
// returns the height and the feature's range exactly; odometry with a scale
// error s scales the height by s (flow cannot tell c from the odometry's scale).
TEST(FlowTrack, ExactProjectionsAlongACurveGiveTheHeight) {
  for (double pitch_deg : {30.0, 45.0, 90.0}) {
    const CameraConfig c = make_config(pitch_deg, true);
    const double ahead = c.ceiling_above_camera_m() / std::tan((pitch_deg + 5.0) * kDeg) + 2.0;
    const Eigen::Vector3d pt(ahead, 0.15, c.ceiling_height_m);
    for (double scale : {1.0, 1.01, 0.99}) {
      FlowTrack track(pitch_deg * kDeg, c.ceiling_above_camera_m());
      golden::CameraPose p{};
      for (int k = 0; k < 8; ++k) {
        const double x = 0.15 * k;
        p = {x, 0.2 * std::sin(x), std::atan(0.2 * std::cos(x))};
        const Eigen::Vector2d seen = seen_at(c, p, pt, true);
        const bool continued = track.add({scale * p.x_m, scale * p.y_m, p.yaw_rad}, seen);
        EXPECT_EQ(continued, k > 0);
      }
      const FlowFit f = track.fit();
      ASSERT_EQ(f.status, Status::ok) << pitch_deg;
      EXPECT_EQ(f.frames, 8);
      EXPECT_NEAR(f.ceiling_above_camera_m, scale * c.ceiling_above_camera_m(), 1e-9) << pitch_deg;
      const double range =
          (pt.x() - p.x_m) * std::cos(p.yaw_rad) + (pt.y() - p.y_m) * std::sin(p.yaw_rad);
      EXPECT_NEAR(f.range_m, scale * range, 1e-9) << pitch_deg;
      EXPECT_LT(f.std_error_m, 1e-9);
    }
  }
}

TEST(FlowTrack, TooShortTracksAndOtherFeaturesStartOver) {
  const CameraConfig c = make_config(45.0, false);
  FlowTrack track(45.0 * kDeg, c.ceiling_above_camera_m());
  const Eigen::Vector3d a(4.0, 0.0, c.ceiling_height_m), b(6.0, 0.0, c.ceiling_height_m);
  EXPECT_FALSE(track.add({0.0, 0.0, 0.0}, seen_at(c, {0.0, 0.0, 0.0}, a, false)));
  EXPECT_TRUE(track.add({0.1, 0.0, 0.0}, seen_at(c, {0.1, 0.0, 0.0}, a, false)));
  EXPECT_EQ(track.fit().status, Status::degenerate);  // two frames
  EXPECT_TRUE(track.add({0.2, 0.0, 0.0}, seen_at(c, {0.2, 0.0, 0.0}, a, false)));
  EXPECT_EQ(track.fit().status, Status::degenerate);  // 0.2 m of travel
  EXPECT_TRUE(track.add({0.4, 0.0, 0.0}, seen_at(c, {0.4, 0.0, 0.0}, a, false)));
  EXPECT_EQ(track.fit().status, Status::ok);
  // A feature 2 m farther is another track.
  EXPECT_FALSE(track.add({0.5, 0.0, 0.0}, seen_at(c, {0.5, 0.0, 0.0}, b, false)));
  EXPECT_EQ(track.size(), 1);
  // Above the horizon of a 45 deg camera: not added.
  EXPECT_FALSE(track.add({0.6, 0.0, 0.0}, {0.0, 2.0}));
  EXPECT_EQ(track.size(), 1);
}

// Rendered frames of the default corridor camera (distortion, blur, noise):
// the tape's image width gives the height within 0.5 %, whatever the yaw and
// offset (the estimator would fail this if it were off by 1 %).
TEST(WidthHeight, RenderedTapeGivesTheHeightWithinHalfAPercent) {
  const CameraConfig c = golden::default_camera();
  const CameraModel cam(c);
  const golden::CeilingScene scene = golden::default_corridor(c);
  golden::RenderParams rp = golden::default_render_params();
  int k = 0;
  for (const golden::CameraPose pose :
       {golden::CameraPose{0.0, 0.0, 0.0}, golden::CameraPose{1.0, 0.25, 0.12},
        golden::CameraPose{2.0, -0.3, -0.1}, golden::CameraPose{17.0, 0.1, 0.05}}) {
    rp.noise_seed = static_cast<uint64_t>(100 + k++);
    const cv::Mat f = golden::render_frame(c, scene, pose, rp);
    const auto runs = runs_of(f, 18 + 12, 18 + 4);
    const TapePose tp = estimate_tape_pose(runs, cam, c);
    ASSERT_EQ(tp.status, Status::ok);
    const WidthHeight h = ceiling_height_from_tape_width(f, runs, cam, c, tp);
    ASSERT_EQ(h.status, Status::ok);
    const double err = h.ceiling_above_camera_m / c.ceiling_above_camera_m() - 1.0;
    std::printf("pose (%.1f, %+.2f, %+.2f): width height %.4f m (%+.3f %%, se %.4f m, %d rows)\n",
                pose.x_m, pose.y_m, pose.yaw_rad, h.ceiling_above_camera_m, 100.0 * err,
                h.std_error_m, h.rows);
    EXPECT_GT(h.rows, 50);
    EXPECT_LT(std::abs(err), 0.005);
  }
  // Without runs or with a failed pose: degenerate.
  const cv::Mat f = golden::render_frame(c, scene, {}, rp);
  EXPECT_EQ(ceiling_height_from_tape_width(f, {}, cam, c, TapePose{}).status, Status::degenerate);
}

// A rendered drive towards the gap at 6 m, the tape end tracked over many
// frames with odometry scaled by 1 +- 1 %: the least-squares track fit gives
// c times the scale within 0.5 %.
TEST(FlowTrack, RenderedDriveGivesTheHeightTimesTheOdometryScale) {
  const CameraConfig c = golden::default_camera();
  const CameraModel cam(c);
  const golden::CeilingScene scene = golden::default_corridor(c);
  golden::RenderParams rp = golden::default_render_params();
  std::vector<std::pair<golden::CameraPose, Eigen::Vector2d>> seen;
  double grey_bias = 0.0, run_bias = 0.0;
  for (int k = 0; k < 18; ++k) {
    const double x = 0.25 * k;
    const golden::CameraPose pose{x, 0.1 + 0.1 * std::sin(0.5 * x), 0.05 * std::cos(0.5 * x)};
    rp.noise_seed = static_cast<uint64_t>(200 + k);
    const cv::Mat f = golden::render_frame(c, scene, pose, rp);
    const auto runs = runs_of(f, 18 + 12, 18 + 4);
    const TapePose tp = estimate_tape_pose(runs, cam, c);
    if (tp.status != Status::ok) continue;
    const auto end = find_tape_end(f, runs, cam, c, tp);
    const auto run_end = find_tape_end(runs, cam, c, tp);
    if (!end || !run_end) continue;
    seen.emplace_back(pose, *end);
    const Eigen::Vector2d truth =
        seen_at(c, pose, Eigen::Vector3d(6.0, 0.0, c.ceiling_height_m), true);
    grey_bias += (end->y() - truth.y()) * c.fy();
    run_bias += (run_end->y() - truth.y()) * c.fy();
  }
  ASSERT_GE(seen.size(), 12u);
  grey_bias /= static_cast<double>(seen.size());
  run_bias /= static_cast<double>(seen.size());
  std::printf("mean end row error: grey %+.3f px, runs %+.3f px\n", grey_bias, run_bias);
  // The runs lose the faint rows of the blurred end (biased towards the tape,
  // up); the grey masses do not.
  EXPECT_LT(std::abs(grey_bias), 0.2);
  EXPECT_LT(std::abs(grey_bias), std::abs(run_bias));
  for (double scale : {1.0, 1.01, 0.99}) {
    FlowTrack track(c.camera_pitch_deg * kDeg, c.ceiling_above_camera_m());
    for (const auto& [pose, end] : seen) {
      track.add({scale * pose.x_m, scale * pose.y_m, pose.yaw_rad}, end);
    }
    const FlowFit f = track.fit();
    ASSERT_EQ(f.status, Status::ok);
    EXPECT_EQ(f.frames, static_cast<int>(seen.size()));
    const double err = f.ceiling_above_camera_m / (scale * c.ceiling_above_camera_m()) - 1.0;
    std::printf(
        "scale %.2f: flow height %.4f m over %d frames, %.2f m (%+.3f %% of c s, se %.4f)\n", scale,
        f.ceiling_above_camera_m, f.frames, f.travel_m, 100.0 * err, f.std_error_m);
    EXPECT_LT(std::abs(err), 0.005);
  }
}

}  // namespace
}  // namespace ceilnav::host
