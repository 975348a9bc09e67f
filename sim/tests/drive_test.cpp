// The closed loop on a short course: the route is planned through its
// junction, the robot finishes on the tape, and the model backend (the
// cycle-level device through its registers, with random stream gaps and
// back-pressure) drives the same trajectory as the fast one, bit for bit;
// a pattern station beside a straight tape fixes the position, and one the
// map puts in the wrong place is rejected by the filter's gate.
#include "sim/drive.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "golden/default_scene.hpp"

namespace ceilnav::sim {
namespace {

Course short_course() {
  Course c;
  c.name = "short";
  TapePolyline t;
  t.points = {{-1.0, 0.0}, {4.0, 0.0}, {4.0, 3.0}};
  t.gaps_m = {{2.0, 2.6}};
  c.tapes.push_back(t);
  c.ceiling_height_m = 2.5;
  c.start = {0.0, 0.0, 0.0};
  c.route = {Turn::left};
  validate(c);
  return c;
}

DriveConfig config(drivers::Backend backend) {
  DriveConfig d;
  d.course = short_course();
  d.camera = golden::default_camera();
  d.camera.image_width = 320;
  d.camera.image_height = 240;
  d.camera.camera_matrix[0] /= 2;
  d.camera.camera_matrix[2] /= 2;
  d.camera.camera_matrix[4] /= 2;
  d.camera.camera_matrix[5] /= 2;
  d.render.render = golden::default_render_params();
  d.device.backend = backend;
  d.device.gap_probability = 0.1;
  d.device.backpressure_probability = 0.3;
  d.ekf.odometry.yaw_scale_sigma = 1e-6;
  d.robot.left_scale = 1.001;
  d.robot.right_scale = 0.999;
  return d;
}

// A straight tape with a pattern station 1.2 m to its left at x = 4: the
// camera (pitch 60) has its panel in view from about 2.5 m before it.
DriveConfig station_config() {
  DriveConfig d = config(drivers::Backend::fast);
  Course& c = d.course;
  c.name = "station";
  c.tapes.clear();
  TapePolyline t;
  t.points = {{-1.0, 0.0}, {5.5, 0.0}};
  c.tapes.push_back(t);
  c.route.clear();
  c.start = {0.3, 0.0, 0.0};
  c.patterns = {{7, 4.0, 1.2, 0.0}};
  validate(c);
  d.camera.camera_pitch_deg = 60.0;
  d.mount.forward_m = d.believed_mount.forward_m = 0.1;
  // Both wheels 0.5 % long: the along-track error grows by 5 mm per metre
  // until a fix (no landmark before the tape's end).
  d.robot.left_scale = d.robot.right_scale = 1.005;
  d.ekf.odometry.wheel_var_per_m = d.robot.slip_sigma_sqrt_m * d.robot.slip_sigma_sqrt_m;
  return d;
}

TEST(Drive, PatternStationFixesThePosition) {
  Drive d(station_config());
  d.run();
  const DriveSummary s = d.summary();
  EXPECT_TRUE(s.finished);
  ASSERT_EQ(s.stations.size(), 1u);
  const DriveSummary::Station& st = s.stations[0];
  EXPECT_EQ(st.id, 7);
  EXPECT_GE(st.fixes_accepted, 5);
  EXPECT_EQ(s.counters.pattern.accepted, st.fixes_accepted);
  EXPECT_EQ(s.counters.pattern.rejected_gate, 0);
  // Every ok fix lies within 3 mm and 0.1 deg of the true camera; an ok fix
  // read the station's identity (its mirror print: the camera sees it with
  // its +x pointing left) or none.
  int ok = 0;
  for (const PatternFixRecord& r : d.pattern_fixes()) {
    if (r.status != "ok") continue;
    ++ok;
    EXPECT_LT(std::hypot(r.fix.x_m - r.truth.x_m, r.fix.y_m - r.truth.y_m), 0.003) << r.frame;
    EXPECT_LT(std::abs(std::remainder(r.fix.yaw_rad - r.truth.yaw_rad, 2.0 * std::numbers::pi)),
              0.1 * std::numbers::pi / 180.0)
        << r.frame;
    EXPECT_GT(r.available_s, r.exposure_s);
  }
  EXPECT_EQ(ok, st.fixes_ok);
  // The error the wheels built up over the approach, then the fixes' error.
  EXPECT_GT(st.error_before_m, st.error_after_m);
  EXPECT_LE(st.error_after_m, 0.003);
  EXPECT_TRUE(st.goal_met());
  // The trajectory shows the fixes where the filter applied them.
  int shown = 0;
  for (const DriveRow& r : d.rows()) shown += r.outcome == "accepted_pattern";
  EXPECT_EQ(shown, st.fixes_accepted);
}

TEST(Drive, AStationMisplacedOnTheMapIsRejectedByTheGate) {
  DriveConfig c = station_config();
  // The map puts the station 5 cm further along the tape than it is: every
  // fix is 5 cm off the filter's prediction, tens of sigmas.
  c.station_map = c.course.patterns;
  c.station_map->at(0).x_m += 0.05;
  Drive d(c);
  d.run();
  const DriveSummary s = d.summary();
  ASSERT_EQ(s.stations.size(), 1u);
  EXPECT_GE(s.stations[0].fixes_ok, 5);
  EXPECT_EQ(s.stations[0].fixes_accepted, 0);
  EXPECT_EQ(s.counters.pattern.accepted, 0);
  EXPECT_EQ(s.counters.pattern.rejected_gate, s.stations[0].fixes_ok);
  EXPECT_FALSE(s.stations[0].goal_met());
  EXPECT_TRUE(s.finished);
}

TEST(Route, ThroughTheLTurnToTheEnd) {
  const RoutePlan p = plan_route(short_course());
  ASSERT_EQ(p.waypoints.size(), 3u);
  EXPECT_NEAR(p.waypoints[1].x(), 4.0, 1e-12);
  EXPECT_NEAR(p.waypoints[2].y(), 3.0, 1e-12);
  ASSERT_EQ(p.junctions.size(), 1u);
  EXPECT_EQ(p.junctions[0].turn, Turn::left);
  EXPECT_NEAR(p.length_m, 7.0, 1e-12);
}

TEST(Route, ATurnThatDoesNotExistIsAnError) {
  Course c = short_course();
  c.route = {Turn::right};
  EXPECT_THROW(plan_route(c), CourseError);
  c.start = {0.0, 1.0, 0.0};  // 1 m off the tape
  EXPECT_THROW(plan_route(c), CourseError);
}

TEST(Drive, ShortCourseFinishesOnTheTape) {
  Drive d(config(drivers::Backend::fast));
  d.run();
  const DriveSummary s = d.summary();
  EXPECT_TRUE(s.finished);
  EXPECT_EQ(s.junctions_taken, 1);
  EXPECT_EQ(s.gaps_crossed, 1);
  EXPECT_GT(s.frames_ok, s.frames / 2);
  EXPECT_GT(s.counters.tape.accepted, 100);
  // Before the turn the along-track error is under a centimetre (7 m of
  // 0.1 % wheel scale): the lateral error stays within a few millimetres.
  EXPECT_LT(s.lateral_max_m, 0.02);
  EXPECT_LT(s.final_position_error_m, 0.02);
}

// The map's heights 3 % high: the landmarks seen from a shrinking distance
// and the tape end at the gap tracked over the frames against the odometry
// (seed 000 eq. 44; its fit reaches the filter as a height) give the filter
// the ceiling's height within half a percent, inside its sigma.
TEST(Drive, TheFilterLearnsTheCeilingWhereTheMapIsWrong) {
  DriveConfig c = config(drivers::Backend::fast);
  c.ceiling.map_scale = 1.03;
  c.ekf.bias.ceiling_scale_sigma = 0.05;
  Drive d(c);
  d.run();
  const DriveSummary s = d.summary();
  EXPECT_GE(s.counters.height.accepted, 1);
  EXPECT_EQ(s.counters.height.rejected_gate, 0);
  // Above the camera (0.3 m high) the map is (2.575 - 0.3) / 2.2 = 3.4 % high.
  const double map_ratio = (2.5 * 1.03 - c.camera_height_m) / (2.5 - c.camera_height_m);
  EXPECT_NEAR(s.ceiling_map_error_rms, map_ratio - 1.0, 1e-9);
  const DriveRow& end = d.rows().back();
  EXPECT_NEAR(end.ceiling_true_m, 2.5 - c.camera_height_m, 1e-12);
  EXPECT_NEAR(end.ceiling_est_m / end.ceiling_true_m, 1.0, 0.005);
  EXPECT_LT(std::abs(end.ceiling_est_m - end.ceiling_true_m), 3.0 * end.ceiling_sigma_m);
  // At the start the estimate is the map's.
  EXPECT_NEAR(d.rows().front().ceiling_est_m / d.rows().front().ceiling_true_m, map_ratio, 1e-6);
  EXPECT_TRUE(s.finished);
  EXPECT_LT(s.final_position_error_m, 0.02);
}

TEST(Drive, ModelBackendDrivesTheSameTrajectoryAsFast) {
  Drive fast(config(drivers::Backend::fast));
  Drive model(config(drivers::Backend::model));
  fast.run();
  model.run();
  ASSERT_EQ(fast.rows().size(), model.rows().size());
  for (std::size_t i = 0; i < fast.rows().size(); ++i) {
    const DriveRow &a = fast.rows()[i], &b = model.rows()[i];
    ASSERT_EQ(a.truth.x_m, b.truth.x_m) << i;
    ASSERT_EQ(a.truth.y_m, b.truth.y_m) << i;
    ASSERT_EQ(a.estimate.yaw_rad, b.estimate.yaw_rad) << i;
    ASSERT_EQ(a.frame_status, b.frame_status) << i;
  }
}

}  // namespace
}  // namespace ceilnav::sim
