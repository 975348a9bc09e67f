#include "host/pattern/pattern_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace ceilnav::host::pattern {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(PatternSearch, SeedScanRuleEq33To37) {
  // 60 deg field of view, 30 Hz, pattern half width 0.6 m, D_min 2 m.
  ScanParams p{60 * kDeg, 30.0, 0.6, 2.0, 0.0};
  const double phi0 = 2.0 * std::atan(0.3);  // eq. 34
  EXPECT_NEAR(pattern_angle_rad(p), phi0, 1e-15);
  EXPECT_NEAR(max_pan_rate(p), (60 * kDeg - phi0) * 30.0, 1e-12);  // eq. 35
  // Eq. 36-37: a robot at 1 m/s moves the pattern by atan(1 / (30 * 2)) per frame.
  p.robot_speed_mps = 1.0;
  EXPECT_NEAR(motion_angle_rad(p), std::atan(1.0 / 60.0), 1e-15);
  EXPECT_NEAR(max_pan_rate(p), (60 * kDeg - phi0 - std::atan(1.0 / 60.0)) * 30.0, 1e-12);
  // A pan step of one frame at that rate leaves an overlap of exactly the
  // pattern's angle plus its motion: the pattern is whole in some frame.
  const double step = max_pan_rate(p) / 30.0;
  EXPECT_NEAR(60 * kDeg - step, phi0 + motion_angle_rad(p), 1e-12);
  // Too close: the pattern spans more than the field of view -> 0, never negative.
  p.d_min_m = 0.3;
  EXPECT_EQ(max_pan_rate(p), 0.0);
  p.video_rate_hz = 0.0;
  EXPECT_EQ(max_pan_rate(p), 0.0);
}

}  // namespace
}  // namespace ceilnav::host::pattern
