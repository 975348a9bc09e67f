#include "nav/odometry_step.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

TEST(OdometryStep, StraightTravelMovesAlongTheHeading) {
  const Pose2 p = advance({1.0, 2.0, std::numbers::pi / 2}, motion_of({0.0, 0.3, 0.3}, 0.4));
  EXPECT_NEAR(p.x_m, 1.0, 1e-15);
  EXPECT_NEAR(p.y_m, 2.3, 1e-15);
  EXPECT_NEAR(p.yaw_rad, std::numbers::pi / 2, 1e-15);
}

TEST(OdometryStep, ManySmallStepsOfAnArcMatchOneStep) {
  // A quarter circle of radius 1 m: wheels on radii 0.8 and 1.2 m.
  const double b = 0.4, quarter = std::numbers::pi / 2;
  const Pose2 one = advance({}, motion_of({0.0, 0.8 * quarter, 1.2 * quarter}, b));
  Pose2 many{};
  for (int i = 0; i < 1000; ++i)
    many = advance(many, motion_of({0.0, 0.8 * quarter / 1000, 1.2 * quarter / 1000}, b));
  EXPECT_NEAR(one.x_m, 1.0, 1e-12);
  EXPECT_NEAR(one.y_m, 1.0, 1e-12);
  EXPECT_NEAR(one.yaw_rad, quarter, 1e-12);
  EXPECT_NEAR(many.x_m, one.x_m, 1e-12);
  EXPECT_NEAR(many.y_m, one.y_m, 1e-12);
  EXPECT_NEAR(many.yaw_rad, one.yaw_rad, 1e-12);
}

TEST(OdometryStep, WrapAngleIsHalfOpen) {
  EXPECT_DOUBLE_EQ(wrap_angle(std::numbers::pi), -std::numbers::pi);
  EXPECT_NEAR(wrap_angle(3 * std::numbers::pi + 0.1), -std::numbers::pi + 0.1, 1e-12);
  EXPECT_NEAR(wrap_angle(-0.2), -0.2, 1e-15);
}

}  // namespace
}  // namespace ceilnav::nav
