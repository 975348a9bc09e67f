#include "nav/mount_calibration.hpp"

#include <algorithm>
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
  // Camera roll and pitch errors at the configured pitch and ceiling height
  // above the camera, to first order (docs/navigation.md, "Mount calibration").
  double roll = 0.0, pitch_error = 0.0, pitch = 60.0 * deg, above = 2.2;
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
      // Measured (configured-height) units: the roll and pitch terms scale
      // with the configured height, the true offset with the scale.
      const double offset = t.scale * cam -
                            t.roll * t.above * std::cos(t.pitch) * std::cos(psi + t.mount_yaw) -
                            t.pitch_error * t.above * std::sin(psi + t.mount_yaw);
      const double yaw =
          psi + t.mount_yaw + t.roll * std::sin(t.pitch) + offset / t.above * t.pitch_error;
      run.samples.push_back({odo, yaw + t.yaw_sigma * g(rng), offset + t.offset_sigma * g(rng)});
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

MountCalibrationOptions pitch_options(const Truth& t, double offset_sigma) {
  MountCalibrationOptions o;
  o.forward_m = t.forward;
  o.offset_sigma_m = offset_sigma;
  o.fit_pitch = true;
  o.ceiling_above_camera_m = t.above;
  return o;
}

TEST(MountCalibration, NoiselessRollAndPitchAreSplitExactly) {
  Truth t;
  t.yaw_sigma = t.offset_sigma = t.odo_var_per_m = 0.0;
  t.odo_scale = 1.0;
  t.mount_yaw = 0.7 * deg;
  t.roll = 0.5 * deg;
  t.pitch_error = 1.0 * deg;
  std::mt19937_64 rng(3);
  const std::vector<CalibrationRun> runs = both_directions(t, rng);
  const MountCalibration c = calibrate_mount(runs, pitch_options(t, 1e-3));
  ASSERT_TRUE(c.ok);
  // Effective values: the roll's yaw and lateral shift are in them.
  EXPECT_NEAR(c.yaw_rad, t.mount_yaw + t.roll * std::sin(t.pitch), 2e-6);
  // The pitch term turns with mu in the model, with the mounting yaw in the
  // truth: c holds the difference h delta roll sin p.
  EXPECT_NEAR(c.lateral_m,
              t.scale * t.lateral - t.roll * t.above * std::cos(t.pitch) +
                  t.above * t.pitch_error * t.roll * std::sin(t.pitch),
              1e-5);
  EXPECT_NEAR(c.offset_scale, t.scale, 1e-4);
  // The roll's shift turns with the camera (cos(psi + yaw)), the model's c
  // with the robot: a sin psi term of roll h cos p yaw, 5e-5 rad of pitch.
  EXPECT_NEAR(c.pitch_error_rad, t.pitch_error, 1e-4);
  const MountErrors e = split_mount(c, t.lateral, t.pitch, t.above);
  // The model's lateral turns with the robot's heading, the roll's shift
  // with the camera's: cos(psi) against cos(psi + yaw), 1e-5 of a roll.
  EXPECT_NEAR(e.yaw_rad, t.mount_yaw, 3e-5);
  EXPECT_NEAR(e.roll_rad, t.roll, 3e-5);
  EXPECT_NEAR(e.pitch_rad, t.pitch_error, 1e-4);
  // Without the pitch term the same runs give a biased yaw: the pitch's yaw
  // bias (offset / h) delta over offsets of a few centimetres.
  const MountCalibration blind = calibrate_mount(runs, t.forward, 1e-3);
  ASSERT_TRUE(blind.ok);
  EXPECT_GT(std::abs(blind.yaw_rad - c.yaw_rad), 1e-4);
  // A wrong lateral from the drawings moves the roll by (error) / (h cos p)
  // and the yaw by -sin p times that; the covariance carries the drawings' sigma.
  const MountErrors off = split_mount(c, t.lateral + 1e-3, t.pitch, t.above, 1e-3);
  EXPECT_NEAR(off.roll_rad - e.roll_rad,
              c.offset_scale * 1e-3 /
                  (t.above * (std::cos(t.pitch) - c.pitch_error_rad * std::sin(t.pitch))),
              1e-9);
  EXPECT_NEAR(off.yaw_rad - e.yaw_rad, -std::sin(t.pitch) * (off.roll_rad - e.roll_rad), 1e-9);
  EXPECT_GT(off.covariance(1, 1),
            e.covariance(1, 1) + 0.9 * std::pow(off.roll_rad - e.roll_rad, 2));
}

TEST(MountCalibration, NoisyRollAndPitchGiveTheMountYawWithin005Deg) {
  Truth t;
  t.mount_yaw = 0.8 * deg;
  t.roll = 0.5 * deg;
  t.pitch_error = 1.0 * deg;
  t.offset_sigma = 1e-3;
  t.yaw_sigma = 0.02 * deg;
  std::mt19937_64 rng(23);
  double worst_effective = 0, worst_yaw = 0, worst_roll = 0, worst_pitch = 0, worst_sigmas = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const MountCalibration c = calibrate_mount(both_directions(t, rng), pitch_options(t, 0.0));
    ASSERT_TRUE(c.ok);
    // The offset sigma comes from the residuals.
    EXPECT_NEAR(c.offset_sigma_m, t.offset_sigma, 0.2 * t.offset_sigma);
    const MountErrors e = split_mount(c, t.lateral, t.pitch, t.above);
    worst_effective =
        std::max(worst_effective, std::abs(c.yaw_rad - t.mount_yaw - t.roll * std::sin(t.pitch)));
    worst_yaw = std::max(worst_yaw, std::abs(e.yaw_rad - t.mount_yaw));
    worst_roll = std::max(worst_roll, std::abs(e.roll_rad - t.roll));
    worst_pitch = std::max(worst_pitch, std::abs(e.pitch_rad - t.pitch_error));
    for (int q = 0; q < 3; ++q) {
      const double err = q == 0 ? e.yaw_rad - t.mount_yaw
                                : (q == 1 ? e.roll_rad - t.roll : e.pitch_rad - t.pitch_error);
      worst_sigmas = std::max(worst_sigmas, std::abs(err) / std::sqrt(e.covariance(q, q)));
    }
  }
  std::printf(
      "20 trials, roll 0.5 deg, pitch error 1 deg: worst effective yaw %.4f deg, mounting yaw "
      "%.4f deg, roll %.4f deg, pitch %.4f deg (%.1f sigma)\n",
      worst_effective / deg, worst_yaw / deg, worst_roll / deg, worst_pitch / deg, worst_sigmas);
  EXPECT_LT(worst_effective, 0.05 * deg);
  EXPECT_LT(worst_yaw, 0.05 * deg);
  EXPECT_LT(worst_roll, 0.1 * deg);
  EXPECT_LT(worst_pitch, 0.2 * deg);
  EXPECT_LT(worst_sigmas, 4.0);
}

TEST(MountCalibration, PitchFitNeedsTheCeilingHeight) {
  const Truth t;
  std::mt19937_64 rng(4);
  MountCalibrationOptions o = pitch_options(t, 1e-3);
  o.ceiling_above_camera_m = 0.0;
  EXPECT_FALSE(calibrate_mount(both_directions(t, rng), o).ok);
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
