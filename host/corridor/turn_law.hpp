// Seed 002 section 4.3 (eq. 26-28): the wheel turn angle from the heading
// error Delta-phi and the lateral shift Delta-y, and its differential-drive
// equivalent. docs/corridor.md, "Turn law".
//
// Signs (our frames): Delta-phi = current pan - model pan (eq. 16 with the
// camera's mounting pan removed), positive when the vehicle heads to the left
// of the corridor axis; Delta-y positive when it is left of the learnt path
// (lateral_shift.hpp); the turn angle delta positive to the left (CCW).
//
//   delta = f(Delta-phi) + g(Delta-y)                                   (26)
//   f = -c1 Delta-phi               if |c1 Delta-phi| <= Delta-phi_max  (27)
//     = -Delta-phi_max sign(Delta-phi)  otherwise
//   g = -c2 (Delta-y + s), limited to |g| <= shift_turn_max             (28)
// then |delta| <= max_turn (the wheel's limit; the seed has none).
// The limit on g is a deviation: the seed bounds f alone, so far from the
// path g steers the vehicle onto a heading whose f the saturation can no
// longer balance: the damping is gone and the loop overshoots by ~0.4 m
// from 0.6 m (turn_law_test, docs/corridor.md). With |g| <= Delta-phi_max
// the approach heading stays where f is linear (|Delta-phi| <=
// Delta-phi_max / c1).
// Eq. 27 as printed tests c1 Delta-phi <= Delta-phi_max without the absolute
// value, so every negative Delta-phi takes the linear branch unbounded
// (docs/seed_errata.md). s is the offset of the wanted path: the law holds
// Delta-y = -s. With S1's metric Delta-y one c2 and one s serve every model
// line (the seed's c2i, s_i per line absorb its unknown per-line scale).
//
// Gains (derivation, docs/corridor.md "Turn law"): the turn angle is that of
// a bicycle of wheelbase L, curvature kappa = tan(delta) / L (a differential
// drive turns at omega = v kappa). About the path, with e = Delta-y and psi =
// Delta-phi over the travelled distance s: e' = sin psi ~ psi, psi' = kappa
// ~ delta / L = -(c1 psi + c2 e) / L, so
//   e'' + (c1 / L) e' + (c2 / L) e = 0.
// Matching e'' + (2 zeta / Lc) e' + e / Lc^2 = 0 (the tape law of
// nav/guidance.hpp): c1 = 2 zeta L / Lc, c2 = L / Lc^2. In time at speed v the
// natural frequency is v / Lc: the time constant Lc / v.
#pragma once

namespace ceilnav::host::corridor {

struct TurnLaw {
  double c1 = 0.0;                    // rad of turn per rad of heading error
  double heading_turn_max_rad = 0.0;  // Delta-phi_max
  double c2_rad_per_m = 0.0;          // rad of turn per m of shift
  double s_m = 0.0;                   // the path held at Delta-y = -s
  double shift_turn_max_rad = 0.0;    // |g| limit (design: Delta-phi_max)
  double max_turn_rad = 0.0;          // the wheel's limit
  double wheelbase_m = 0.0;           // L of kappa = tan(delta) / L
};

// The design the gains come from.
struct TurnLawDesign {
  // Lc: the distance over which the lateral error decays. 0.6 m: a time
  // constant of 2 s at 0.3 m/s, twenty frame periods at 10 frames/s, so the
  // frame rate and a frame of latency barely touch the loop.
  double convergence_length_m = 0.6;
  double damping = 1.0;  // zeta: critically damped, no overshoot (linear)
  // L: the robot of sim/ (sim::RobotParams::wheel_base_m); any L gives the
  // same curvature law, it only scales delta.
  double wheelbase_m = 0.40;
  // The heading error beyond which a pan is no measurement: the axis'
  // vanishing point leaves the image at the half field of view atan((W/2) /
  // fx) (32.6 deg for 640 px, fx = 500 px); Delta-phi_max = c1 times that.
  double credible_heading_rad = 0.5693;
  // The curvature limit of the guidance (nav::SteeringOptions, 5 / m).
  double max_curvature_per_m = 5.0;
  double s_m = 0.0;
};

TurnLaw design_turn_law(const TurnLawDesign& design);
TurnLaw design_turn_law();  // the default design

double heading_term(double delta_phi_rad, const TurnLaw& law);                  // f, eq. 27
double shift_term(double delta_y_m, const TurnLaw& law);                        // g, eq. 28
double wheel_turn(double delta_phi_rad, double delta_y_m, const TurnLaw& law);  // eq. 26, limited

// The differential-drive command of a turn angle at speed v: omega = v
// tan(delta) / L (rad/s, positive CCW).
double yaw_rate(double turn_rad, double speed_mps, const TurnLaw& law);

}  // namespace ceilnav::host::corridor
