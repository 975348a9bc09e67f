#include "nav/map.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

constexpr double pi = std::numbers::pi;

TapeMeasurement tape(double yaw, double offset, double sigma_yaw = 0.01, double sigma_off = 0.01) {
  TapeMeasurement m;
  m.yaw_rad = yaw;
  m.offset_m = offset;
  m.covariance = Eigen::Vector2d(sigma_yaw * sigma_yaw, sigma_off * sigma_off).asDiagonal();
  return m;
}

TEST(TapeMap, PredictionIsYawAndLeftOffsetAlongTheSegment) {
  const TapeSegment s{{0, 0}, {5, 0}, 0.05};
  const TapePrediction p = predict_tape(s, {1.0, 0.2, 0.1}, 0.1);
  EXPECT_EQ(p.branch, 0);
  EXPECT_NEAR(p.h(0), 0.1, 1e-15);
  EXPECT_NEAR(p.h(1), 0.2, 1e-15);
  // The same tape entered the other way round: the branch flips, h does not.
  const TapePrediction r = predict_tape({{5, 0}, {0, 0}, 0.05}, {1.0, 0.2, 0.1}, 0.1);
  EXPECT_EQ(r.branch, 1);
  EXPECT_NEAR(r.h(0), 0.1, 1e-15);
  EXPECT_NEAR(r.h(1), 0.2, 1e-15);
}

TEST(TapeMap, ZenithYawModuloPiPicksTheBranchNearestThePrediction) {
  // Driving along -X, 0.2 m left of the tape in world Y (+Y), i.e. 0.2 m to
  // the camera's right: a zenith result names the -X direction, yaw -0.05.
  const TapeSegment s{{0, 0}, {5, 0}, 0.05};
  const TapePrediction p = predict_tape(s, {3.0, 0.2, pi - 0.05}, -0.05);
  EXPECT_EQ(p.branch, 1);
  EXPECT_NEAR(p.h(0), -0.05, 1e-15);
  EXPECT_NEAR(p.h(1), -0.2, 1e-15);
}

TEST(TapeMap, JacobianMatchesFiniteDifferences) {
  const TapeSegment s{{0.3, -0.2}, {2.0, 1.5}, 0.05};
  const Pose2 c{1.0, 0.4, 0.9};
  const TapePrediction p = predict_tape(s, c, 0.1);
  const double e = 1e-6;
  for (int j = 0; j < 3; ++j) {
    Pose2 plus = c, minus = c;
    (j == 0 ? plus.x_m : j == 1 ? plus.y_m : plus.yaw_rad) += e;
    (j == 0 ? minus.x_m : j == 1 ? minus.y_m : minus.yaw_rad) -= e;
    const Eigen::Vector2d d =
        (predict_tape(s, plus, 0.1).h - predict_tape(s, minus, 0.1).h) / (2 * e);
    EXPECT_NEAR(d(0), p.jacobian(0, j), 1e-8);
    EXPECT_NEAR(d(1), p.jacobian(1, j), 1e-8);
  }
}

TEST(TapeMap, AssociatesTheSegmentWithTheSmallestMahalanobisInnovation) {
  // An L-shaped course and a parallel tape 1 m to the left of its first leg.
  const TapeMap map({{{0, 0}, {4, 0}, 0.05}, {{4, 0}, {4, 4}, 0.05}, {{0, 1}, {4, 1}, 0.05}});
  const Eigen::Matrix3d cov = Eigen::Vector3d(0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02).asDiagonal();
  // Near the corner, heading up the second leg, 0.05 m left of it.
  auto a = map.associate(tape(0.01, 0.05), {3.95, 0.5, pi / 2}, cov);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->segment, 1);
  EXPECT_NEAR(a->innovation(0), 0.01, 1e-12);
  EXPECT_NEAR(a->innovation(1), 0.0, 1e-12);
  // On the first leg, 0.1 m left of it: the first leg, not the parallel tape
  // whose offset would be -0.9 m; seen from 0.1 m right of the parallel tape, it.
  a = map.associate(tape(0.0, 0.1), {2.0, 0.1, 0.0}, cov);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->segment, 0);
  a = map.associate(tape(0.0, -0.1), {2.0, 0.9, 0.0}, cov);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->segment, 2);
  // S = H P H^T + R.
  const Eigen::Matrix2d s_expected =
      a->prediction.jacobian * cov * a->prediction.jacobian.transpose() +
      Eigen::Vector2d(1e-4, 1e-4).asDiagonal().toDenseMatrix();
  EXPECT_NEAR((a->innovation_covariance - s_expected).norm(), 0.0, 1e-15);
}

TEST(TapeMap, NothingInViewIsUnassociated) {
  const TapeMap map({{{0, 0}, {4, 0}, 0.05}});
  const Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-4;
  AssociationOptions opt;
  opt.view_radius_m = 2.0;
  EXPECT_FALSE(map.associate(tape(0, 0), {7.0, 0.0, 0.0}, cov, opt));  // 3 m past its end
  EXPECT_TRUE(map.associate(tape(0, 0), {5.5, 0.0, 0.0}, cov, opt));
  // A large position uncertainty widens the reach: 3 sigma of 0.5 m.
  const Eigen::Matrix3d wide = Eigen::Vector3d(0.25, 0.01, 1e-4).asDiagonal();
  EXPECT_TRUE(map.associate(tape(0, 0), {7.0, 0.0, 0.0}, wide, opt));
  EXPECT_FALSE(TapeMap{}.associate(tape(0, 0), {0, 0, 0}, cov, opt));
  EXPECT_NEAR(distance_to_segment({2.0, 3.0}, map.segments()[0]), 3.0, 1e-15);
  EXPECT_NEAR(distance_to_segment({-3.0, 4.0}, map.segments()[0]), 5.0, 1e-15);
}

}  // namespace
}  // namespace ceilnav::nav
