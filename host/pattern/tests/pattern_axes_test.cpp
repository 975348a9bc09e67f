// The pattern frame of a circle pose and the camera's spherical position in
// it (pattern_axes.hpp), and the other circle pose of a disc ellipse
// (mirror_pose): pieces the conic method, the plane bar-code reader and the
// refinement with the bars share.
#include "host/pattern/pattern_axes.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "host/pattern/circle_pose.hpp"

namespace ceilnav::host::pattern {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(PatternAxes, RightHandedWithTheNormalAsZAndUpInTheYZPlane) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, -0.9).normalized();
  const Eigen::Vector3d up(0.05, -1.0, 0.1);
  const auto a = pattern_axes_cam(n, up);
  ASSERT_TRUE(a.has_value());
  EXPECT_NEAR((a->transpose() * *a - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(a->determinant(), 1.0, 1e-12);
  EXPECT_NEAR((a->col(2) - n).norm(), 0.0, 1e-15);
  // y is the vertical's part across the normal: x is perpendicular to the
  // vertical, y leans toward it.
  EXPECT_NEAR(a->col(0).dot(up), 0.0, 1e-12);
  EXPECT_GT(a->col(1).dot(up), 0.0);
}

TEST(PatternAxes, EmptyWhenTheVerticalIsAlongTheNormal) {
  const Eigen::Vector3d n(0.0, -1.0, 0.0);
  EXPECT_FALSE(pattern_axes_cam(n, Eigen::Vector3d(0.0, -1.0, 0.0)).has_value());
  EXPECT_FALSE(pattern_axes_cam(n, Eigen::Vector3d(0.0, 2.0, 0.0)).has_value());
}

TEST(PatternAxes, SphericalFromPoseRecoversDistanceThetaAndBeta) {
  for (const double theta_deg : {0.0, 20.0, 67.5}) {
    for (const double beta_deg : {-150.0, -30.0, 45.0, 120.0}) {
      const double d = 3.2, t = theta_deg * kDeg, b = beta_deg * kDeg;
      // Some orientation of the pattern in the camera.
      const Eigen::Vector3d n =
          Eigen::AngleAxisd(0.4, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()) *
          Eigen::Vector3d(0.0, 0.0, -1.0);
      const auto axes = pattern_axes_cam(n, Eigen::Vector3d(0.0, -1.0, 0.0));
      ASSERT_TRUE(axes.has_value());
      // Camera at (sin t sin b, sin t cos b, cos t) D in the pattern frame.
      const Eigen::Vector3d cam_pat =
          d * Eigen::Vector3d(std::sin(t) * std::sin(b), std::sin(t) * std::cos(b), std::cos(t));
      const Eigen::Vector3d centre = -(*axes * cam_pat);
      PatternPose p;
      spherical_from_pose(centre, *axes, p);
      EXPECT_NEAR(p.d_m, d, 1e-12);
      EXPECT_NEAR(p.theta_rad, t, 1e-7);
      if (theta_deg > 0.0) {
        EXPECT_NEAR(std::remainder(p.beta_rad - b, 2.0 * std::numbers::pi), 0.0, 1e-9);
      }
    }
  }
}

TEST(MirrorPose, TheOtherCirclePoseOfTheSameEllipseAndNoneForAFrontalCircle) {
  const auto e = ellipse_from_covariance(
      Eigen::Vector2d(0.1, -0.05), (Eigen::Matrix2d() << 0.004, 0.001, 0.001, 0.002).finished());
  ASSERT_TRUE(e.has_value());
  const auto poses = circle_poses_from_conic(conic_from_ellipse(*e), 0.25);
  ASSERT_EQ(poses.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    PatternPose p;
    p.ellipse = *e;
    p.normal_cam = poses[k].normal;
    const auto other = mirror_pose(p, 0.25);
    ASSERT_TRUE(other.has_value());
    EXPECT_NEAR((other->normal - poses[1 - k].normal).norm(), 0.0, 1e-12);
    EXPECT_NEAR((other->centre - poses[1 - k].centre).norm(), 0.0, 1e-12);
  }
  // A circle seen face-on on the optical axis has one pose: no mirror.
  const auto frontal =
      ellipse_from_covariance(Eigen::Vector2d(0.0, 0.0), 0.003 * Eigen::Matrix2d::Identity());
  ASSERT_TRUE(frontal.has_value());
  PatternPose p;
  p.ellipse = *frontal;
  const auto one = circle_poses_from_conic(conic_from_ellipse(*frontal), 0.25);
  ASSERT_EQ(one.size(), 1u);
  p.normal_cam = one[0].normal;
  EXPECT_FALSE(mirror_pose(p, 0.25).has_value());
}

}  // namespace
}  // namespace ceilnav::host::pattern
