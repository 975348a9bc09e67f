#include "nav/guidance.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Guidance, LineErrorSigns) {
  // A leg along +Y: left of it is -X.
  const LineError e = line_error({-0.2, 1.0, kPi / 2 + 0.1}, {0.0, 0.0}, {0.0, 4.0});
  EXPECT_NEAR(e.lateral_m, 0.2, 1e-15);
  EXPECT_NEAR(e.along_m, 1.0, 1e-15);
  EXPECT_NEAR(e.heading_rad, 0.1, 1e-15);
  EXPECT_NEAR(e.length_m, 4.0, 1e-15);
  EXPECT_THROW(line_error({}, {1.0, 1.0}, {1.0, 1.0}), std::invalid_argument);
}

// Drives the steering law alone along the X axis in steps of ds (constant
// curvature per step, exact arcs); returns e(s) sampled every step.
std::vector<double> drive_line(const SteeringOptions& o, double e0, double psi0, double length,
                               double ds = 1e-3) {
  Pose2 p{0.0, e0, psi0};
  std::vector<double> e;
  for (double s = 0.0; s < length; s += ds) {
    e.push_back(p.y_m);
    const LineError err = line_error(p, {-1.0, 0.0}, {1000.0, 0.0});
    p = advance(p, {ds, steering_curvature(err, o) * ds});
  }
  return e;
}

TEST(Guidance, FeedbackLinearisedLawIsCriticallyDampedInDistance) {
  // e'' + 2/L e' + e/L^2 = 0 with e(0) = e0, e'(0) = 0: e = e0 (1 + s/L) exp(-s/L),
  // also from a heading far off the line (the law is exact, not linearised).
  SteeringOptions o;
  o.max_curvature_per_m = 1e9;
  const double L = o.convergence_length_m, e0 = 0.3, ds = 1e-4;
  const auto e = drive_line(o, e0, 0.0, 3.0, ds);
  for (double s : {0.2, 0.4, 0.8, 1.6, 2.4}) {
    const auto i = static_cast<std::size_t>(std::lround(s / ds));
    EXPECT_NEAR(e[i], e0 * (1.0 + s / L) * std::exp(-s / L), 1e-4) << s;
  }
  for (double v : e) EXPECT_GT(v, 0.0);  // no overshoot
}

TEST(Guidance, PurePursuitIsTheLinearLawAtDampingOneOverRootTwo) {
  // About the line pure pursuit with look-ahead l is kappa = -2 psi / l - 2 e / l^2:
  // L = l / sqrt 2, zeta = 1 / sqrt 2, overshoot exp(-pi zeta / sqrt(1 - zeta^2)) = exp(-pi).
  SteeringOptions pp;
  pp.law = SteeringLaw::pure_pursuit;
  pp.lookahead_m = 0.6;
  SteeringOptions lin;
  lin.law = SteeringLaw::linear;
  lin.convergence_length_m = 0.6 / std::sqrt(2.0);
  lin.damping = 1.0 / std::sqrt(2.0);
  const double e0 = 1e-3;
  const auto a = drive_line(pp, e0, 0.0, 4.0);
  const auto b = drive_line(lin, e0, 0.0, 4.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  EXPECT_LT(worst, 1e-3 * e0 * 10);
  const double overshoot = -*std::min_element(a.begin(), a.end()) / e0;
  EXPECT_NEAR(overshoot, std::exp(-kPi), 0.003);
}

// Closed loop on a polyline with a perfect state: returns the largest lateral
// error to the leg being driven, outside pivots.
struct DriveResult {
  double max_lateral_m = 0.0;
  int pivots = 0;
  Pose2 end;
  FollowerMode mode = FollowerMode::follow;
  double time_s = 0.0;
};
DriveResult follow(const std::vector<Eigen::Vector2d>& path, Pose2 p, const FollowerOptions& o,
                   double blind_from_m = 1e9) {
  PathFollower f(path, o);
  DriveResult r;
  const double dt = 0.01;
  double travelled = 0.0;
  FollowerMode last = f.mode();
  for (int k = 0; k < 200000 && f.mode() != FollowerMode::finished; ++k) {
    const double blind = std::max(0.0, travelled - blind_from_m);
    const Command c = f.update(p, dt, blind);
    if (c.mode == FollowerMode::pivot && last != FollowerMode::pivot) ++r.pivots;
    last = c.mode;
    if (c.mode == FollowerMode::lost) break;
    if (c.mode == FollowerMode::follow)
      r.max_lateral_m = std::max(r.max_lateral_m, std::abs(c.error.lateral_m));
    p = advance(p, {c.v_mps * dt, c.omega_radps * dt});
    travelled += c.v_mps * dt;
    r.time_s += dt;
  }
  r.end = p;
  r.mode = f.mode();
  return r;
}

TEST(Guidance, FollowerPivotsAtJunctionsAndStopsAtTheEnd) {
  // Straight, an L-turn left, a T-branch taken right, a gentle bend (steered through).
  const std::vector<Eigen::Vector2d> path = {
      {0.0, 0.0}, {4.0, 0.0}, {4.0, 3.0}, {7.0, 3.0}, {10.0, 3.3}};
  const DriveResult r = follow(path, {0.0, 0.0, 0.0}, {});
  EXPECT_EQ(r.mode, FollowerMode::finished);
  EXPECT_EQ(r.pivots, 2);
  // The bend of atan(0.1) is steered through: handed over with heading error
  // -t, e(s) = -sin(t) s exp(-s/L) peaks at s = L with sin(t) L / e.
  const double t = std::atan(0.1), L = FollowerOptions{}.steering.convergence_length_m;
  EXPECT_NEAR(r.max_lateral_m, std::sin(t) * L / std::exp(1.0), 5e-4);
  EXPECT_NEAR(r.end.x_m, 10.0, 2e-3);
  EXPECT_NEAR(r.end.y_m, 3.3, 2e-3);
}

TEST(Guidance, FollowerConvergesFromAnOffsetStart) {
  const DriveResult r = follow({{0.0, 0.0}, {6.0, 0.0}}, {0.0, 0.05, 0.05}, {});
  EXPECT_EQ(r.mode, FollowerMode::finished);
  EXPECT_NEAR(r.end.y_m, 0.0, 1e-4);
}

TEST(Guidance, BlindTravelSlowsThenStops) {
  FollowerOptions o;
  PathFollower f({{0.0, 0.0}, {20.0, 0.0}}, o);
  Pose2 p{};
  Command c;
  for (int k = 0; k < 400; ++k) c = f.update(p, 0.01, 0.0);  // up to cruise speed
  EXPECT_NEAR(c.v_mps, o.cruise_speed_mps, 1e-12);
  for (int k = 0; k < 400; ++k) c = f.update(p, 0.01, o.blind_slow_m + 0.01);
  EXPECT_NEAR(c.v_mps, o.blind_speed_mps, 1e-12);
  c = f.update(p, 0.01, o.blind_stop_m);
  EXPECT_EQ(c.mode, FollowerMode::lost);
  EXPECT_EQ(c.v_mps, 0.0);
  c = f.update(p, 0.01, 0.0);  // a fix again
  EXPECT_EQ(c.mode, FollowerMode::follow);
  EXPECT_GT(c.v_mps, 0.0);
}

TEST(Guidance, BadPathsAreRefused) {
  EXPECT_THROW(PathFollower({{0.0, 0.0}}), std::invalid_argument);
  EXPECT_THROW(PathFollower({{0.0, 0.0}, {0.0, 0.0}}), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::nav
