#include "nav/chi_square.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

TEST(ChiSquare, QuantilesMatchPublishedTables) {
  // Tabulated values (NIST/SEMATECH handbook, table 1.3.6.7.4); the 150-dof
  // ones from Simpson integration of the density (2e5 intervals).
  EXPECT_NEAR(chi_square_quantile(0.95, 1), 3.841459, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.999, 2), 13.815511, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.999, 3), 16.266236, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.025, 3), 0.215795, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.975, 3), 9.348404, 1e-6);
  EXPECT_NEAR(chi_square_quantile(0.975, 150), 185.800447, 1e-5);
  EXPECT_NEAR(chi_square_quantile(0.025, 150), 117.984515, 1e-5);
}

TEST(ChiSquare, CdfOfTwoDofIsClosedForm) {
  // dof 2: an exponential with mean 2.
  for (double x : {0.01, 0.5, 2.0, 7.0, 30.0})
    EXPECT_NEAR(chi_square_cdf(x, 2), 1.0 - std::exp(-0.5 * x), 1e-14) << x;
  EXPECT_EQ(chi_square_cdf(0.0, 3), 0.0);
  EXPECT_EQ(chi_square_cdf(-1.0, 3), 0.0);
}

}  // namespace
}  // namespace ceilnav::nav
