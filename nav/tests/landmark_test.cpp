// Landmarks along the tape (tape ends at gaps, junctions) fix the position
// along the tape, which the tape's yaw and offset cannot: a straight drive
// whose wheels under-report their travel by 0.3 % (twice the filter's prior sigma).
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "nav/ekf.hpp"

namespace ceilnav::nav {
namespace {

struct Result {
  double along_error_m = 0.0;  // |x estimate - x truth| at the end
  double sigma_x_m = 0.0;
  double scale_estimate = 0.0;  // mean of the wheel scale errors
  Counters counters;
};

// 20 m along +X at 0.5 m/s; landmarks every 5 m; with `seen`, each frame
// (10 per second) that has a landmark 0.5-2 m ahead measures it (sigma 5 mm).
Result drive(bool seen, bool wrong_kind = false) {
  TapeMap map;
  map.add({{-1.0, 0.0}, {30.0, 0.0}, 0.05});
  for (double x : {5.0, 10.0, 15.0, 20.0})
    map.add_landmark({LandmarkMeasurement::Kind::tape_end, {x, 0.0}});
  EkfOptions opt;
  State x0 = State::Zero();
  Covariance p0 = Ekf::calibration_prior(opt.odometry);
  p0(state::x, state::x) = p0(state::y, state::y) = 1e-6;
  p0(state::yaw, state::yaw) = 1e-6;
  Ekf ekf(opt, &map, 0.0, x0, p0);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  const double dt = 0.01, v = 0.5, scale = 1.003;  // true travel = 1.003 x measured
  double x_true = 0.0;
  for (int k = 1; k <= 4000; ++k) {
    const double step = v * dt;
    x_true += step;
    ekf.predict({k * dt, step / scale, step / scale});
    if (seen && k % 10 == 0) {
      for (double l : {5.0, 10.0, 15.0, 20.0}) {
        const double ahead = l - x_true;
        if (ahead < 0.5 || ahead > 2.0) continue;
        LandmarkMeasurement m;
        m.time = {k * dt, k * dt};
        m.kind =
            wrong_kind ? LandmarkMeasurement::Kind::junction : LandmarkMeasurement::Kind::tape_end;
        m.along_m = ahead + noise(rng);
        m.variance_m2 = 0.005 * 0.005;
        ekf.update(m);
      }
    }
  }
  Result r;
  r.along_error_m = std::abs(ekf.state()(state::x) - x_true);
  r.sigma_x_m = std::sqrt(ekf.covariance()(state::x, state::x));
  r.scale_estimate = 0.5 * (ekf.state()(state::left_scale) + ekf.state()(state::right_scale));
  r.counters = ekf.counters();
  return r;
}

TEST(Landmarks, FixThePositionAlongTheTapeAndTheOdometryScale) {
  const Result blind = drive(false);
  const Result fixed = drive(true);
  // Dead reckoning loses 0.3 % of 20 m, and knows it only to its prior.
  EXPECT_NEAR(blind.along_error_m, 0.0598, 0.001);
  EXPECT_GT(blind.sigma_x_m, 0.02);
  EXPECT_LT(fixed.along_error_m, 0.005);
  EXPECT_LT(fixed.along_error_m, 3.0 * fixed.sigma_x_m);
  EXPECT_NEAR(fixed.scale_estimate, 0.003, 0.001);
  EXPECT_GT(fixed.counters.landmark.accepted, 40);
}

TEST(Landmarks, OnlyLandmarksOfTheMeasuredKindAreCandidates) {
  const Result r = drive(true, true);
  EXPECT_EQ(r.counters.landmark.accepted, 0);
  EXPECT_GT(r.counters.landmark.unassociated, 40);
}

}  // namespace
}  // namespace ceilnav::nav
