#include "nav/ekf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "nav/chi_square.hpp"

namespace ceilnav::nav {
namespace {

// Two times closer than this are the same instant (ticks and frames are
// integer multiples of different periods; their sums differ by rounding).
constexpr double same_time_s = 1e-9;

// sinc(h) = sin(h)/h and its derivative (h cos h - sin h)/h^2, with series
// below |h| = 1e-4 (as advance() does).
double sinc(double h) {
  return std::abs(h) < 1e-4 ? 1.0 - h * h / 6.0 : std::sin(h) / h;
}
double sinc_derivative(double h) {
  return std::abs(h) < 1e-4 ? -h / 3.0 + h * h * h / 30.0
                            : (h * std::cos(h) - std::sin(h)) / (h * h);
}

// Kalman update with the Joseph form (stays symmetric positive definite).
template <int M>
void kalman_update(State& x, Covariance& p, const Eigen::Matrix<double, M, state::size>& h,
                   const Eigen::Matrix<double, M, 1>& innovation,
                   const Eigen::Matrix<double, M, M>& s, const Eigen::Matrix<double, M, M>& r) {
  Eigen::Matrix<double, state::size, M> k;  // P H^T S^-1 (S, P symmetric)
  if constexpr (M == 1) {
    k = (h * p).transpose() / s(0, 0);
  } else {
    k = s.ldlt().solve(h * p).transpose();
  }
  x += k * innovation;
  x(state::yaw) = wrap_angle(x(state::yaw));
  const Covariance a = Covariance::Identity() - k * h;
  p = a * p * a.transpose() + k * r * k.transpose();
  p = 0.5 * (p + p.transpose());
}

}  // namespace

Ekf::Ekf(const EkfOptions& options, const TapeMap* map, double t0_s, const State& x0,
         const Covariance& p0)
    : opt_(options),
      map_(map),
      gate_tape_(chi_square_quantile(options.gate_probability, 2)),
      gate_pattern_(chi_square_quantile(options.gate_probability, 3)),
      gate_landmark_(chi_square_quantile(options.gate_probability, 1)) {
  if (!(options.odometry.wheel_base_m > 0.0)) throw std::invalid_argument("wheel base <= 0");
  Entry e;
  e.t_s = t0_s;
  e.step.t_s = t0_s;
  e.x = x0;
  e.x(state::yaw) = wrap_angle(e.x(state::yaw));
  e.p = p0;
  history_.push_back(std::move(e));
}

Covariance Ekf::calibration_prior(const OdometryModel& m) {
  Covariance p = Covariance::Zero();
  p(state::left_scale, state::left_scale) = m.wheel_scale_sigma * m.wheel_scale_sigma;
  p(state::right_scale, state::right_scale) = m.wheel_scale_sigma * m.wheel_scale_sigma;
  p(state::yaw_scale, state::yaw_scale) = m.yaw_scale_sigma * m.yaw_scale_sigma;
  return p;
}

Covariance Ekf::bias_prior(const MeasurementBiasModel& b) {
  Covariance p = Covariance::Zero();
  p(state::tape_yaw_bias, state::tape_yaw_bias) = b.tape_yaw_sigma_rad * b.tape_yaw_sigma_rad;
  p(state::tape_offset_bias, state::tape_offset_bias) =
      b.tape_offset_sigma_m * b.tape_offset_sigma_m;
  p(state::landmark_bias, state::landmark_bias) = b.landmark_sigma_m * b.landmark_sigma_m;
  p(state::ceiling_scale, state::ceiling_scale) = b.ceiling_scale_sigma * b.ceiling_scale_sigma;
  return p;
}

void Ekf::propagate(State& x, Covariance& p, const OdometryStep& step) const {
  const OdometryModel& m = opt_.odometry;
  const double b = m.wheel_base_m;
  const double l = step.left_m, r = step.right_m;
  const double el = x(state::left_scale), er = x(state::right_scale), ew = x(state::yaw_scale);
  const double lt = (1.0 + el) * l, rt = (1.0 + er) * r;
  const double ds = 0.5 * (lt + rt);
  const double w = (rt - lt) / b;
  const double dpsi = (1.0 + ew) * w;

  // Pose' = advance(pose, ds, dpsi): x' = x + ds sinc(h) cos(psi + h), h = dpsi/2.
  const double psi = x(state::yaw);
  const double h = 0.5 * dpsi, sh = sinc(h), dsh = sinc_derivative(h);
  const double th = psi + h, c = std::cos(th), s = std::sin(th);
  // d(x', y', psi') / d(psi, ds, dpsi).
  Eigen::Matrix3d dpose = Eigen::Matrix3d::Zero();
  dpose(0, 0) = -ds * sh * s;
  dpose(1, 0) = ds * sh * c;
  dpose(2, 0) = 1.0;
  dpose(0, 1) = sh * c;
  dpose(1, 1) = sh * s;
  dpose(0, 2) = ds * (0.5 * dsh * c - 0.5 * sh * s);
  dpose(1, 2) = ds * (0.5 * dsh * s + 0.5 * sh * c);
  dpose(2, 2) = 1.0;
  // d(ds, dpsi) / d(e_l, e_r, e_w) and d(ds, dpsi) / d(w_l, w_r, w_psi).
  Eigen::Matrix<double, 2, 3> dmotion_de, dmotion_dw;
  dmotion_de << 0.5 * l, 0.5 * r, 0.0, -(1.0 + ew) * l / b, (1.0 + ew) * r / b, w;
  dmotion_dw << 0.5, 0.5, 0.0, -(1.0 + ew) / b, (1.0 + ew) / b, 1.0;

  Covariance f = Covariance::Identity();
  f.block<3, 1>(0, state::yaw) = dpose.col(0);
  f.block<3, 3>(0, state::left_scale) = dpose.rightCols<2>() * dmotion_de;
  Eigen::Matrix<double, state::size, 3> g = Eigen::Matrix<double, state::size, 3>::Zero();
  g.topRows<3>() = dpose.rightCols<2>() * dmotion_dw;
  const Eigen::Vector3d q(m.wheel_var_per_m * std::abs(l), m.wheel_var_per_m * std::abs(r),
                          m.yaw_var_per_rad * std::abs(r - l) / b);

  // The bias states decay over the distance the view moves, from the wheels'
  // readings (so that F has no terms in the scale states): phi = exp(-D/len),
  // with the driving noise sigma^2 (1 - phi^2) that keeps their variance
  // stationary (and splits exactly when a step is split).
  const MeasurementBiasModel& bm = opt_.bias;
  const double view_moved = 0.5 * std::abs(l + r) + bm.turn_length_m_per_rad * std::abs(r - l) / b;
  constexpr int nb = state::biases;
  Eigen::Matrix<double, nb, 1> bias_var;
  bias_var << bm.tape_yaw_sigma_rad * bm.tape_yaw_sigma_rad,
      bm.tape_offset_sigma_m * bm.tape_offset_sigma_m, bm.landmark_sigma_m * bm.landmark_sigma_m,
      bm.ceiling_scale_sigma * bm.ceiling_scale_sigma;
  const double lengths[nb] = {bm.tape_length_m, bm.tape_length_m, bm.landmark_length_m,
                              bm.ceiling_length_m};
  Eigen::Matrix<double, nb, 1> bias_q;
  for (int i = 0; i < nb; ++i) {
    const double phi = std::exp(-view_moved / lengths[i]);
    f(state::tape_yaw_bias + i, state::tape_yaw_bias + i) = phi;
    bias_q(i) = bias_var(i) * (1.0 - phi * phi);
  }

  const Pose2 next = advance({x(state::x), x(state::y), psi}, {ds, dpsi});
  x(state::x) = next.x_m;
  x(state::y) = next.y_m;
  x(state::yaw) = next.yaw_rad;
  x.tail<nb>() = f.bottomRightCorner<nb, nb>().diagonal().cwiseProduct(x.tail<nb>());
  p = f * p * f.transpose() + g * q.asDiagonal() * g.transpose();
  p.bottomRightCorner<nb, nb>() += bias_q.asDiagonal();
  p = 0.5 * (p + p.transpose());
}

Pose2 Ekf::camera_pose(const State& x) const {
  const double c = std::cos(x(state::yaw)), s = std::sin(x(state::yaw));
  const CameraMount& m = opt_.mount;
  return {x(state::x) + c * m.forward_m - s * m.left_m,
          x(state::y) + s * m.forward_m + c * m.left_m, wrap_angle(x(state::yaw) + m.yaw_rad)};
}

Eigen::Matrix<double, 3, state::size> Ekf::camera_jacobian(const State& x) const {
  const double c = std::cos(x(state::yaw)), s = std::sin(x(state::yaw));
  const CameraMount& m = opt_.mount;
  Eigen::Matrix<double, 3, state::size> j = Eigen::Matrix<double, 3, state::size>::Zero();
  j(0, state::x) = 1.0;
  j(1, state::y) = 1.0;
  j(0, state::yaw) = -s * m.forward_m - c * m.left_m;
  j(1, state::yaw) = c * m.forward_m - s * m.left_m;
  j(2, state::yaw) = 1.0;
  return j;
}

Pose2 Ekf::pose() const {
  const State& x = state();
  return {x(state::x), x(state::y), x(state::yaw)};
}

double Ekf::nees(const State& truth) const {
  constexpr int n = state::tape_yaw_bias;  // the pose and the odometry's calibration
  Eigen::Matrix<double, n, 1> e = (state() - truth).head<n>();
  e(state::yaw) = wrap_angle(e(state::yaw));
  return e.dot(covariance().topLeftCorner<n, n>().ldlt().solve(e));
}

double Ekf::pose_nees(const Pose2& truth) const {
  const State& x = state();
  const Eigen::Vector3d e(x(state::x) - truth.x_m, x(state::y) - truth.y_m,
                          wrap_angle(x(state::yaw) - truth.yaw_rad));
  return e.dot(covariance().topLeftCorner<3, 3>().ldlt().solve(e));
}

Outcome Ekf::correct_tape(State& x, Covariance& p, const TapeMeasurement& m) const {
  if (map_ == nullptr) return Outcome::unassociated;
  const Eigen::Matrix<double, 3, state::size> jc = camera_jacobian(x);
  const Eigen::Matrix3d pc = jc * p * jc.transpose();
  // z = h(camera) + b + noise: the segment is chosen for the measurement less
  // the biases' estimate, their variance added to its own; the gate and the
  // update then use the full Jacobian (the biases' covariance with the pose).
  // The offset is (1 + kappa) times the true one (the ceiling scale): the
  // segment is chosen at the true scale, z_off = (1 + kappa) h_off + b_off.
  const double k1 = 1.0 + x(state::ceiling_scale);
  TapeMeasurement unbiased = m;
  unbiased.yaw_rad = wrap_angle(m.yaw_rad - x(state::tape_yaw_bias));
  unbiased.offset_m = (m.offset_m - x(state::tape_offset_bias)) / k1;
  unbiased.covariance += p.block<2, 2>(state::tape_yaw_bias, state::tape_yaw_bias);
  unbiased.covariance.row(1) /= k1;
  unbiased.covariance.col(1) /= k1;
  const std::optional<Association> a =
      map_->associate(unbiased, camera_pose(x), pc, opt_.association);
  if (!a) return Outcome::unassociated;
  Eigen::Matrix<double, 2, state::size> h = a->prediction.jacobian * jc;
  h.row(1) *= k1;
  h(1, state::ceiling_scale) = a->prediction.h(1);
  h(0, state::tape_yaw_bias) = 1.0;
  h(1, state::tape_offset_bias) = 1.0;
  Eigen::Vector2d nu = tape_innovation(unbiased, a->prediction);
  nu(1) *= k1;  // m_off - b_off - (1 + kappa) h_off
  const Eigen::Matrix2d s = h * p * h.transpose() + m.covariance;
  if (nu.dot(s.ldlt().solve(nu)) > gate_tape_) return Outcome::rejected_gate;
  kalman_update<2>(x, p, h, nu, s, m.covariance);
  return Outcome::accepted;
}

Outcome Ekf::correct_pattern(State& x, Covariance& p, const PatternFix& m) const {
  const Eigen::Matrix<double, 3, state::size> h = camera_jacobian(x);
  const Pose2 c = camera_pose(x);
  const Eigen::Vector3d nu(m.x_m - c.x_m, m.y_m - c.y_m, wrap_angle(m.yaw_rad - c.yaw_rad));
  const Eigen::Matrix3d s = h * p * h.transpose() + m.covariance;
  if (nu.dot(s.ldlt().solve(nu)) > gate_pattern_) return Outcome::rejected_gate;
  kalman_update<3>(x, p, h, nu, s, m.covariance);
  return Outcome::accepted;
}

// h = (L - c) . u for the landmark L, the camera's floor position c and the
// tape direction u at L the camera faces (fixed by the map): dh/dc = -u^T,
// dh/dyaw = 0, then through the mount's Jacobian to the state.
Outcome Ekf::correct_landmark(State& x, Covariance& p, const LandmarkMeasurement& m) const {
  if (map_ == nullptr) return Outcome::unassociated;
  const Pose2 c = camera_pose(x);
  const Eigen::Vector2d cam(c.x_m, c.y_m);
  const Eigen::Matrix<double, 3, state::size> jc = camera_jacobian(x);
  double best = std::numeric_limits<double>::infinity();
  Eigen::Matrix<double, 1, state::size> h_best;
  double nu_best = 0.0, s_best = 0.0;
  for (const Landmark& l : map_->landmarks()) {
    if (l.kind != m.kind) continue;
    const std::optional<Eigen::Vector2d> u = map_->along_direction(l.position, c.yaw_rad);
    if (!u) continue;
    const Eigen::Vector2d rel = l.position - cam;
    if (rel.norm() > opt_.association.view_radius_m + 1.0) continue;
    // z = (1 + kappa) (L - c) . u + b + noise.
    const double k1 = 1.0 + x(state::ceiling_scale);
    const double true_distance = rel.dot(*u);
    const double predicted = k1 * true_distance;
    const Eigen::Matrix<double, 1, 3> hc(-u->x(), -u->y(), 0.0);
    Eigen::Matrix<double, 1, state::size> h = k1 * hc * jc;
    h(0, state::ceiling_scale) = true_distance;
    h(0, state::landmark_bias) = 1.0;
    const double s = (h * p * h.transpose())(0, 0) + m.variance_m2;
    const double nu = m.along_m - predicted - x(state::landmark_bias);
    if (nu * nu / s < best) {
      best = nu * nu / s;
      h_best = h;
      nu_best = nu;
      s_best = s;
    }
  }
  if (!std::isfinite(best)) return Outcome::unassociated;
  if (best > gate_landmark_) return Outcome::rejected_gate;
  kalman_update<1>(x, p, h_best, Eigen::Matrix<double, 1, 1>(nu_best),
                   Eigen::Matrix<double, 1, 1>(s_best), Eigen::Matrix<double, 1, 1>(m.variance_m2));
  return Outcome::accepted;
}

// z = used / ((1 + kappa) (1 + e_bar)), e_bar = (e_l + e_r) / 2 against the
// odometry (else e_bar = 0): the ceiling scale's relation to a measured height.
Outcome Ekf::correct_height(State& x, Covariance& p, const CeilingHeight& m) const {
  const double k1 = 1.0 + x(state::ceiling_scale);
  const double e1 =
      m.against_odometry ? 1.0 + 0.5 * (x(state::left_scale) + x(state::right_scale)) : 1.0;
  const double predicted = m.used_m / (k1 * e1);
  Eigen::Matrix<double, 1, state::size> h = Eigen::Matrix<double, 1, state::size>::Zero();
  h(0, state::ceiling_scale) = -predicted / k1;
  if (m.against_odometry) {
    h(0, state::left_scale) = h(0, state::right_scale) = -0.5 * predicted / e1;
  }
  const double r = m.sigma_m * m.sigma_m;
  const double s = (h * p * h.transpose())(0, 0) + r;
  const double nu = m.height_m - predicted;
  if (nu * nu / s > gate_landmark_) return Outcome::rejected_gate;
  kalman_update<1>(x, p, h, Eigen::Matrix<double, 1, 1>(nu), Eigen::Matrix<double, 1, 1>(s),
                   Eigen::Matrix<double, 1, 1>(r));
  return Outcome::accepted;
}

double Ekf::ceiling_height(double used_m) const {
  return used_m / (1.0 + state()(state::ceiling_scale));
}

double Ekf::ceiling_height_sigma(double used_m) const {
  const double k1 = 1.0 + state()(state::ceiling_scale);
  return used_m / (k1 * k1) * std::sqrt(covariance()(state::ceiling_scale, state::ceiling_scale));
}

Outcome Ekf::correct(State& x, Covariance& p, const Measurement& m) const {
  switch (m.kind) {
    case Measurement::Kind::tape:
      return correct_tape(x, p, m.tape);
    case Measurement::Kind::pattern:
      return correct_pattern(x, p, m.pattern);
    case Measurement::Kind::landmark:
      return correct_landmark(x, p, m.landmark);
    case Measurement::Kind::height:
      return correct_height(x, p, m.height);
  }
  return Outcome::not_ok;
}

void Ekf::count(const Measurement& m, Outcome o, int delta) {
  KindCounters& k = m.kind == Measurement::Kind::tape       ? counters_.tape
                    : m.kind == Measurement::Kind::pattern  ? counters_.pattern
                    : m.kind == Measurement::Kind::landmark ? counters_.landmark
                                                            : counters_.height;
  switch (o) {
    case Outcome::accepted:
      k.accepted += delta;
      break;
    case Outcome::pending:
      k.pending += delta;
      break;
    case Outcome::rejected_gate:
      k.rejected_gate += delta;
      break;
    case Outcome::unassociated:
      k.unassociated += delta;
      break;
    case Outcome::too_old:
      k.too_old += delta;
      break;
    case Outcome::not_ok:
      k.not_ok += delta;
      break;
  }
}

std::size_t Ekf::entry_at(double t_s) {
  // First entry at or after t_s (t_s lies within the history).
  std::size_t k = 0;
  while (history_[k].t_s < t_s - same_time_s) ++k;
  if (std::abs(history_[k].t_s - t_s) <= same_time_s) return k;
  // Split the step into history_[k] at t_s: the wheels are taken to turn at a
  // constant rate over the step, so the first part is the fraction f of each
  // wheel's travel (the arc of advance() splits exactly: same curvature).
  Entry& next = history_[k];
  const Entry& prev = history_[k - 1];
  const double f = (t_s - prev.t_s) / (next.t_s - prev.t_s);
  Entry e;
  e.t_s = t_s;
  e.step = {t_s, f * next.step.left_m, f * next.step.right_m};
  next.step.left_m -= e.step.left_m;
  next.step.right_m -= e.step.right_m;
  e.x = prev.x;
  e.p = prev.p;
  propagate(e.x, e.p, e.step);
  history_.insert(history_.begin() + static_cast<std::ptrdiff_t>(k), std::move(e));
  return k;
}

void Ekf::repropagate_after(std::size_t k) {
  for (std::size_t i = k + 1; i < history_.size(); ++i) {
    Entry& e = history_[i];
    e.x = history_[i - 1].x;
    e.p = history_[i - 1].p;
    propagate(e.x, e.p, e.step);
    ++counters_.repropagated_steps;
    for (Stored& s : e.measurements) {
      const Outcome o = correct(e.x, e.p, s.m);
      if (o != s.outcome) {
        count(s.m, s.outcome, -1);
        count(s.m, o, +1);
        s.outcome = o;
      }
    }
  }
}

Outcome Ekf::submit(const Measurement& m) {
  if (!m.ok()) {
    count(m, Outcome::not_ok, +1);
    return Outcome::not_ok;
  }
  const double t = opt_.timing == Timing::at_arrival ? time() : m.exposure_s();
  if (t > time() + same_time_s) {
    pending_.push_back({m, Outcome::pending});
    count(m, Outcome::pending, +1);
    return Outcome::pending;
  }
  if (t < history_.front().t_s - same_time_s) {
    count(m, Outcome::too_old, +1);
    return Outcome::too_old;
  }
  const std::size_t k = entry_at(t);
  Entry& e = history_[k];
  const Outcome o = correct(e.x, e.p, m);
  e.measurements.push_back({m, o});
  count(m, o, +1);
  repropagate_after(k);
  return o;
}

Outcome Ekf::update(const TapeMeasurement& m) {
  Measurement s;
  s.tape = m;
  return submit(s);
}

Outcome Ekf::update(const PatternFix& m) {
  Measurement s;
  s.kind = Measurement::Kind::pattern;
  s.pattern = m;
  return submit(s);
}

Outcome Ekf::update(const LandmarkMeasurement& m) {
  Measurement s;
  s.kind = Measurement::Kind::landmark;
  s.landmark = m;
  return submit(s);
}

Outcome Ekf::update(const CeilingHeight& m) {
  if (m.status == MeasurementStatus::ok &&
      (!std::isfinite(m.height_m) || !(m.sigma_m > 0.0) || !(m.used_m > 0.0))) {
    throw std::invalid_argument("CeilingHeight: needs a finite height, sigma > 0 and used > 0");
  }
  Measurement s;
  s.kind = Measurement::Kind::height;
  s.height = m;
  return submit(s);
}

void Ekf::apply_pending() {
  // Oldest exposure first; a measurement keeps its place among equal times.
  std::stable_sort(pending_.begin(), pending_.end(), [](const Stored& a, const Stored& b) {
    return a.m.exposure_s() < b.m.exposure_s();
  });
  std::vector<Stored> still;
  std::vector<Stored> due;
  for (Stored& s : pending_) {
    const double t = s.m.exposure_s();
    (t > time() + same_time_s ? still : due).push_back(std::move(s));
  }
  pending_ = std::move(still);
  for (const Stored& s : due) {
    count(s.m, Outcome::pending, -1);
    submit(s.m);
  }
}

void Ekf::predict(const OdometryStep& step) {
  if (!(step.t_s > time())) throw std::invalid_argument("odometry step not after the last one");
  Entry e;
  e.t_s = step.t_s;
  e.step = step;
  e.x = state();
  e.p = covariance();
  propagate(e.x, e.p, step);
  history_.push_back(std::move(e));
  if (!pending_.empty()) apply_pending();
  // Keep one entry at or before time() - history_s (the base of any insertion).
  while (history_.size() > 2 && history_[1].t_s <= time() - opt_.history_s) history_.pop_front();
}

}  // namespace ceilnav::nav
