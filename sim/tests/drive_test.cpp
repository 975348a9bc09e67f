// The closed loop on a short course: the route is planned through its
// junction, the robot finishes on the tape, and the model backend (the
// cycle-level device through its registers, with random stream gaps and
// back-pressure) drives the same trajectory as the fast one, bit for bit.
#include "sim/drive.hpp"

#include <cmath>

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
