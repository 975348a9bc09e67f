#include "nav/mount_calibration.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

constexpr double deg = std::numbers::pi / 180.0;

struct Truth {
  double mount_yaw = 0.5 * deg, lateral = 0.02, forward = 0.15, scale = 1.02;
  double yaw_sigma = 0.1 * deg, offset_sigma = 5e-3;
  double odo_scale = 1.0015, odo_var_per_m = 1e-5;  // OdometryModel's slip, both wheels
};

// A run of `length` m along the tape at 0.5 m/s, 30 fps: the robot's heading
// relative to the tape is +heading for the first half and -heading for the
// second (a 0.3 m linear change between), starting at lateral position y0.
// Returns the final lateral position.
double drive(const Truth& t, double y0, double heading, double length, CalibrationRun& run,
             std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const double ds_frame = 0.5 / 30.0, fine = 1e-4;
  auto psi_at = [&](double s) {
    const double u = std::clamp((s - 0.5 * length) / 0.3 + 0.5, 0.0, 1.0);
    return heading * (1.0 - 2.0 * u);
  };
  double s = 0.0, y = y0, odo = 0.0, next = ds_frame;
  while (s < length) {
    y += fine * std::sin(psi_at(s + 0.5 * fine));
    s += fine;
    if (s >= next) {
      odo += ds_frame * t.odo_scale + std::sqrt(0.5 * t.odo_var_per_m * ds_frame) * g(rng);
      const double psi = psi_at(s);
      const double cam = y + t.forward * std::sin(psi) + t.lateral * std::cos(psi);
      run.samples.push_back(
          {odo, psi + t.mount_yaw + t.yaw_sigma * g(rng), t.scale * cam + t.offset_sigma * g(rng)});
      next += ds_frame;
    }
  }
  run.end_distance_m = odo;
  return y;
}

std::vector<CalibrationRun> both_directions(const Truth& t, std::mt19937_64& rng) {
  std::vector<CalibrationRun> runs(2);
  const double end = drive(t, 0.03, 4.0 * deg, 4.0, runs[0], rng);
  runs[1].turned_in_place = true;
  drive(t, -end, 3.0 * deg, 4.0, runs[1], rng);
  return runs;
}

TEST(MountCalibration, BothDirectionsGiveTheMountYawWithin005Deg) {
  const Truth t;
  std::mt19937_64 rng(17);
  double worst_yaw = 0, worst_yaw_sigmas = 0, worst_lateral = 0, worst_scale = 0;
  double worst_scale_sigmas = 0, scale_sigma = 0, lateral_sigma = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const MountCalibration c = calibrate_mount(both_directions(t, rng), t.forward, t.offset_sigma);
    ASSERT_TRUE(c.ok);
    const double e = c.yaw_rad - t.mount_yaw;
    worst_yaw = std::max(worst_yaw, std::abs(e));
    worst_yaw_sigmas = std::max(worst_yaw_sigmas, std::abs(e) / std::sqrt(c.covariance(0, 0)));
    // The body-fixed part of the measured offset: the scale times the mount's lateral.
    worst_lateral = std::max(worst_lateral, std::abs(c.lateral_m - t.scale * t.lateral));
    worst_scale = std::max(worst_scale, std::abs(c.offset_scale - t.scale));
    worst_scale_sigmas = std::max(
        worst_scale_sigmas, std::abs(c.offset_scale - t.scale) / std::sqrt(c.covariance(2, 2)));
    scale_sigma = std::sqrt(c.covariance(2, 2));
    lateral_sigma = std::sqrt(c.covariance(1, 1));
    EXPECT_LT(c.rms_residual_m, 1.2 * t.offset_sigma);
  }
  std::printf(
      "20 trials: worst mount yaw error %.4f deg (%.1f sigma), lateral %.2f mm (sigma "
      "%.2f), offset scale %.4f (%.1f sigma, sigma %.4f)\n",
      worst_yaw / deg, worst_yaw_sigmas, 1e3 * worst_lateral, 1e3 * lateral_sigma, worst_scale,
      worst_scale_sigmas, scale_sigma);
  EXPECT_LT(worst_yaw, 0.05 * deg);
  EXPECT_LT(worst_yaw_sigmas, 4.0);
  EXPECT_LT(worst_lateral, 3e-3);
  // The scale rests on the lateral excursion of the runs (a few cm): ~1 %.
  EXPECT_LT(worst_scale_sigmas, 4.0);
  EXPECT_LT(worst_scale, 0.04);
}

TEST(MountCalibration, NoiselessRunsAreRecoveredExactly) {
  Truth t;
  t.yaw_sigma = 0.0;
  t.offset_sigma = 0.0;
  t.odo_var_per_m = 0.0;
  t.odo_scale = 1.0;
  std::mt19937_64 rng(1);
  const MountCalibration c = calibrate_mount(both_directions(t, rng), t.forward, 1e-3);
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(c.yaw_rad, t.mount_yaw, 2e-6);
  EXPECT_NEAR(c.lateral_m, t.scale * t.lateral, 1e-5);
  EXPECT_NEAR(c.offset_scale, t.scale, 1e-4);
}

TEST(MountCalibration, NeedsARunTurnedInPlaceAndEnoughSamples) {
  const Truth t;
  std::mt19937_64 rng(2);
  std::vector<CalibrationRun> runs = both_directions(t, rng);
  const MountCalibration linked = calibrate_mount(runs, t.forward, t.offset_sigma);
  // Without the link between the runs the lateral is told from the start
  // positions only through cos psi: its sigma grows a hundredfold.
  runs[1].turned_in_place = false;
  const MountCalibration free = calibrate_mount(runs, t.forward, t.offset_sigma);
  ASSERT_TRUE(linked.ok);
  ASSERT_TRUE(free.ok);
  EXPECT_LT(std::sqrt(linked.covariance(1, 1)), 2e-3);
  EXPECT_GT(std::sqrt(free.covariance(1, 1)), 100 * std::sqrt(linked.covariance(1, 1)));
  runs[0].turned_in_place = true;  // nothing to start from
  EXPECT_FALSE(calibrate_mount(runs, t.forward, t.offset_sigma).ok);
  EXPECT_FALSE(calibrate_mount({}, t.forward, t.offset_sigma).ok);
  CalibrationRun few;
  few.samples.resize(5);
  EXPECT_FALSE(calibrate_mount({few}, t.forward, t.offset_sigma).ok);
}

}  // namespace
}  // namespace ceilnav::nav
