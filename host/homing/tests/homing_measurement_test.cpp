// From the tracker's pixel and turn to the navigation layer's homing
// measurement (host/homing/homing_measurement.hpp), against the ceiling
// renderer's projection (golden::ceiling::project): the site point, seen
// from a camera moved and turned, gives back where the site camera is in
// the robot's frame, with and without lens distortion.
#include "host/homing/homing_measurement.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

#include "golden/ceiling/ceiling.hpp"
#include "golden/ceiling/render.hpp"

namespace ceilnav::host::homing {
namespace {

namespace gc = golden::ceiling;
constexpr double kDeg = std::numbers::pi / 180.0;

TEST(HomingMeasurement, GivesTheSiteCameraInTheRobotFrame) {
  gc::Ceiling ceiling;
  ceiling.height_m = 3.5;
  for (const bool distortion : {false, true}) {
    CameraConfig cam;
    if (distortion) cam.distortion_coefficients = {-0.25, 0.08, 0.001, -0.0005, 0.0};
    const CameraModel model(cam);
    gc::Pose site;
    site.x_m = 1.0;
    site.y_m = -0.5;
    site.yaw_rad = 20.0 * kDeg;
    for (const auto& [dx, dy, dyaw] :
         {std::tuple{0.3, -0.2, 35.0}, {-0.6, 0.4, -120.0}, {0.0, 0.0, 0.0}, {0.9, 0.3, 179.0}}) {
      gc::Pose now = site;
      now.x_m += dx;
      now.y_m += dy;
      now.yaw_rad += dyaw * kDeg;
      const auto px = gc::project(cam, ceiling, now, site.x_m, site.y_m, true);
      ASSERT_TRUE(px.has_value());
      TrackResult t;
      t.status = TrackStatus::ok;
      t.x_px = px->x();
      t.y_px = px->y();
      t.gamma_deg = std::fmod(-dyaw + 360.0, 360.0);  // the content turns against the robot
      const nav::HomingMeasurement m = homing_measurement(t, model, 3.0, 2);
      ASSERT_EQ(m.status, nav::MeasurementStatus::ok);
      EXPECT_EQ(m.site, 2);
      const double c = std::cos(now.yaw_rad), s = std::sin(now.yaw_rad);
      EXPECT_NEAR(m.forward_m, c * -dx + s * -dy, 1e-9) << distortion << " " << dyaw;
      EXPECT_NEAR(m.left_m, -s * -dx + c * -dy, 1e-9) << distortion << " " << dyaw;
      EXPECT_NEAR(m.turn_rad, -dyaw * kDeg, 1e-12);
      EXPECT_GT(m.covariance(0, 0), 0.0);
      EXPECT_GT(m.covariance(2, 2), 0.0);
    }
  }
}

TEST(HomingMeasurement, OnlyAnOkMatchIsAMeasurement) {
  const CameraModel model(CameraConfig{});
  TrackResult t;
  t.status = TrackStatus::ambiguous;
  t.x_px = 100.0;
  EXPECT_EQ(homing_measurement(t, model, 3.0).status, nav::MeasurementStatus::inconsistent);
  t.status = TrackStatus::not_found;
  EXPECT_EQ(homing_measurement(t, model, 3.0).status, nav::MeasurementStatus::not_found);
  EXPECT_THROW(homing_measurement(t, model, 0.0), std::invalid_argument);
  EXPECT_THROW(homing_measurement(t, model, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::host::homing
