// The fusion filter: an extended Kalman filter over the robot's planar pose
// and its odometry's calibration, predicted with every wheel-odometry step and
// corrected with tape measurements (through the tape map and the camera
// mount) and pattern fixes, each applied at the exposure time of its frame
// (retroactive correction, seed 001 section 2.2). Models, Jacobians, the
// history and the gate: docs/navigation.md, "Fusion filter" and "Retroactive
// correction".
#pragma once

#include <deque>
#include <vector>

#include <Eigen/Core>

#include "nav/map.hpp"
#include "nav/measurement.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::nav {

// State: robot pose (x, y, yaw of the wheel-axis midpoint, world frame), the
// odometry's calibration errors: each wheel's travel scale error e_l, e_r
// (true travel = (1 + e) * measured) and the heading scale error e_w (true
// heading change = (1 + e_w) * (r - l) / b: the effective wheel base's error),
// and the vision's systematic errors (MeasurementBiasModel): the tape
// measurement's yaw and offset biases, the landmark distances' bias, and the
// relative error kappa of the ceiling height the vision measured with
// (h_used = (1 + kappa) h_true, which scales every offset and distance).
namespace state {
inline constexpr int x = 0, y = 1, yaw = 2, left_scale = 3, right_scale = 4, yaw_scale = 5;
inline constexpr int tape_yaw_bias = 6, tape_offset_bias = 7, landmark_bias = 8;
inline constexpr int ceiling_scale = 9;
inline constexpr int size = 10;
inline constexpr int biases = size - tape_yaw_bias;  // the Gauss-Markov states at the end
}  // namespace state
using State = Eigen::Matrix<double, state::size, 1>;
using Covariance = Eigen::Matrix<double, state::size, state::size>;

// The odometry error model (docs/navigation.md): per step, with measured
// wheel travels l, r and nominal heading change dpsi,
//   true left travel  = (1 + e_l) l + w_l,   var w_l = wheel_var_per_m |l|
//   true right travel = (1 + e_r) r + w_r,   var w_r = wheel_var_per_m |r|
//   true heading change = (1 + e_w)(true r - true l)/b + w_psi,
//                                            var w_psi = yaw_var_per_rad |dpsi|
// w: random slip and tread/floor irregularity (independent per step: the
// variance grows with the distance, a random walk); e: calibration errors,
// constant, with prior standard deviations *_scale_sigma. The defaults give a
// dead-reckoning position sigma of 2.0 % of the distance after 5 m straight
// (seed 004: sigma_o = 2.012e-2 d, its robot's typical leg being under 5 m).
struct OdometryModel {
  double wheel_base_m = 0.4;
  double wheel_var_per_m = 1e-5;      // 3.2 mm per wheel after 1 m
  double yaw_var_per_rad = 4e-4;      // 0.02 rad per radian turned (tyre scrub)
  double wheel_scale_sigma = 1.5e-3;  // wheel radius known to 0.15 %
  double yaw_scale_sigma = 1e-2;      // effective wheel base known to 1 %
};

// Systematic errors of the vision measurements: what a frame's error shares
// with its neighbours' (the lens model's and the renderer's residual where
// the tape sits in the image, a detector's bias at a tape end, the map's
// survey). Each is a first-order Gauss-Markov state, measured z = h(x) + b +
// white noise, whose correlation decays with the distance the camera's view
// moves: exp(-D / length) for D = |travel| + turn_length_m_per_rad |turn|
// (docs/navigation.md, "Systematic errors"). With the sigmas 0 (the default)
// the states stay 0 with zero variance and the filter is the one without them.
//
// The ceiling scale kappa is the relative error of the ceiling height above
// the camera that the vision measured with (the map's, where the camera
// looks): a tape offset and a landmark distance come out (1 + kappa) times
// the true ones, z = (1 + kappa) h(x) + b + noise. Its sigma is the map's
// survey error (relative); its length the distance over which the map's
// error stays the same (a zone of the ceiling). A measured height
// (CeilingHeight) observes it directly; so does a landmark seen from several
// distances while the odometry measures the travel (the flow of seed 000,
// eq. 44, inside the filter).
struct MeasurementBiasModel {
  double tape_yaw_sigma_rad = 0.0;
  double tape_offset_sigma_m = 0.0;
  double landmark_sigma_m = 0.0;
  double ceiling_scale_sigma = 0.0;
  double tape_length_m = 2.0;      // the tape's place in the image changes slowly while following
  double landmark_length_m = 1.0;  // about the stretch over which one landmark stays in view
  double ceiling_length_m = 20.0;  // about a ceiling zone
  double turn_length_m_per_rad = 1.0;
};

// Camera on the robot: its position (forward, left of the wheel-axis
// midpoint) and its yaw relative to the robot's heading.
struct CameraMount {
  double forward_m = 0.0, left_m = 0.0, yaw_rad = 0.0;
};

enum class Timing {
  retroactive,  // a measurement is applied at its frame's exposure time
  at_arrival,   // applied to the present state when it arrives (for comparison)
};

struct EkfOptions {
  OdometryModel odometry;
  MeasurementBiasModel bias;
  CameraMount mount;
  AssociationOptions association;
  // Innovation gate: a measurement whose squared Mahalanobis innovation
  // exceeds the chi-square quantile of this probability (dof: 2 for a tape,
  // 3 for a pattern fix) is an outlier.
  double gate_probability = 0.999;
  // The history covers at least this span before the latest odometry tick; a
  // measurement exposed before the history's start is dropped (too_old).
  double history_s = 1.0;
  Timing timing = Timing::retroactive;
};

enum class Outcome {
  accepted,
  pending,        // exposed after the latest odometry tick: applied when odometry passes it
  rejected_gate,  // outside the innovation gate
  unassociated,   // no tape segment could be in view
  too_old,        // exposed before the history's start
  not_ok,         // the estimator's status was not ok
};

// Decisions per measurement kind. A measurement re-applied after an older one
// was inserted before it is re-associated and re-gated; the counts follow its
// latest decision.
struct KindCounters {
  int accepted = 0, pending = 0, rejected_gate = 0, unassociated = 0, too_old = 0, not_ok = 0;
};
struct Counters {
  KindCounters tape, pattern, landmark, height;
  int repropagated_steps = 0;  // odometry steps re-propagated by retroactive corrections
};

class Ekf {
 public:
  // `map` must outlive the filter (nullptr: tape measurements are unassociated).
  Ekf(const EkfOptions& options, const TapeMap* map, double t0_s, const State& x0,
      const Covariance& p0);

  // The initial covariance of the calibration states from the odometry model
  // (pose block left zero).
  static Covariance calibration_prior(const OdometryModel& m);
  // The bias states' stationary variances (MeasurementBiasModel); add it to
  // the initial covariance.
  static Covariance bias_prior(const MeasurementBiasModel& b);

  // Predict with the wheel travel since the previous tick (step.t_s > time()).
  void predict(const OdometryStep& step);

  Outcome update(const TapeMeasurement& m);
  Outcome update(const PatternFix& m);
  // A landmark seen along the tape: associated with the map's landmark of its
  // kind whose predicted distance is nearest in Mahalanobis terms, among
  // those ahead of the camera within the association's view radius.
  Outcome update(const LandmarkMeasurement& m);
  // A measured ceiling height above the camera: observes the ceiling scale
  // (and, when measured against the odometry, the wheels' scale errors).
  Outcome update(const CeilingHeight& m);
  // The ceiling height above the camera the filter believes, for the height
  // `used_m` the vision measured with: used / (1 + kappa), and its sigma.
  double ceiling_height(double used_m) const;
  double ceiling_height_sigma(double used_m) const;

  double time() const { return history_.back().t_s; }
  const State& state() const { return history_.back().x; }
  const Covariance& covariance() const { return history_.back().p; }
  Pose2 pose() const;
  const Counters& counters() const { return counters_; }
  std::size_t history_size() const { return history_.size(); }

  // Camera pose (x, y, yaw) of a robot state through the mount, and its
  // Jacobian d(camera) / d(state).
  Pose2 camera_pose(const State& x) const;
  Eigen::Matrix<double, 3, state::size> camera_jacobian(const State& x) const;

  // One prediction step of the model (mean and covariance, in place); public
  // for the Jacobian test.
  void propagate(State& x, Covariance& p, const OdometryStep& step) const;

  // Normalised estimation error squared against a true state (yaw wrapped):
  // the pose and calibration states (the biases have no truth to compare
  // with), and the pose block alone.
  double nees(const State& truth) const;
  double pose_nees(const Pose2& truth) const;

 private:
  // One of the two kinds (a tagged pair: std::variant trips GCC 12's
  // maybe-uninitialized analysis in the sorting of the pending list).
  struct Measurement {
    enum class Kind { tape, pattern, landmark, height } kind = Kind::tape;
    TapeMeasurement tape;
    PatternFix pattern;
    LandmarkMeasurement landmark;
    CeilingHeight height;
    const MeasurementTime& time() const {
      return kind == Kind::tape       ? tape.time
             : kind == Kind::pattern  ? pattern.time
             : kind == Kind::landmark ? landmark.time
                                      : height.time;
    }
    MeasurementStatus status() const {
      return kind == Kind::tape       ? tape.status
             : kind == Kind::pattern  ? pattern.status
             : kind == Kind::landmark ? landmark.status
                                      : height.status;
    }
    double exposure_s() const { return time().exposure_s; }
    bool ok() const { return status() == MeasurementStatus::ok; }
  };
  struct Stored {
    Measurement m;
    Outcome outcome = Outcome::accepted;
  };
  struct Entry {
    double t_s = 0.0;
    OdometryStep step;  // the wheel travel from the previous entry to this one
    State x = State::Zero();
    Covariance p = Covariance::Zero();
    std::vector<Stored> measurements;  // applied here, after the step, in order
  };

  Outcome submit(const Measurement& m);
  Outcome correct(State& x, Covariance& p, const Measurement& m) const;
  Outcome correct_tape(State& x, Covariance& p, const TapeMeasurement& m) const;
  Outcome correct_pattern(State& x, Covariance& p, const PatternFix& m) const;
  Outcome correct_landmark(State& x, Covariance& p, const LandmarkMeasurement& m) const;
  Outcome correct_height(State& x, Covariance& p, const CeilingHeight& m) const;
  std::size_t entry_at(double t_s);  // index of the entry at t_s, splitting a step
  void repropagate_after(std::size_t k);
  void count(const Measurement& m, Outcome o, int delta);
  void apply_pending();

  EkfOptions opt_;
  const TapeMap* map_;
  double gate_tape_, gate_pattern_, gate_landmark_;
  std::deque<Entry> history_;
  std::vector<Stored> pending_;
  Counters counters_;
};

}  // namespace ceilnav::nav
