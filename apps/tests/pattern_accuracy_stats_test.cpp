// The pattern-accuracy study's figures on hand-made rows: the per-theta and
// per-D maxima (projection over the seed's beta = +-90 deg only), the
// conic+bars RMS sums, beta and bar-code counts, and the pass rule.
#include <gtest/gtest.h>

#include <vector>

#include "apps/pattern_accuracy.hpp"

namespace ceilnav::app {
namespace {

constexpr double kRadius = 0.1;

PatternAccuracyRow row(double d, double theta, bool seed_set) {
  PatternAccuracyRow r{};
  r.d = d;
  r.theta = theta;
  r.seed_set = seed_set;
  for (int m = 0; m < kPatternMethods; ++m) r.ok[m] = true;
  r.identity = 7;
  r.read = 7;
  r.code_visible = true;
  r.bar_px = 2.0;
  return r;
}

TEST(PatternAccuracyStats, MaximaPerThetaAndDistance) {
  std::vector<PatternAccuracyRow> rows;
  PatternAccuracyRow a = row(2.0, 30.0, true);
  a.err[0][1] = -0.5;  // projection theta error, seed set: counted
  a.err[3][0] = 0.1;   // conic+bars D error %
  a.err[3][1] = -0.2;
  PatternAccuracyRow b = row(3.0, 30.0, false);
  b.err[0][1] = 4.0;  // projection off the seed set: not counted
  b.err[2][1] = 0.7;
  b.err[3][0] = -0.2;
  b.err[3][1] = 0.1;
  rows = {a, b};
  const PatternAccuracyStats st = summarise_pattern_accuracy(rows, kRadius);
  ASSERT_EQ(st.by_theta.size(), 1u);
  const auto& t = st.by_theta.at(30.0);
  EXPECT_DOUBLE_EQ(t[0], 0.5);
  EXPECT_DOUBLE_EQ(t[2], 0.7);
  EXPECT_DOUBLE_EQ(t[3], 0.2);
  EXPECT_DOUBLE_EQ(t[4], 0.2 * 0.2 + 0.1 * 0.1);  // conic+bars sum of squares
  EXPECT_EQ(st.counts_theta.at(30.0)[0], 2);
  ASSERT_EQ(st.by_d.size(), 2u);
  EXPECT_DOUBLE_EQ(st.by_d.at(3.0)[3], 0.2);
  EXPECT_EQ(st.by_d.at(3.0)[0], 0.0);  // its projection row was off the seed set
  EXPECT_DOUBLE_EQ(st.conic_d_max, 0.2);
  EXPECT_DOUBLE_EQ(st.conic_theta_max15, 0.2);
  EXPECT_TRUE(st.bars_ok);
  EXPECT_TRUE(st.pass());
}

TEST(PatternAccuracyStats, ThetaBarAppliesFrom15Degrees) {
  PatternAccuracyRow low = row(2.0, 7.5, true);
  low.err[3][1] = 2.0;  // large, but below theta 15: not under the bar
  PatternAccuracyRow high = row(2.0, 15.0, true);
  high.err[3][1] = 0.31;
  PatternAccuracyStats st = summarise_pattern_accuracy({low}, kRadius);
  EXPECT_EQ(st.conic_theta_max15, 0.0);
  EXPECT_TRUE(st.pass());
  st = summarise_pattern_accuracy({low, high}, kRadius);
  EXPECT_DOUBLE_EQ(st.conic_theta_max15, 0.31);
  EXPECT_FALSE(st.pass());
}

TEST(PatternAccuracyStats, MissedPoseOrDistanceFailsTheBars) {
  PatternAccuracyRow missed = row(2.0, 30.0, true);
  missed.ok[3] = false;
  PatternAccuracyStats st = summarise_pattern_accuracy({missed}, kRadius);
  EXPECT_FALSE(st.bars_ok);
  EXPECT_FALSE(st.pass());
  PatternAccuracyRow far = row(5.0, 30.0, true);
  far.err[3][0] = -0.35;
  st = summarise_pattern_accuracy({far}, kRadius);
  EXPECT_DOUBLE_EQ(st.conic_d_max, 0.35);
  EXPECT_FALSE(st.pass());
}

TEST(PatternAccuracyStats, BetaCountedWhereTheDiscIsTilted) {
  PatternAccuracyRow tilted = row(1.0, 30.0, true);  // D sin(theta) = 0.5 >= 1.5 R
  tilted.beta_ok[1] = true;
  tilted.beta_ok[3] = true;
  PatternAccuracyRow flat = row(1.0, 15.0, true);  // 0.26 >= 0.15: counted, none right
  PatternAccuracyRow small = row(1.0, 7.5, true);  // theta < 15: not counted
  small.beta_ok[3] = true;
  const PatternAccuracyStats st = summarise_pattern_accuracy({tilted, flat, small}, kRadius);
  EXPECT_EQ(st.beta_frames, 2);
  EXPECT_EQ(st.beta_resolved[1], 1);
  EXPECT_EQ(st.beta_resolved[2], 0);
  EXPECT_EQ(st.beta_resolved[3], 1);
  // With a larger disc the 15-degree frame falls under 1.5 R.
  EXPECT_EQ(summarise_pattern_accuracy({tilted, flat, small}, 0.2).beta_frames, 1);
}

TEST(PatternAccuracyStats, BarCodeReadsAndWrongIdentities) {
  PatternAccuracyRow read = row(2.0, 30.0, true);
  PatternAccuracyRow thin = row(5.0, 30.0, true);
  thin.bar_px = 1.2;  // in view, bars too thin: not required
  thin.read = -1;
  PatternAccuracyRow out = row(5.0, 60.0, true);
  out.code_visible = false;
  out.read = -1;
  PatternAccuracyStats st = summarise_pattern_accuracy({read, thin, out}, kRadius);
  EXPECT_EQ(st.visible, 1);
  EXPECT_EQ(st.visible_read, 1);
  EXPECT_EQ(st.visible_thin, 1);
  EXPECT_EQ(st.wrong, 0);
  EXPECT_TRUE(st.identity_ok());
  EXPECT_TRUE(st.pass());

  PatternAccuracyRow unread = row(2.0, 30.0, true);
  unread.read = -1;  // visible, not read
  st = summarise_pattern_accuracy({read, unread}, kRadius);
  EXPECT_EQ(st.visible_read, 1);
  EXPECT_FALSE(st.identity_ok());
  EXPECT_FALSE(st.pass());

  PatternAccuracyRow wrong = row(5.0, 60.0, true);
  wrong.code_visible = false;
  wrong.read = 8;  // a read of the wrong identity counts even out of view
  st = summarise_pattern_accuracy({read, wrong}, kRadius);
  EXPECT_EQ(st.wrong, 1);
  EXPECT_FALSE(st.pass());
}

}  // namespace
}  // namespace ceilnav::app
