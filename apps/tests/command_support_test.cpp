// Helpers of the tape commands: angle wrapping, the RMS accumulator, frame
// names and the random poses of the accuracy benchmark.
#include "apps/command_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

namespace ceilnav::app {
namespace {

TEST(CommandSupport, WrapAngle) {
  constexpr double kPi = std::numbers::pi;
  EXPECT_NEAR(wrap_angle(0.25), 0.25, 1e-15);
  EXPECT_NEAR(wrap_angle(2.0 * kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(wrap_angle(-2.0 * kPi - 0.25), -0.25, 1e-12);
  EXPECT_NEAR(wrap_angle(1.5 * kPi), -0.5 * kPi, 1e-12);
}

TEST(CommandSupport, RmsAndLargestMagnitude) {
  Rms e;
  EXPECT_EQ(e.rms(), 0.0);  // nothing added
  e.add(3.0);
  e.add(-4.0);
  EXPECT_EQ(e.n, 2);
  EXPECT_DOUBLE_EQ(e.rms(), std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(e.max_abs, 4.0);
}

TEST(CommandSupport, FrameNames) {
  EXPECT_EQ(frame_name(0), "frame_0000.png");
  EXPECT_EQ(frame_name(42), "frame_0042.png");
  EXPECT_EQ(frame_name(12345), "frame_12345.png");
}

TEST(CommandSupport, OverlayEveryNthFrameFromFrameZero) {
  auto due = [](int every, size_t frames) {
    std::vector<size_t> picked;
    for (size_t i = 0; i < frames; ++i) {
      if (overlay_due(every, i)) picked.push_back(i);
    }
    return picked;
  };
  EXPECT_EQ(due(0, 5), (std::vector<size_t>{}));  // off: the command's own single overlay only
  EXPECT_EQ(due(1, 4), (std::vector<size_t>{0, 1, 2, 3}));
  EXPECT_EQ(due(2, 5), (std::vector<size_t>{0, 2, 4}));
  EXPECT_EQ(due(3, 7), (std::vector<size_t>{0, 3, 6}));
  EXPECT_EQ(due(10, 3), (std::vector<size_t>{0}));  // frame 0 always, even when N > frames
  EXPECT_THROW(overlay_due(-1, 0), std::runtime_error);
  EXPECT_THROW(check_overlay_every(-2), std::runtime_error);
  EXPECT_NO_THROW(check_overlay_every(0));
  EXPECT_NO_THROW(check_overlay_every(5));
}

TEST(CommandSupport, OverlayFileNamedAfterItsFrame) {
  EXPECT_EQ(overlay_file_name("frame_0003.png"), "frame_0003.png");
  EXPECT_EQ(overlay_file_name("/data/run 2/cam0_000017.png"), "cam0_000017.png");
  EXPECT_EQ(overlay_file_name("shot.v2.PNG"), "shot.v2.png");
}

TEST(CommandSupport, SampledPosesStayInTheirRanges) {
  std::mt19937_64 rng(3);
  double yaw_lo = 0, yaw_hi = 0, pitch_lo = 90, pitch_hi = 0;
  for (int i = 0; i < 2000; ++i) {
    const SampledPose p = sample_pose(rng, 20.0, 60.0, 15.0, 0.5, 5.0, 1.0);
    ASSERT_GE(p.pitch_deg, 20.0);
    ASSERT_LT(p.pitch_deg, 60.0);
    ASSERT_LE(std::abs(p.pose.yaw_rad), 15.0 * kDeg);
    ASSERT_LE(std::abs(p.pose.y_m), 0.5);
    ASSERT_GE(p.pose.x_m, 0.0);
    ASSERT_LT(p.pose.x_m, 10.0);
    ASSERT_GE(p.noise, 0.0);
    ASSERT_LT(p.noise, 5.0);
    ASSERT_GE(p.blur, 0.0);
    ASSERT_LT(p.blur, 1.0);
    yaw_lo = std::min(yaw_lo, p.pose.yaw_rad / kDeg);
    yaw_hi = std::max(yaw_hi, p.pose.yaw_rad / kDeg);
    pitch_lo = std::min(pitch_lo, p.pitch_deg);
    pitch_hi = std::max(pitch_hi, p.pitch_deg);
  }
  // Both ends of each range are reached.
  EXPECT_LT(yaw_lo, -14.5);
  EXPECT_GT(yaw_hi, 14.5);
  EXPECT_LT(pitch_lo, 21.0);
  EXPECT_GT(pitch_hi, 59.0);
  // The same seed gives the same poses.
  std::mt19937_64 a(9), b(9);
  EXPECT_EQ(sample_pose(a, 20, 60, 15, 0.5, 5, 1).pose.y_m,
            sample_pose(b, 20, 60, 15, 0.5, 5, 1).pose.y_m);
}

}  // namespace
}  // namespace ceilnav::app
