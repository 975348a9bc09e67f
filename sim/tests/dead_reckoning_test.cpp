// Vision off: the closed loop drives on dead reckoning alone, and the
// filter's odometry model (the robot's slip and scrub, wheel scale errors
// drawn from its prior, the start drawn from its initial covariance) is
// consistent with the simulated robot: over many seeds the pose NEES at the
// end averages to its 3 degrees of freedom (docs/navigation.md, "Vision off").
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "nav/chi_square.hpp"
#include "sim/drive.hpp"

namespace ceilnav::sim {
namespace {

Course straight(double length_m) {
  Course c;
  c.name = "straight";
  TapePolyline t;
  t.points = {{-1.0, 0.0}, {length_m, 0.0}};
  c.tapes.push_back(t);
  c.ceiling_height_m = 2.5;
  c.start = {0.0, 0.0, 0.0};
  validate(c);
  return c;
}

DriveConfig blind(uint64_t seed) {
  DriveConfig d;
  d.course = straight(5.0);
  d.vision = false;
  d.robot.seed = seed;
  std::mt19937_64 rng(seed + 17);
  std::normal_distribution<double> scale(0.0, d.ekf.odometry.wheel_scale_sigma);
  d.robot.left_scale = 1.0 + scale(rng);
  d.robot.right_scale = 1.0 + scale(rng);
  d.ekf.odometry.wheel_var_per_m = d.robot.slip_sigma_sqrt_m * d.robot.slip_sigma_sqrt_m;
  d.ekf.odometry.yaw_var_per_rad = d.robot.scrub_sigma_sqrt_rad * d.robot.scrub_sigma_sqrt_rad;
  d.ekf.odometry.yaw_scale_sigma = 1e-6;  // the simulated wheel base is exact
  d.follower.blind_slow_m = d.follower.blind_stop_m = std::numeric_limits<double>::infinity();
  return d;
}

struct Batch {
  double mean_nees = 0.0, error_rms_m = 0.0, sigma_rms_m = 0.0, driven_m = 0.0;
};

Batch run_batch(int runs, const std::function<void(DriveConfig&)>& change) {
  Batch b;
  for (int k = 0; k < runs; ++k) {
    DriveConfig d = blind(static_cast<uint64_t>(k + 1));
    change(d);
    Drive drive(d);
    drive.run();
    const DriveSummary s = drive.summary();
    EXPECT_TRUE(s.finished);
    b.mean_nees += s.final_pose_nees / runs;
    b.error_rms_m += s.final_position_error_m * s.final_position_error_m / runs;
    b.sigma_rms_m += s.final_position_sigma_m * s.final_position_sigma_m / runs;
    b.driven_m += s.driven_m / runs;
  }
  b.error_rms_m = std::sqrt(b.error_rms_m);
  b.sigma_rms_m = std::sqrt(b.sigma_rms_m);
  return b;
}

TEST(DeadReckoning, TheFilterIsConsistentWithTheRobotWithoutVision) {
  const int runs = 1000;
  const Batch b = run_batch(runs, [](DriveConfig&) {});
  // The mean of 1000 chi-square(3) draws lies in [lo, hi] with 99 %; the
  // top is widened by 10 % for the linearisation of the heading (1.4 deg
  // sigma at the end; docs/navigation.md, "Fusion filter", measured 3.16
  // against 3 at 7.5 deg).
  const double lo = nav::chi_square_quantile(0.005, 3.0 * runs) / runs;
  const double hi = 1.1 * nav::chi_square_quantile(0.995, 3.0 * runs) / runs;
  std::printf(
      "dead reckoning, %d runs of %.1f m: mean end NEES %.3f (99 %% band %.3f-%.3f), "
      "RMS error %.1f mm = %.2f %% of d, RMS filter sigma %.1f mm\n",
      runs, b.driven_m, b.mean_nees, lo, hi, 1e3 * b.error_rms_m,
      100.0 * b.error_rms_m / b.driven_m, 1e3 * b.sigma_rms_m);
  EXPECT_GE(b.mean_nees, lo);
  EXPECT_LE(b.mean_nees, hi);
  // Seed 004's odometric drift, 2.012e-2 d, as an order-of-magnitude check.
  EXPECT_GT(b.error_rms_m / b.driven_m, 0.01);
  EXPECT_LT(b.error_rms_m / b.driven_m, 0.04);
}

TEST(DeadReckoning, AFilterThatBelievesHalfTheSlipIsCaughtOverconfident) {
  // The same drives with the filter's slip variance at half the robot's:
  // the test above must be able to fail.
  const int runs = 1000;
  const Batch b = run_batch(runs, [](DriveConfig& d) { d.ekf.odometry.wheel_var_per_m *= 0.5; });
  std::printf("filter slip variance at half the robot's: mean end NEES %.3f\n", b.mean_nees);
  EXPECT_GT(b.mean_nees, 1.1 * nav::chi_square_quantile(0.995, 3.0 * runs) / runs);
}

}  // namespace
}  // namespace ceilnav::sim
