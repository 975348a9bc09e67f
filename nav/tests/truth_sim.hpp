// A pure-math truth simulator for the fusion filter's tests (no rendering): a
// differential-drive robot follows a course of straight tapes with a
// pure-pursuit law on its true pose; its wheels turn as commanded (the
// encoders' reading) and its ground motion follows the odometry error model of
// nav/ekf.hpp (scale errors drawn from the prior, slip per step); the camera on its mount measures
// the tape in view (yaw, offset, Gaussian noise of the stated covariance) and pattern stations near
// it, at 30 fps with a latency of whole frames.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "nav/ekf.hpp"
#include "nav/map.hpp"
#include "nav/measurement.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::nav::sim {

struct SimConfig {
  std::vector<Eigen::Vector2d> course;  // tape centre line, a polyline driven from its first point
  double speed_mps = 0.5;
  double ramp_s = 1.0;  // speed ramps up linearly from 0 over this time
  double tick_s = 0.01;
  double frame_s = 1.0 / 30.0;
  double first_frame_s = 0.004;          // frames are not aligned with ticks
  int latency_min = 1, latency_max = 3;  // frames, uniform
  double lookahead_m = 0.4;
  double max_curvature = 1.0 / 0.3;
  double view_radius_m = 0.8;      // a tape within this of the camera, ...
  double max_rel_yaw_rad = 1.0;    // ... at most this far from the camera's yaw (forward view)
  bool zenith = false;             // report the yaw modulo pi
  double yaw_sigma_rad = 1.75e-3;  // 0.1 deg
  double offset_sigma_m = 5e-3;
  std::vector<Eigen::Vector2d> stations;  // pattern stations (camera over one within 0.25 m: a fix)
  double fix_sigma_m = 0.01, fix_yaw_sigma_rad = 0.0087;
  double duration_s = 0.0;  // 0: until the end of the course
  OdometryModel odometry;
  CameraMount mount;
  // The initial estimate's pose error is drawn from this covariance.
  Eigen::Vector3d pose_sigma0{0.02, 0.02, 0.01};
};

struct Tick {
  OdometryStep step;        // what the encoders report
  State truth;              // true pose and true calibration after the step
  double ds = 0, dpsi = 0;  // true motion over the step
};

struct SimRun {
  State truth0, estimate0;
  Covariance p0;
  std::vector<Tick> ticks;
  std::vector<TapeMeasurement> tapes;  // in exposure order
  std::vector<PatternFix> fixes;
  std::vector<State> tape_truth;  // true state at each tape measurement's exposure
};

inline TapeMap map_of(const std::vector<Eigen::Vector2d>& course) {
  TapeMap m;
  for (std::size_t i = 1; i < course.size(); ++i) m.add({course[i - 1], course[i], 0.05});
  return m;
}

inline Pose2 camera_of(const Pose2& robot, const CameraMount& m) {
  const double c = std::cos(robot.yaw_rad), s = std::sin(robot.yaw_rad);
  return {robot.x_m + c * m.forward_m - s * m.left_m, robot.y_m + s * m.forward_m + c * m.left_m,
          wrap_angle(robot.yaw_rad + m.yaw_rad)};
}

// The true measurement of the tape the camera looks along, if any in view.
inline std::optional<Eigen::Vector2d> true_tape(const TapeMap& map, const Pose2& cam,
                                                const SimConfig& cfg) {
  std::optional<Eigen::Vector2d> best;
  for (const TapeSegment& s : map.segments()) {
    if (distance_to_segment({cam.x_m, cam.y_m}, s) > cfg.view_radius_m) continue;
    const Eigen::Vector2d d = s.b - s.a;
    const double phi = std::atan2(d.y(), d.x());
    for (int branch = 0; branch < 2; ++branch) {
      const double dir = phi + branch * std::numbers::pi;
      const double yaw = wrap_angle(cam.yaw_rad - dir);
      if (std::abs(yaw) > cfg.max_rel_yaw_rad) continue;
      const Eigen::Vector2d n(-std::sin(dir), std::cos(dir));
      const Eigen::Vector2d h(yaw, n.dot(Eigen::Vector2d(cam.x_m, cam.y_m) - s.a));
      if (!best || std::abs(h(0)) < std::abs((*best)(0))) best = h;
    }
  }
  return best;
}

inline SimRun simulate(const SimConfig& cfg, std::mt19937_64& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_int_distribution<int> latency(cfg.latency_min, cfg.latency_max);
  const OdometryModel& om = cfg.odometry;
  const TapeMap map = map_of(cfg.course);
  SimRun run;

  // Path arc length.
  std::vector<double> arc{0.0};
  for (std::size_t i = 1; i < cfg.course.size(); ++i)
    arc.push_back(arc.back() + (cfg.course[i] - cfg.course[i - 1]).norm());
  auto point_at = [&](double s) {
    s = std::clamp(s, 0.0, arc.back());
    std::size_t i = 1;
    while (i + 1 < arc.size() && arc[i] < s) ++i;
    const double f = (s - arc[i - 1]) / (arc[i] - arc[i - 1]);
    return Eigen::Vector2d(cfg.course[i - 1] + f * (cfg.course[i] - cfg.course[i - 1]));
  };

  const Eigen::Vector2d d0 = cfg.course[1] - cfg.course[0];
  State truth = State::Zero();
  truth(state::x) = cfg.course[0].x();
  truth(state::y) = cfg.course[0].y();
  truth(state::yaw) = std::atan2(d0.y(), d0.x());
  truth(state::left_scale) = om.wheel_scale_sigma * gauss(rng);
  truth(state::right_scale) = om.wheel_scale_sigma * gauss(rng);
  truth(state::yaw_scale) = om.yaw_scale_sigma * gauss(rng);
  run.truth0 = truth;
  run.p0 = Ekf::calibration_prior(om);
  for (int i = 0; i < 3; ++i) run.p0(i, i) = cfg.pose_sigma0(i) * cfg.pose_sigma0(i);
  run.estimate0 = State::Zero();
  for (int i = 0; i < 3; ++i) run.estimate0(i) = truth(i) + cfg.pose_sigma0(i) * gauss(rng);

  const double duration = cfg.duration_s > 0.0 ? cfg.duration_s : 1e9;
  double progress = 0.0, t = 0.0;
  double next_frame = cfg.first_frame_s;
  while (t < duration && progress < arc.back() - 0.05) {
    const double v = cfg.speed_mps * std::min(1.0, (t + cfg.tick_s) / cfg.ramp_s);
    const double ds_cmd = v * cfg.tick_s;
    // Pure pursuit on the true pose.
    const Eigen::Vector2d pos(truth(state::x), truth(state::y));
    double best = 1e18;
    for (double s = std::max(0.0, progress - 0.2); s <= progress + 0.3; s += 0.005) {
      const double e = (point_at(s) - pos).squaredNorm();
      if (e < best) {
        best = e;
        progress = std::max(progress, s);
      }
    }
    const Eigen::Vector2d target = point_at(progress + cfg.lookahead_m) - pos;
    const double alpha = wrap_angle(std::atan2(target.y(), target.x()) - truth(state::yaw));
    const double kappa =
        std::clamp(2.0 * std::sin(alpha) / cfg.lookahead_m, -cfg.max_curvature, cfg.max_curvature);
    const double dpsi_cmd = kappa * ds_cmd;

    // The wheels are servoed to the commanded travel: the encoders read it.
    // The ground travel follows from the readings through the model (scale
    // errors, slip independent of the readings: the filter's model).
    const double b = om.wheel_base_m;
    Tick tick;
    tick.step = {t + cfg.tick_s, ds_cmd - 0.5 * b * dpsi_cmd, ds_cmd + 0.5 * b * dpsi_cmd};
    const double l = tick.step.left_m, r = tick.step.right_m;
    const double lt = (1.0 + truth(state::left_scale)) * l +
                      std::sqrt(om.wheel_var_per_m * std::abs(l)) * gauss(rng);
    const double rt = (1.0 + truth(state::right_scale)) * r +
                      std::sqrt(om.wheel_var_per_m * std::abs(r)) * gauss(rng);
    const double ds = 0.5 * (lt + rt);
    const double dpsi = (1.0 + truth(state::yaw_scale)) * (rt - lt) / b +
                        std::sqrt(om.yaw_var_per_rad * std::abs(dpsi_cmd)) * gauss(rng);
    tick.ds = ds;
    tick.dpsi = dpsi;

    const Pose2 before{truth(state::x), truth(state::y), truth(state::yaw)};
    // Frames exposed within this tick: the true pose on the tick's arc.
    while (next_frame <= t + cfg.tick_s) {
      const double f = (next_frame - t) / cfg.tick_s;
      const Pose2 at = advance(before, {f * ds, f * dpsi});
      const Pose2 cam = camera_of(at, cfg.mount);
      const double available = next_frame + latency(rng) * cfg.frame_s;
      if (auto h = true_tape(map, cam, cfg)) {
        TapeMeasurement m;
        m.time = {next_frame, available};
        m.yaw_rad = (*h)(0) + cfg.yaw_sigma_rad * gauss(rng);
        m.offset_m = (*h)(1) + cfg.offset_sigma_m * gauss(rng);
        m.covariance = Eigen::Vector2d(cfg.yaw_sigma_rad * cfg.yaw_sigma_rad,
                                       cfg.offset_sigma_m * cfg.offset_sigma_m)
                           .asDiagonal();
        m.zenith = cfg.zenith;
        if (cfg.zenith && std::abs(m.yaw_rad) >= 0.5 * std::numbers::pi) {
          // Known modulo pi: name the other direction (offset changes side).
          m.yaw_rad = wrap_angle(m.yaw_rad + std::numbers::pi);
          m.offset_m = -m.offset_m;
        }
        run.tapes.push_back(m);
        State s = truth;
        s(state::x) = at.x_m;
        s(state::y) = at.y_m;
        s(state::yaw) = at.yaw_rad;
        run.tape_truth.push_back(s);
      }
      for (const Eigen::Vector2d& st : cfg.stations) {
        if ((Eigen::Vector2d(cam.x_m, cam.y_m) - st).norm() > 0.25) continue;
        PatternFix fx;
        fx.time = {next_frame, available};
        fx.x_m = cam.x_m + cfg.fix_sigma_m * gauss(rng);
        fx.y_m = cam.y_m + cfg.fix_sigma_m * gauss(rng);
        fx.yaw_rad = wrap_angle(cam.yaw_rad + cfg.fix_yaw_sigma_rad * gauss(rng));
        fx.covariance =
            Eigen::Vector3d(cfg.fix_sigma_m * cfg.fix_sigma_m, cfg.fix_sigma_m * cfg.fix_sigma_m,
                            cfg.fix_yaw_sigma_rad * cfg.fix_yaw_sigma_rad)
                .asDiagonal();
        run.fixes.push_back(fx);
      }
      next_frame += cfg.frame_s;
    }
    const Pose2 after = advance(before, {ds, dpsi});
    truth(state::x) = after.x_m;
    truth(state::y) = after.y_m;
    truth(state::yaw) = after.yaw_rad;
    tick.truth = truth;
    run.ticks.push_back(tick);
    t += cfg.tick_s;
  }
  return run;
}

// What the filter reports at every tick of a run.
struct RunResult {
  std::vector<double> nees, pose_nees;
  std::vector<Eigen::Vector3d> error;  // estimate - truth (x, y, yaw)
  std::vector<Eigen::Vector3d> sigma;  // sqrt of the pose covariance's diagonal
  Counters counters;
};

// Runs the filter over a simulated run: each tick's odometry, then every
// measurement whose result is available by the tick's time, in the order of
// availability. `tamper` may change a measurement before it is delivered.
template <typename Tamper>
RunResult run_filter(const SimRun& run, const EkfOptions& opt, const TapeMap& map, bool measure,
                     Tamper tamper) {
  Ekf ekf(opt, &map, 0.0, run.estimate0, run.p0);
  struct Arrival {
    double t;
    bool tape;
    std::size_t i;
  };
  std::vector<Arrival> arrivals;
  if (measure) {
    for (std::size_t i = 0; i < run.tapes.size(); ++i)
      arrivals.push_back({run.tapes[i].time.available_s, true, i});
    for (std::size_t i = 0; i < run.fixes.size(); ++i)
      arrivals.push_back({run.fixes[i].time.available_s, false, i});
  }
  std::stable_sort(arrivals.begin(), arrivals.end(),
                   [](const Arrival& a, const Arrival& b) { return a.t < b.t; });
  RunResult r;
  std::size_t next = 0;
  for (const Tick& tick : run.ticks) {
    ekf.predict(tick.step);
    while (next < arrivals.size() && arrivals[next].t <= tick.step.t_s + 1e-9) {
      const Arrival& a = arrivals[next++];
      if (a.tape) {
        TapeMeasurement m = run.tapes[a.i];
        tamper(m, a.i);
        ekf.update(m);
      } else {
        ekf.update(run.fixes[a.i]);
      }
    }
    r.nees.push_back(ekf.nees(tick.truth));
    const Pose2 truth{tick.truth(state::x), tick.truth(state::y), tick.truth(state::yaw)};
    r.pose_nees.push_back(ekf.pose_nees(truth));
    const Pose2 e = ekf.pose();
    r.error.emplace_back(e.x_m - truth.x_m, e.y_m - truth.y_m,
                         wrap_angle(e.yaw_rad - truth.yaw_rad));
    r.sigma.push_back(ekf.covariance().diagonal().head<3>().cwiseSqrt());
  }
  r.counters = ekf.counters();
  return r;
}

inline RunResult run_filter(const SimRun& run, const EkfOptions& opt, const TapeMap& map,
                            bool measure = true) {
  return run_filter(run, opt, map, measure, [](TapeMeasurement&, std::size_t) {});
}

}  // namespace ceilnav::nav::sim
