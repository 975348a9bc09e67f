#include "host/pattern/pattern_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace ceilnav::host::pattern {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(PatternSearch, SeedScanRuleEq33To37) {
  // 60 deg field of view, 30 Hz, pattern half width 0.6 m, D_min 2 m.
  ScanParams p{60 * kDeg, 30.0, 0.6, 2.0, 0.0};
  const double phi0 = 2.0 * std::atan(0.3);  // eq. 34
  EXPECT_NEAR(pattern_angle_rad(p), phi0, 1e-15);
  EXPECT_NEAR(max_pan_rate(p), (60 * kDeg - phi0) * 30.0, 1e-12);  // eq. 35
  // Eq. 36-37: a robot at 1 m/s moves the pattern by atan(1 / (30 * 2)) per frame.
  p.robot_speed_mps = 1.0;
  EXPECT_NEAR(motion_angle_rad(p), std::atan(1.0 / 60.0), 1e-15);
  EXPECT_NEAR(max_pan_rate(p), (60 * kDeg - phi0 - std::atan(1.0 / 60.0)) * 30.0, 1e-12);
  // A pan step of one frame at that rate leaves an overlap of exactly the
  // pattern's angle plus its motion: the pattern is whole in some frame.
  const double step = max_pan_rate(p) / 30.0;
  EXPECT_NEAR(60 * kDeg - step, phi0 + motion_angle_rad(p), 1e-12);
  // Too close: the pattern spans more than the field of view -> 0, never negative.
  p.d_min_m = 0.3;
  EXPECT_EQ(max_pan_rate(p), 0.0);
  p.video_rate_hz = 0.0;
  EXPECT_EQ(max_pan_rate(p), 0.0);
}

// The helical scan covers what it must: every direction within the tilt
// range, all the way round, has the whole pattern (its angle at D_min plus
// one frame's motion) inside some frame (checked exactly on the sphere on a
// 1 deg grid); every frame-to-frame step is within the scan rule's per-frame
// limit on each axis (eq. 33-37: fov - phi_0 - phi_m), and the tilt within
// the mount's range.
TEST(PatternSearch, HelicalScanCoversTheRegionWithinTheScanRule) {
  struct Case {
    double hfov, vfov, d_min, speed, tilt0, range;
  };
  for (const Case c :
       {Case{63.2, 49.5, 2.0, 0.0, 0.0, 20.0}, Case{63.2, 49.5, 1.5, 0.5, 10.0, 30.0},
        Case{40.0, 30.0, 3.0, 0.0, -5.0, 10.0}, Case{90.0, 70.0, 1.0, 1.0, 0.0, 45.0}}) {
    HelicalParams p;
    p.hfov_rad = c.hfov * kDeg;
    p.vfov_rad = c.vfov * kDeg;
    p.d_min_m = c.d_min;
    p.robot_speed_mps = c.speed;
    p.pan0_rad = 30.0 * kDeg;
    p.tilt0_rad = c.tilt0 * kDeg;
    p.tilt_range_rad = c.range * kDeg;
    const std::vector<PanTilt> scan = helical_scan(p);
    ASSERT_GT(scan.size(), 3u) << c.hfov;
    EXPECT_NEAR(scan[0].pan_rad, p.pan0_rad, 1e-12);
    EXPECT_NEAR(scan[0].tilt_rad, p.tilt0_rad, 1e-12);
    const ScanParams sp{p.hfov_rad, p.video_rate_hz, p.pattern_half_width_m, p.d_min_m,
                        p.robot_speed_mps};
    const double lost = pattern_angle_rad(sp) + motion_angle_rad(sp);
    for (std::size_t i = 1; i < scan.size(); ++i) {
      EXPECT_LE(std::abs(scan[i].pan_rad - scan[i - 1].pan_rad), p.hfov_rad - lost) << i;
      EXPECT_LE(std::abs(scan[i].tilt_rad - scan[i - 1].tilt_rad), p.vfov_rad - lost) << i;
      EXPECT_LE(std::abs(scan[i].tilt_rad - p.tilt0_rad), p.tilt_range_rad + 1e-12) << i;
    }
    const double r = 0.5 * lost;
    int holes = 0;
    for (int tilt = -static_cast<int>(c.range); tilt <= static_cast<int>(c.range); ++tilt) {
      for (int pan = -180; pan < 180; ++pan) {
        const PanTilt d{pan * kDeg, (c.tilt0 + tilt) * kDeg};
        bool seen = false;
        for (const PanTilt& f : scan) {
          if (cone_in_view(f, p.hfov_rad, p.vfov_rad, d, r)) {
            seen = true;
            break;
          }
        }
        if (!seen) ++holes;
      }
    }
    EXPECT_EQ(holes, 0) << c.hfov << " " << c.range << " frames " << scan.size();
    std::printf(
        "helix %.1f x %.1f deg, D_min %.1f m, v %.1f m/s, tilt %+.0f +- %.0f deg: %zu frames\n",
        c.hfov, c.vfov, c.d_min, c.speed, c.tilt0, c.range, scan.size());
  }
}

// The seed's 1-D rule applied to each axis of the helix (pitch per turn and
// step = the whole footprint, fraction 1) leaves directions whose pattern no
// frame holds whole (docs/seed_errata.md): the coverage check above is not
// vacuous, and the planner's fraction 0.7 (< 1/sqrt(2)) is needed.
TEST(PatternSearch, HelixAtTheOneDimensionalRuleLeavesHoles) {
  HelicalParams p;
  p.hfov_rad = 63.2 * kDeg;
  p.vfov_rad = 49.5 * kDeg;
  p.d_min_m = 2.0;
  p.tilt_range_rad = 20.0 * kDeg;
  p.fraction = 1.0;
  const std::vector<PanTilt> scan = helical_scan(p);
  const ScanParams sp{p.hfov_rad, p.video_rate_hz, p.pattern_half_width_m, p.d_min_m, 0.0};
  int holes = 0;
  for (int tilt = -20; tilt <= 20; ++tilt) {
    for (int pan = -180; pan < 180; ++pan) {
      bool seen = false;
      for (const PanTilt& f : scan) {
        seen = seen || cone_in_view(f, p.hfov_rad, p.vfov_rad, {pan * kDeg, tilt * kDeg},
                                    0.5 * pattern_angle_rad(sp));
      }
      if (!seen) ++holes;
    }
  }
  EXPECT_GT(holes, 0);
  p.fraction = kHelixFraction;
  EXPECT_LT(scan.size(), helical_scan(p).size());
}

TEST(PatternSearch, HelicalScanRefusesWhatNoScanCanDo) {
  HelicalParams p;
  p.hfov_rad = 60.0 * kDeg;
  p.vfov_rad = 45.0 * kDeg;
  p.d_min_m = 0.5;  // the pattern (1.18 m) spans more than the field: no scan
  p.tilt_range_rad = 10.0 * kDeg;
  EXPECT_TRUE(helical_scan(p).empty());
  p.d_min_m = 2.0;
  p.tilt_range_rad = 85.0 * kDeg;  // beyond the mount
  EXPECT_TRUE(helical_scan(p).empty());
  p.tilt_range_rad = 0.0;  // a level scan: the helix degenerates to pan sweeps
  const auto level = helical_scan(p);
  ASSERT_FALSE(level.empty());
  for (const PanTilt& f : level) EXPECT_EQ(f.tilt_rad, 0.0);
}

// Eq. 15-16 with the disc's radius: the side wall shows only when the
// camera's foot on the wall is outside it (D sin theta > R'), and the seed's
// t = T f sin theta / D is the limit for R' << D sin theta; T_min gives the
// asked width.
TEST(PatternSearch, ShadowWidthAndMinimumThicknessEq15To16) {
  const double f = 520.0, rp = 0.275;
  EXPECT_EQ(shadow_width_px(0.05, rp, f, 1.0, 10.0 * kDeg), 0.0);  // 0.17 m < R'
  EXPECT_EQ(shadow_width_px(0.0, rp, f, 3.0, 30.0 * kDeg), 0.0);
  // Far, thin, small R': the seed's formula.
  const double seed = 0.01 * f * std::sin(40.0 * kDeg) / 50.0;
  EXPECT_NEAR(shadow_width_px(0.01, 1e-6, f, 50.0, 40.0 * kDeg) / seed, 1.0, 0.002);
  // The standard pattern (T 0.05 m, R' 0.275 m) at 5 m, 15 deg: the seed's
  // formula gives 1.35 px; with R' the band is 0.81 of that.
  const double t = shadow_width_px(0.05, rp, f, 5.0, 15.0 * kDeg);
  const double t_seed = 0.05 * f * std::sin(15.0 * kDeg) / 5.0;
  EXPECT_LT(t, 0.85 * t_seed);
  EXPECT_GT(t, 0.7 * t_seed);
  for (const double n : {0.5, 1.0, 2.0}) {
    const double tm = min_thickness_m(n, rp, f, 5.0, 15.0 * kDeg);
    ASSERT_TRUE(std::isfinite(tm));
    EXPECT_NEAR(shadow_width_px(tm, rp, f, 5.0, 15.0 * kDeg), n, 1e-9);
    // The seed's eq. 16 asks less: T_seed = n D / (f sin theta).
    EXPECT_GT(tm, n * 5.0 / (f * std::sin(15.0 * kDeg)));
  }
  EXPECT_TRUE(std::isinf(min_thickness_m(1.0, rp, f, 1.0, 10.0 * kDeg)));
}

}  // namespace
}  // namespace ceilnav::host::pattern
