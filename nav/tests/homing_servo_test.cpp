// Seed 004's two-step servo (nav/homing_servo.hpp): the adaptive gain's
// shape, the robot's error from the camera's measurement with the look point
// ahead of the axis, the look offset from turns in place, and the closed
// loop on an exact unicycle (no rendering): from starts up to 1.5 m away
// and headings all round, the servo ends within its tolerances, with its
// phases in the seed's order.
#include "nav/homing_servo.hpp"

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "nav/odometry_step.hpp"

namespace ceilnav::nav {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(AdaptiveGain, RunsFromItsValueAtZeroToItsValueAtInfinity) {
  const AdaptiveGain g{2.0, 0.5, 3.0};
  EXPECT_DOUBLE_EQ(g(0.0), 2.0);
  EXPECT_NEAR(g(100.0), 0.5, 1e-12);
  // The slope at zero: (g(h) - g(0)) / h -> -3.
  EXPECT_NEAR((g(1e-7) - g(0.0)) / 1e-7, -3.0, 1e-5);
  EXPECT_LT(g(0.2), g(0.1));
  EXPECT_DOUBLE_EQ(g(-0.3), g(0.3));
  const AdaptiveGain constant{1.2, 1.2, 5.0};
  EXPECT_DOUBLE_EQ(constant(0.7), 1.2);
}

// The measurement a camera whose look point sits at c on the robot makes of
// a site whose robot pose is `site`: s = p + R(g) c - c (p: the site's
// wheel-axis midpoint in the robot's frame, g: its heading minus the
// robot's).
HomingMeasurement measure(const Pose2& robot, const Pose2& site, double cf, double cl) {
  const double dx = site.x_m - robot.x_m, dy = site.y_m - robot.y_m;
  const double c = std::cos(robot.yaw_rad), s = std::sin(robot.yaw_rad);
  const double px = c * dx + s * dy, py = -s * dx + c * dy;
  const double g = wrap_angle(site.yaw_rad - robot.yaw_rad);
  HomingMeasurement m;
  m.forward_m = px + std::cos(g) * cf - std::sin(g) * cl - cf;
  m.left_m = py + std::sin(g) * cf + std::cos(g) * cl - cl;
  m.turn_rad = g;
  return m;
}

TEST(HomingServo, RobotErrorUndoesTheLookOffset) {
  const Pose2 site{1.0, 2.0, 0.4};
  for (const Pose2& robot : {Pose2{1.3, 1.8, -0.2}, Pose2{0.2, 2.5, 2.9}, Pose2{1.0, 2.0, -2.0}}) {
    const HomingMeasurement m = measure(robot, site, 0.12, -0.03);
    const HomingError e = robot_error(m, 0.12, -0.03);
    const double dx = site.x_m - robot.x_m, dy = site.y_m - robot.y_m;
    EXPECT_NEAR(e.forward_m, std::cos(robot.yaw_rad) * dx + std::sin(robot.yaw_rad) * dy, 1e-12);
    EXPECT_NEAR(e.left_m, -std::sin(robot.yaw_rad) * dx + std::cos(robot.yaw_rad) * dy, 1e-12);
    EXPECT_NEAR(e.turn_rad, wrap_angle(site.yaw_rad - robot.yaw_rad), 1e-12);
  }
  // A robot on the site but turned sees the site camera away from its own
  // camera (the look point moves on a circle), and its error is zero.
  const HomingMeasurement m = measure({1.0, 2.0, 1.4}, site, 0.12, -0.03);
  EXPECT_GT(std::hypot(m.forward_m, m.left_m), 0.1);
  EXPECT_NEAR(robot_error(m, 0.12, -0.03).distance_m(), 0.0, 1e-12);
}

TEST(HomingServo, LookOffsetFromTurnsIsExactOnExactTurns) {
  const Pose2 site{0.0, 0.0, 0.3};
  std::vector<HomingMeasurement> turns;
  for (int k = 1; k <= 5; ++k) {
    turns.push_back(measure({0.0, 0.0, 0.3 + k * kPi / 3.0}, site, 0.116, -0.0105));
  }
  const Eigen::Vector2d c = look_offset_from_turns(turns);
  EXPECT_NEAR(c.x(), 0.116, 1e-12);
  EXPECT_NEAR(c.y(), -0.0105, 1e-12);
  // Too little turning, or too few turns, is refused.
  EXPECT_THROW(look_offset_from_turns({turns[0]}), std::invalid_argument);
  std::vector<HomingMeasurement> small{measure({0, 0, 0.35}, site, 0.1, 0.0),
                                       measure({0, 0, 0.4}, site, 0.1, 0.0)};
  EXPECT_THROW(look_offset_from_turns(small), std::invalid_argument);
  // Turns that were not measured do not count.
  turns[1].status = MeasurementStatus::not_found;
  turns[1].forward_m = 5.0;
  EXPECT_NEAR(look_offset_from_turns(turns).x(), 0.116, 1e-12);
}

TEST(HomingServo, ParametersAreChecked) {
  HomingServoParams p;
  p.position.at_zero = 0.0;
  EXPECT_THROW(HomingServo{p}, std::invalid_argument);
  p = {};
  p.drive_cone_rad = 2.0;
  EXPECT_THROW(HomingServo{p}, std::invalid_argument);
  p = {};
  p.hysteresis = 0.5;
  EXPECT_THROW(HomingServo{p}, std::invalid_argument);
  p = {};
  p.max_speed_m_s = std::nan("");
  EXPECT_THROW(HomingServo{p}, std::invalid_argument);
  p = {};
  p.fine_smoothing = 0.0;
  EXPECT_THROW(HomingServo{p}, std::invalid_argument);
  p = {};
  p.turn_resume_position_m = 0.001;  // below hysteresis x position_tolerance_m
  EXPECT_THROW(HomingServo{p}, std::invalid_argument);
}

TEST(HomingServo, AMeasurementThatIsNotOkStopsTheRobot) {
  HomingServo servo;
  HomingMeasurement m = measure({0.5, 0.0, 0.0}, {1.0, 0.0, 0.0}, 0.0, 0.0);
  EXPECT_GT(servo.update(m).v_m_s, 0.0);
  m.status = MeasurementStatus::not_found;
  const HomingCommand c = servo.update(m);
  EXPECT_EQ(c.v_m_s, 0.0);
  EXPECT_EQ(c.omega_rad_s, 0.0);
  EXPECT_EQ(c.phase, HomingPhase::position);
}

TEST(HomingServo, BacksUpToASiteBehind) {
  HomingServo servo;
  const HomingCommand c = servo.update(measure({1.0, 0.0, 0.0}, {0.7, 0.02, 0.0}, 0.0, 0.0));
  EXPECT_LT(c.v_m_s, 0.0);
  EXPECT_EQ(c.phase, HomingPhase::position);
}

// The closed loop on an exact unicycle at 10 Hz, the command applied from
// the next frame (one frame of latency), the robot's rate limits.
struct LoopResult {
  bool done = false;
  double position_m = 0.0, heading_rad = 0.0, time_s = 0.0;
  double max_speed = 0.0, max_rate = 0.0;
  bool phases_in_order = true;
};

LoopResult close_loop(const Pose2& start, const Pose2& site, const HomingServoParams& p,
                      double turn_noise_rad = 0.0, double position_noise_m = 0.0, uint32_t seed = 1,
                      const std::function<void(HomingMeasurement&)>& distort = {}) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  HomingServo servo(p);
  Pose2 robot = start;
  HomingCommand applied;
  LoopResult r;
  HomingPhase last = HomingPhase::position;
  const double dt = 0.02;
  for (int k = 0; k < 60 * 50; ++k) {
    if (k % 5 == 0) {
      HomingMeasurement m = measure(robot, site, p.camera_forward_m, p.camera_left_m);
      m.forward_m += position_noise_m * normal(rng);
      m.left_m += position_noise_m * normal(rng);
      m.turn_rad += turn_noise_rad * normal(rng);
      if (distort) distort(m);
      const HomingCommand c = servo.update(m);
      // Position, then orientation, then done; a step resumes only if its
      // error grew back (not expected on exact measurements).
      if (turn_noise_rad == 0.0 && !distort && c.phase == HomingPhase::position &&
          last != HomingPhase::position) {
        r.phases_in_order = false;
      }
      last = c.phase;
      if (c.phase == HomingPhase::done && applied.v_m_s == 0.0 && applied.omega_rad_s == 0.0) {
        r.done = true;
        r.time_s = k * dt;
        break;
      }
      applied = c;
      r.max_speed = std::max(r.max_speed, std::abs(c.v_m_s));
      r.max_rate = std::max(r.max_rate, std::abs(c.omega_rad_s));
    }
    robot = advance(robot, {applied.v_m_s * dt, applied.omega_rad_s * dt});
  }
  r.position_m = std::hypot(site.x_m - robot.x_m, site.y_m - robot.y_m);
  r.heading_rad = wrap_angle(site.yaw_rad - robot.yaw_rad);
  return r;
}

TEST(HomingServo, ConvergesFromStartsAllRound) {
  HomingServoParams p;
  p.camera_forward_m = 0.116;
  p.camera_left_m = -0.0105;
  const Pose2 site{2.0, -1.0, 0.7};
  int runs = 0;
  double worst_time = 0.0;
  for (double r : {0.01, 0.3, 1.0, 1.5}) {
    for (int b = 0; b < 8; ++b) {
      for (double h : {0.0, 0.5, -1.6, 3.1}) {
        const double bearing = b * kPi / 4.0;
        const Pose2 start{site.x_m + r * std::cos(bearing), site.y_m + r * std::sin(bearing),
                          site.yaw_rad + h};
        const LoopResult res = close_loop(start, site, p);
        ASSERT_TRUE(res.done) << r << " " << b << " " << h;
        EXPECT_LE(res.position_m, p.position_tolerance_m * p.hysteresis) << r << " " << b;
        EXPECT_LE(std::abs(res.heading_rad), p.heading_tolerance_rad) << r << " " << b;
        EXPECT_TRUE(res.phases_in_order) << r << " " << b << " " << h;
        EXPECT_LE(res.max_speed, p.max_speed_m_s + 1e-12);
        EXPECT_LE(res.max_rate, p.max_yaw_rate_rad_s + 1e-12);
        worst_time = std::max(worst_time, res.time_s);
        ++runs;
      }
    }
  }
  std::printf("%d runs, the slowest homed in %.1f s\n", runs, worst_time);
  EXPECT_LT(worst_time, 30.0);
}

// Frame noise of 0.3 deg in the turn and 0.3 mm in the position (a ceiling
// of beams at 3.9 m): every homing ends, and the fine band's smoothing
// keeps the final heading's scatter below half the noise of one frame.
TEST(HomingServo, EndsDespiteFrameNoise) {
  HomingServoParams p;
  p.camera_forward_m = 0.1;
  const Pose2 site{0.0, 0.0, 0.0};
  double sum2 = 0.0, worst_position = 0.0;
  const int runs = 40;
  for (int seed = 1; seed <= runs; ++seed) {
    const Pose2 start{0.2 * std::cos(seed), 0.2 * std::sin(seed), 0.3 * std::sin(3.0 * seed)};
    const LoopResult r =
        close_loop(start, site, p, 0.3 * kPi / 180.0, 0.0003, static_cast<uint32_t>(seed));
    ASSERT_TRUE(r.done) << seed;
    sum2 += r.heading_rad * r.heading_rad;
    worst_position = std::max(worst_position, r.position_m);
  }
  const double rms_deg = std::sqrt(sum2 / runs) * 180.0 / kPi;
  std::printf("noisy frames: heading RMS %.3f deg, worst position %.2f mm\n", rms_deg,
              1e3 * worst_position);
  EXPECT_LT(rms_deg, 0.15);  // half the noise of one frame
  EXPECT_LT(worst_position, 0.003);
}

// A match biased at some turns (the turned grid under changed lamps: 3 mm
// to the left while the turn to the site is 2 - 4 deg, exact elsewhere): the
// turn in place does not send the robot back to step i for it, and the
// homing ends within the tolerances plus the bias it saw at step i's end.
// With the old resumption (hysteresis x position tolerance, 2 mm) the robot
// went back and forth between the steps until the loop's minute ran out.
TEST(HomingServo, ATurnDependentBiasDoesNotRestartThePositionStep) {
  const auto bias = [](HomingMeasurement& m) {
    const double deg = std::abs(m.turn_rad) * 180.0 / kPi;
    if (deg > 2.0 && deg < 4.0) m.left_m += 0.003;
  };
  HomingServoParams p;
  p.camera_forward_m = -0.049;
  p.camera_left_m = 0.046;
  const Pose2 site{0.65, -0.3, 0.17};
  for (double h : {0.1, -0.12, 0.2}) {
    const Pose2 start{0.6, -0.35, 0.17 + h};
    const LoopResult res = close_loop(start, site, p, 0.0, 0.0, 1, bias);
    ASSERT_TRUE(res.done) << h;
    EXPECT_LE(res.position_m, 0.003 + p.position_tolerance_m) << h;
    EXPECT_LE(std::abs(res.heading_rad), p.heading_tolerance_rad) << h;
    EXPECT_LT(res.time_s, 30.0) << h;
  }
  // The same with the step resumed at hysteresis x position tolerance.
  p.turn_resume_position_m = p.hysteresis * p.position_tolerance_m;
  int unfinished = 0;
  for (double h : {0.1, -0.12, 0.2}) {
    const LoopResult res = close_loop({0.6, -0.35, 0.17 + h}, site, p, 0.0, 0.0, 1, bias);
    if (!res.done) ++unfinished;
  }
  std::printf("resumed at 2 mm: %d of 3 homings never ended\n", unfinished);
  EXPECT_GT(unfinished, 0);  // the bias is one that made the robot cycle
}

}  // namespace
}  // namespace ceilnav::nav
