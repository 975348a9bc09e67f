#include "host/corridor/corridor_types.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ceilnav::host::corridor {
namespace {

TEST(CorridorTypes, NormalFormRoundTripsThroughHomogeneous) {
  for (double theta : {0.0, 0.3, 1.5707963, 2.9, 3.14}) {
    for (double rho : {-120.0, 0.0, 37.5}) {
      const ImageLine l{theta, rho, 2.0};
      const ImageLine m = line_from_homogeneous(-3.0 * l.homogeneous(), 2.0);
      // Same line: theta in [0, pi) and the same point set.
      EXPECT_GE(m.theta_rad, 0.0);
      EXPECT_LT(m.theta_rad, std::numbers::pi);
      EXPECT_NEAR(m.theta_rad, theta, 1e-12);
      EXPECT_NEAR(m.rho_px, rho, 1e-9);
    }
  }
  // A normal pointing to theta in [pi, 2 pi) is flipped with the sign of rho.
  const ImageLine f = line_from_homogeneous({0.0, -1.0, 5.0});  // -v + 5 = 0: v = 5
  EXPECT_NEAR(f.theta_rad, std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(f.rho_px, 5.0, 1e-12);
}

TEST(CorridorTypes, IntersectionLiesOnBothLines) {
  const ImageLine a{0.4, 100.0}, b{1.9, -30.0};
  const ImagePoint p = intersect(a, b);
  ASSERT_TRUE(p.finite);
  EXPECT_NEAR(a.homogeneous().dot(Eigen::Vector3d(p.px.x(), p.px.y(), 1.0)), 0.0, 1e-9);
  EXPECT_NEAR(b.homogeneous().dot(Eigen::Vector3d(p.px.x(), p.px.y(), 1.0)), 0.0, 1e-9);
  const ImagePoint q = intersect(a, ImageLine{0.4, 7.0});
  EXPECT_FALSE(q.finite);
  EXPECT_NEAR(std::abs(q.direction.dot(Eigen::Vector2d(std::cos(0.4), std::sin(0.4)))), 0.0, 1e-12);
}

}  // namespace
}  // namespace ceilnav::host::corridor
