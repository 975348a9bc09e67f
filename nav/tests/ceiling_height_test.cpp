#include "nav/ceiling_height.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

TEST(CeilingHeight, WithoutMeasurementsTheMapHolds) {
  CeilingHeightFilter f;
  const auto e = f.estimate(3, 2.2);
  EXPECT_DOUBLE_EQ(e.height_m, 2.2);
  EXPECT_NEAR(e.sigma_m, 0.02 * 2.2, 1e-12);
  EXPECT_EQ(e.updates, 0);
  // The zone keeps its state: a later map value does not restart it.
  EXPECT_DOUBLE_EQ(f.estimate(3, 9.0).height_m, 2.2);
}

TEST(CeilingHeight, GateRejectsAWrongFeatureAndLeavesTheFilter) {
  CeilingHeightFilter f;
  EXPECT_FALSE(f.update(0, 2.2, CeilingHeightFilter::Source::width, 4.4, 0.002));
  EXPECT_EQ(f.counters().width_rejected, 1);
  EXPECT_DOUBLE_EQ(f.estimate(0, 2.2).height_m, 2.2);
  EXPECT_TRUE(f.update(0, 2.2, CeilingHeightFilter::Source::flow, 2.25, 0.01));
  EXPECT_EQ(f.counters().flow_accepted, 1);
}

TEST(CeilingHeight, RejectsBadArguments) {
  CeilingHeightFilter f;
  EXPECT_THROW(f.estimate(0, 0.0), std::invalid_argument);
  EXPECT_THROW(f.update(0, 2.0, CeilingHeightFilter::Source::width, NAN, 0.01),
               std::invalid_argument);
  EXPECT_THROW(f.update(0, 2.0, CeilingHeightFilter::Source::width, 2.0, 0.0),
               std::invalid_argument);
  CeilingHeightOptions bad;
  bad.map_sigma_fraction = 0.0;
  EXPECT_THROW(CeilingHeightFilter{bad}, std::invalid_argument);
}

// Monte Carlo over maps off by their sigma, biased width and flow methods and
// white noise, two zones seen one after the other: the height's error over
// its sigma is standard normal (NEES of one dof: mean 1, and the 95 % band
// holds 95 % of the runs), and the error shrinks from the map's 2 % to the
// width method's shared 0.3 %.
TEST(CeilingHeight, ConsistentOverMonteCarloAndBelowTheMapsError) {
  const CeilingHeightOptions o;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n01(0.0, 1.0);
  const int runs = 2000;
  double nees_sum = 0.0, err2_map = 0.0, err2 = 0.0;
  int in_band = 0;
  for (int r = 0; r < runs; ++r) {
    CeilingHeightFilter f(o);
    const double bw = o.width_bias_fraction * n01(rng), bf = o.flow_bias_fraction * n01(rng);
    const double truth[2] = {2.2, 2.5};
    double map[2];
    for (int z = 0; z < 2; ++z) map[z] = truth[z] * (1.0 + o.map_sigma_fraction * n01(rng));
    for (int z = 0; z < 2; ++z) {
      for (int k = 0; k < 60; ++k) {
        const double sw = 0.002 * truth[z];
        f.update(z, map[z], CeilingHeightFilter::Source::width,
                 truth[z] * (1.0 + bw) + sw * n01(rng), sw);
        if (k % 10 == 9) {
          const double sf = 0.004 * truth[z];
          f.update(z, map[z], CeilingHeightFilter::Source::flow,
                   truth[z] * (1.0 + bf) + sf * n01(rng), sf);
        }
      }
    }
    const auto e = f.estimate(1, map[1]);
    const double d = (e.height_m - truth[1]) / e.sigma_m;
    nees_sum += d * d;
    in_band += std::abs(d) <= 1.96;
    err2 += std::pow(e.height_m - truth[1], 2);
    err2_map += std::pow(map[1] - truth[1], 2);
  }
  EXPECT_NEAR(nees_sum / runs, 1.0, 0.1);
  EXPECT_NEAR(static_cast<double>(in_band) / runs, 0.95, 0.015);
  const double rel = std::sqrt(err2 / runs) / 2.5, rel_map = std::sqrt(err2_map / runs) / 2.5;
  EXPECT_NEAR(rel_map, 0.02, 0.002);
  EXPECT_LT(rel, 0.0035);
  EXPECT_GT(rel, 0.002);  // the width method's shared error stays
}

}  // namespace
}  // namespace ceilnav::nav
