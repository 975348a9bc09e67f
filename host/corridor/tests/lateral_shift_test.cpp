#include "host/corridor/lateral_shift.hpp"

#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "host/corridor/tests/corridor_scene.hpp"

namespace ceilnav::host::corridor {
namespace {

using testing::ceiling_lines;
using testing::corridor_camera;
using testing::corridor_mount;
using testing::kDeg;
using testing::lines_of;
using testing::pose_at;

// A model learnt on the corridor's centre line (the seed's "middle path"):
// 17 images, 1 cm of wander and 1 deg of pan wander, and the given line noise.
CorridorModel centre_model(double sigma_theta, double sigma_rho, uint64_t seed) {
  const CameraConfig camera = corridor_camera();
  const golden::corridor::Corridor corridor = golden::corridor::default_corridor();
  std::mt19937_64 rng(seed);
  const bool noisy = sigma_theta > 0.0 || sigma_rho > 0.0;
  std::normal_distribution<double> wander(0.0, noisy ? 0.01 : 0.0),
      pan_noise(0.0, noisy ? 1.0 * kDeg : 0.0);
  std::vector<LearningImage> images;
  for (int i = 0; i < 17; ++i) {
    LearningImage im;
    im.pan_rad = pan_noise(rng);
    im.lines =
        lines_of(ceiling_lines(camera, corridor, pose_at(wander(rng), im.pan_rad, 1.0 + 0.25 * i),
                               sigma_theta, sigma_rho, rng));
    images.push_back(im);
  }
  LearnOptions opt;
  opt.line_height_m = camera.ceiling_above_camera_m();
  return learn_model(images, model_camera(camera, corridor_mount()), opt);
}

std::vector<ImageLine> current_lines(double y, double pan, double sigma_theta, double sigma_rho,
                                     std::mt19937_64& rng, double x = 7.0) {
  return lines_of(ceiling_lines(corridor_camera(), golden::corridor::default_corridor(),
                                pose_at(y, pan, x), sigma_theta, sigma_rho, rng));
}

// The seed's three cases of section 5 (our Delta-y is positive left): 60 cm
// left heading right by 3.002 deg, 10 cm left heading left by 1.45 deg, 60
// cm right heading left by 3.002 deg. Noise-free: S1 is exact for every
// matched line, in metres (the seed prints -3120, -2677, -1870 "with z'_1 =
// -10000").
TEST(LateralShift, SeedCasesAreExactInMetres) {
  const CorridorModel model = centre_model(0.0, 0.0, 1);
  std::mt19937_64 rng(1);
  const struct { double y, pan; } cases[] = {{0.6, -0.0524}, {0.1, 0.0253}, {-0.6, 0.0524}};
  for (const auto& c : cases) {
    const LateralShift s = lateral_shift(current_lines(c.y, c.pan, 0, 0, rng), c.pan, model);
    ASSERT_TRUE(s.valid);
    EXPECT_NEAR(s.shift_m, c.y, 1e-9);
    EXPECT_NEAR(s.strongest_shift_m, c.y, 1e-9);
    EXPECT_GE(s.matches.size(), 5u);
    for (const LineShift& m : s.matches) EXPECT_NEAR(m.shift_m, c.y, 1e-9);
  }
}

// One line, one model line (seed step 9 / eq. 25): the shift is h times the
// change of inclination, its derivatives those of S2.
TEST(LateralShift, OneLineShiftAndItsDerivatives) {
  const CorridorModel model = centre_model(0.0, 0.0, 1);
  const ModelCamera& mc = model.camera;
  const int j = 2;
  const double q0 = model.lines[j].inclination;
  const double shift = 0.37, pan = 4.0 * kDeg;
  const ImageLine now = line_of_inclination(q0 - shift / 1.8, mc, pan, 10.0);
  const std::optional<LineShift> s = line_shift(now, pan, model, j);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->shift_m, shift, 1e-12);
  const double e = 1e-6;
  auto at = [&](double dt, double dr) {
    const ImageLine l = line_from_homogeneous(
        {std::cos(now.theta_rad + dt), std::sin(now.theta_rad + dt), -(now.rho_px + dr)});
    return line_shift(l, pan, model, j)->shift_m;
  };
  EXPECT_NEAR(s->d_shift_d_theta, (at(e, 0) - at(-e, 0)) / (2 * e), 1e-5);
  EXPECT_NEAR(s->d_shift_d_rho, (at(0, e) - at(0, -e)) / (2 * e), 1e-7);
  const ShiftOptions o;
  EXPECT_NEAR(s->sigma_m,
              std::hypot(s->d_shift_d_theta * o.sigma_theta_rad, s->d_shift_d_rho * o.sigma_rho_px),
              1e-12);
}

// The pan only resolves a sign: 1 deg of pan error moves nothing noise-free.
TEST(LateralShift, PanErrorsDoNotMoveTheShift) {
  const CorridorModel model = centre_model(0.0, 0.0, 1);
  std::mt19937_64 rng(2);
  const std::vector<ImageLine> lines = current_lines(-0.45, 6.0 * kDeg, 0, 0, rng);
  for (double err : {-2.0, -1.0, 1.0, 2.0}) {
    const LateralShift s = lateral_shift(lines, (6.0 + err) * kDeg, model);
    ASSERT_TRUE(s.valid);
    EXPECT_NEAR(s.shift_m, -0.45, 1e-9);
  }
}

// Robust matching: a third of the lines missing and two spurious lines.
TEST(LateralShift, MatchesDespiteMissingAndSpuriousLines) {
  const CorridorModel model = centre_model(0.1 * kDeg, 0.5, 3);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int n = 0;
  for (double y = -0.8; y <= 0.8001; y += 0.1) {
    std::vector<ImageLine> lines;
    for (const ImageLine& l : current_lines(y, -5.0 * kDeg, 0.1 * kDeg, 0.5, rng)) {
      if (u01(rng) > 0.33) lines.push_back(l);
    }
    lines.push_back({0.9, 150.0, 1000.0});
    lines.push_back({2.2, -300.0, 1000.0});
    const LateralShift s = lateral_shift(lines, -5.0 * kDeg, model);
    ASSERT_TRUE(s.valid) << y;
    EXPECT_NEAR(s.shift_m, y, 0.06) << y;
    ++n;
  }
  EXPECT_EQ(n, 17);
}

// With only the seams (0.6 m apart) a 0.6 m shift is ambiguous; the prior
// of the tracking picks the right one.
TEST(LateralShift, PriorResolvesThePeriodicAmbiguity) {
  const CorridorModel full = centre_model(0.0, 0.0, 1);
  CorridorModel seams = full;
  seams.lines.clear();
  for (const ModelLine& l : full.lines) {
    const double y = l.inclination * 1.8;
    if (std::abs(y) < 0.01 || std::abs(std::abs(y) - 0.6) < 0.01) seams.lines.push_back(l);
  }
  ASSERT_EQ(seams.lines.size(), 3u);
  // Current: the seams at y = 0 and 0.6 seen from y = 0.6 fit the model's
  // (0, 0.6) for a shift of 0.6 as well as its (-0.6, 0) for a shift of 0.
  std::vector<ImageLine> lines;
  for (double y_line : {0.0, 0.6}) {
    lines.push_back(line_of_inclination((y_line - 0.6) / 1.8, full.camera, 0.0, 100.0));
  }
  ShiftOptions o;
  o.prior_m = 0.55;
  const LateralShift s = lateral_shift(lines, 0.0, seams, o);
  ASSERT_TRUE(s.valid);
  EXPECT_NEAR(s.shift_m, 0.6, 1e-9);
  EXPECT_EQ(s.matches.size(), 2u);
  o.prior_m = 0.0;
  EXPECT_NEAR(lateral_shift(lines, 0.0, seams, o).shift_m, 0.0, 1e-9);
}

// The score: one unit per matched line against ((s - prior) / sigma)^2 / 2.
// A model of lines at y = 0, 0.15, 0.30, 0.45 and the lines at 0, 0.15,
// 0.45 seen from y = 0.15: the true shift 0.15 matches all three, a shift of
// 0 (the 0.15 m step onto the neighbouring lines) two. A prior at 0 with
// sigma 5 cm costs the true shift 4.5 units and the two matches at the prior
// win; with sigma 0.3 m it costs 0.125 and the true shift wins.
TEST(LateralShift, ThePriorWeighsAgainstTheMatchCount) {
  const CorridorModel m = centre_model(0.0, 0.0, 1);
  const double h = m.lines.front().height_m;
  CorridorModel four = m;
  four.lines.clear();
  for (double y : {0.45, 0.30, 0.15, 0.0}) {
    ModelLine l = m.lines.front();
    l.inclination = y / h;
    l.line = line_of_inclination(l.inclination, m.camera, m.pan_rad, 100.0);
    four.lines.push_back(l);
  }
  std::vector<ImageLine> lines;
  for (double y : {0.0, 0.15, 0.45}) {
    lines.push_back(line_of_inclination((y - 0.15) / h, four.camera, 0.0, 100.0));
  }
  ShiftOptions o;
  o.match_tolerance_m = 0.02;
  o.prior_m = 0.0;
  o.prior_sigma_m = 0.3;
  const LateralShift wide = lateral_shift(lines, 0.0, four, o);
  ASSERT_TRUE(wide.valid);
  EXPECT_NEAR(wide.shift_m, 0.15, 1e-9);
  EXPECT_EQ(wide.matches.size(), 3u);
  o.prior_sigma_m = 0.05;
  const LateralShift tight = lateral_shift(lines, 0.0, four, o);
  ASSERT_TRUE(tight.valid);
  EXPECT_NEAR(tight.shift_m, 0.0, 1e-9);
  EXPECT_EQ(tight.matches.size(), 2u);
}

// The reported sigma is the scatter's: Monte Carlo with an exact model.
TEST(LateralShift, SigmaMatchesTheScatter) {
  const CorridorModel model = centre_model(0.0, 0.0, 1);
  std::mt19937_64 rng(9);
  ShiftOptions o;
  o.sigma_theta_rad = 0.15 * kDeg;
  o.sigma_rho_px = 0.7;
  double sum2 = 0.0, sigma2 = 0.0;
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const LateralShift s =
        lateral_shift(current_lines(0.3, 3.0 * kDeg, o.sigma_theta_rad, o.sigma_rho_px, rng),
                      3.0 * kDeg, model, o);
    ASSERT_TRUE(s.valid);
    sum2 += (s.shift_m - 0.3) * (s.shift_m - 0.3);
    sigma2 += s.sigma_m * s.sigma_m;
  }
  const double rms = std::sqrt(sum2 / n), predicted = std::sqrt(sigma2 / n);
  std::printf("sigma: scatter %.4f m, predicted %.4f m\n", rms, predicted);
  EXPECT_NEAR(rms / predicted, 1.0, 0.15);
}

struct SweepResult {
  double combined_rms, strongest_rms, worst;
  int frames, failed;
};

// +-80 cm in 5 cm steps, pans -10..10 deg in 5 deg steps, at four places
// along the corridor; the model learnt on the centre line with the same
// line noise (learnt = true: it then carries the learning drive's 1 cm
// wander too) or exact (learnt = false: the current lines' noise alone).
SweepResult sweep(double sigma_theta, double sigma_rho, bool learnt, uint64_t seed) {
  SweepResult r{0, 0, 0, 0, 0};
  double c2 = 0.0, s2 = 0.0;
  for (uint64_t model_seed = 0; model_seed < 4; ++model_seed) {
    const CorridorModel model = learnt
                                    ? centre_model(sigma_theta, sigma_rho, seed + 100 * model_seed)
                                    : centre_model(0.0, 0.0, 1);
    std::mt19937_64 rng(seed + 7 + model_seed);
    ShiftOptions o;
    o.sigma_theta_rad = sigma_theta;
    o.sigma_rho_px = sigma_rho;
    for (int k = -16; k <= 16; ++k) {
      const double y = 0.05 * k;
      for (double pan_deg : {-10.0, -5.0, 0.0, 5.0, 10.0}) {
        const double x = 3.0 + 1.7 * static_cast<double>(model_seed);
        const LateralShift s =
            lateral_shift(current_lines(y, pan_deg * kDeg, sigma_theta, sigma_rho, rng, x),
                          pan_deg * kDeg, model, o);
        ++r.frames;
        if (!s.valid) {
          ++r.failed;
          continue;
        }
        c2 += (s.shift_m - y) * (s.shift_m - y);
        s2 += (s.strongest_shift_m - y) * (s.strongest_shift_m - y);
        r.worst = std::max(r.worst, std::abs(s.shift_m - y));
      }
    }
  }
  const int ok = r.frames - r.failed;
  r.combined_rms = std::sqrt(c2 / ok);
  r.strongest_rms = std::sqrt(s2 / ok);
  return r;
}

// The goal of the brief: RMS <= 2 cm over +-80 cm at realistic line noise
// (a Hough peak refined to 0.05-0.2 deg and 0.3-1 px), the model learnt
// with the same noise. The limits are the measured values (docs/corridor.md)
// with a margin: the combination of ~9 lines and the model's median make the
// error a few millimetres, dominated by the learning drive's 1 cm wander.
TEST(LateralShift, SweepRmsAtHoughNoise) {
  const struct {
    double theta_deg, rho_px, limit_m;
  } levels[] = {{0.05, 0.3, 0.008}, {0.1, 0.5, 0.008}, {0.2, 1.0, 0.008}, {0.5, 2.0, 0.012}};
  for (const auto& lv : levels) {
    const SweepResult r = sweep(lv.theta_deg * kDeg, lv.rho_px, true, 11);
    std::printf(
        "learnt model, noise %.2f deg %.1f px: combined RMS %.4f m (worst %.4f), strongest line "
        "RMS "
        "%.4f m, %d frames, %d failed\n",
        lv.theta_deg, lv.rho_px, r.combined_rms, r.worst, r.strongest_rms, r.frames, r.failed);
    EXPECT_EQ(r.failed, 0);
    EXPECT_LE(r.combined_rms, lv.limit_m);
    EXPECT_LE(r.combined_rms, 0.02);
  }
}

// The line noise alone (exact model): combining the matched lines beats the
// seed's strongest line (step 9) at every level, by about the square root of
// the number of lines.
TEST(LateralShift, CombiningLinesBeatsTheStrongestLine) {
  const struct {
    double theta_deg, rho_px;
  } levels[] = {{0.05, 0.3}, {0.1, 0.5}, {0.2, 1.0}, {0.5, 2.0}};
  for (const auto& lv : levels) {
    const SweepResult r = sweep(lv.theta_deg * kDeg, lv.rho_px, false, 21);
    std::printf(
        "exact model, noise %.2f deg %.1f px: combined RMS %.4f m (worst %.4f), strongest line RMS "
        "%.4f m\n",
        lv.theta_deg, lv.rho_px, r.combined_rms, r.worst, r.strongest_rms);
    EXPECT_EQ(r.failed, 0);
    EXPECT_LT(r.combined_rms, 0.6 * r.strongest_rms);
  }
}

}  // namespace
}  // namespace ceilnav::host::corridor
