#include "host/nav_measurements.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace ceilnav::host {
namespace {

TapePose ok_pose() {
  TapePose p;
  p.status = Status::ok;
  p.method = "runs_centre_line";
  p.yaw_rad = 0.1;
  p.offset_m = -0.5;
  p.covariance << 4e-8, 1e-8, 1e-8, 9e-8;
  return p;
}

TEST(NavMeasurements, OkPoseCarriesItsQuantityAndInflatedCovarianceWithFloors) {
  TapeNoiseModel n;
  const nav::TapeMeasurement m = tape_measurement(ok_pose(), {1.0, 1.05}, n);
  EXPECT_EQ(m.status, nav::MeasurementStatus::ok);
  EXPECT_FALSE(m.zenith);
  EXPECT_EQ(m.yaw_rad, 0.1);
  EXPECT_EQ(m.offset_m, -0.5);
  EXPECT_EQ(m.time.exposure_s, 1.0);
  EXPECT_EQ(m.time.available_s, 1.05);
  const double off_rel = n.ceiling_relative_sigma * 0.5;
  EXPECT_DOUBLE_EQ(m.covariance(0, 0), 2.5 * 4e-8 + n.yaw_floor_rad * n.yaw_floor_rad);
  EXPECT_DOUBLE_EQ(m.covariance(1, 1),
                   2.5 * 9e-8 + n.offset_floor_m * n.offset_floor_m + off_rel * off_rel);
  EXPECT_DOUBLE_EQ(m.covariance(0, 1), 2.5 * 1e-8);
  EXPECT_DOUBLE_EQ(m.covariance(1, 0), 2.5 * 1e-8);
}

TEST(NavMeasurements, ZenithPosesAreFlagged) {
  TapePose p = ok_pose();
  p.method = "zenith_moments";
  EXPECT_TRUE(tape_measurement(p, {}).zenith);
}

TEST(NavMeasurements, AnythingButOkCarriesNoQuantity) {
  const std::pair<Status, nav::MeasurementStatus> cases[] = {
      {Status::no_tape, nav::MeasurementStatus::not_found},
      {Status::too_few_points, nav::MeasurementStatus::degenerate},
      {Status::degenerate, nav::MeasurementStatus::degenerate},
      {Status::bad_config, nav::MeasurementStatus::degenerate},
      {Status::frame_invalid, nav::MeasurementStatus::invalid},
      {Status::inconsistent, nav::MeasurementStatus::inconsistent},
      {Status::jump, nav::MeasurementStatus::inconsistent},
  };
  for (const auto& [s, want] : cases) {
    TapePose p = ok_pose();
    p.status = s;
    const nav::TapeMeasurement m = tape_measurement(p, {});
    EXPECT_EQ(m.status, want) << to_string(s);
    EXPECT_EQ(m.yaw_rad, 0.0) << to_string(s);
    EXPECT_EQ(m.offset_m, 0.0) << to_string(s);
  }
}

}  // namespace
}  // namespace ceilnav::host
