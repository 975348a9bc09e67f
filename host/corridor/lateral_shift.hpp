// Seed 002 section 4.2 (eq. 21-25): the lateral shift of the vehicle from
// the learnt path, by matching the current image's axis lines to the model's.
// docs/corridor.md, "Lateral shift".
//
// Our Delta-y is the seed's Delta-x: the camera's shift perpendicular to the
// corridor axis since the learnt path, POSITIVE TO THE LEFT (+Y, as the tape
// offset of BRIEF section 5).
//
// Derivation in our frames (replaces eq. 21-25). An axis line at lateral
// offset dy and height h above the camera lies in the plane of world normal
// (0, h, -dy); its image l gives that plane back as n_w = R^T K^T l, so
// q = dy / h = -n_w.z / n_w.y (corridor_model.hpp, M1). Between the model
// (camera at y0, pan phi0) and now (y1 = y0 + Delta-y, pan phi1 = phi0 +
// Delta-phi), the line is the same (y_L, z_L), the camera height the same:
//   q0 = (y_L - y0) / h,  q1 = (y_L - y1) / h   =>   Delta-y = h (q0 - q1).   (S1)
// The rotations are undone exactly in n_w (eq. 21's T_-psi T_-theta T_-dphi
// T_-phi0 ... T_phi0 T_theta T_psi chain), and the translation is the one
// unknown. The seed's eq. 25 instead keeps one image point of the current
// line and its depth z'_1 as an unknown scale: for a point of depth z on the
// line, z and h are tied by the line's geometry, so "z'_1 treated as a
// scalar" makes its Delta-x proportional to an unknown (its experiments
// print Delta-x = -3120 .. -1870 "with z'_1 = -10000", not centimetres).
// S1 names the scale: h, the line's height above the camera (the ceiling
// height minus the camera height for ceiling lines), stored in the model.
//
// Error propagation: d Delta-y / d theta1 = -h dq1/dtheta1 and the same for
// rho1 (inclination_gradient, the chain rule through M1). Closed form for a
// camera of tilt tau, pan 0, swing 0, fx = fy = f, principal point (cx, cy),
// to first order in the line's miss of the vanishing point (n_w.x ~ 0):
//   n_w = (s c_y' + c c_z', -c_x', -c c_y' + s c_z'), c = cos tau, s = sin tau,
//   (c_x', c_y', c_z') = K^T l = (f cos t, f sin t, cx cos t + cy sin t - rho),
//   q = (s (cx cos t + cy sin t - rho) - c f sin t) / (f cos t),
//   d Delta-y / d rho   =  h s / (f cos t)                                 (S2)
//   d Delta-y / d theta = -h [(s (cy cos t - cx sin t) - c f cos t) / (f cos t) + q tan t]
// On the line (through the vanishing point) q = -tan t / c: a rotation of the
// line about the vanishing point moves Delta-y by h / (c cos^2 t) per
// radian (2.2 m/rad, 3.8 mm per 0.1 deg for h = 1.8 m, tau = 35 deg); a
// theta error at fixed rho turns it about the foot of its normal from pixel
// (0, 0) instead, and costs h (c - s cy / f) at t = 0: 1.7 mm per 0.1 deg
// for f = 500 px, cy = 240 px; a rho error costs h s / f = 2 mm per px.
// All matched lines are combined, weighted by 1 / sigma^2 (seed step 9 uses
// the strongest alone): about 1 / sqrt(lines) of one line's error.
#pragma once

#include <optional>
#include <vector>

#include "host/corridor/corridor_model.hpp"

namespace ceilnav::host::corridor {

struct ShiftOptions {
  // Line measurement noise (a Hough peak's): the weights and sigmas.
  double sigma_theta_rad = 0.1 * 3.14159265358979323846 / 180.0;
  double sigma_rho_px = 0.5;
  // A current line matches a model line when its shift is within this of
  // the consensus shift: well above a line's error (mm from the line noise,
  // ~1 cm from the learnt path's wander) and well below half the smallest
  // spacing of ceiling lines (0.15 m between a lamp edge and a seam in the
  // default corridor), or shifts between two lines gather false matches.
  double match_tolerance_m = 0.04;
  // A prior shift (the predicted one, when tracking) and its standard
  // deviation: a proposal s scores (matched lines) - ((s - prior) /
  // prior_sigma_m)^2 / 2, the log-likelihood of its matches (one unit per
  // line: a line the proposal explains) plus the Gaussian prior's; only
  // proposals within prior_gate_m are considered. nullopt: none; the most
  // matched lines win, ties to the smallest residual, then the shift nearest
  // 0 (the learnt path). The ceiling's lines repeat (seams every 0.6 m, lamp
  // edges 0.15 m from seams in the default corridor): a shift by such a
  // step explains some lines as well as the true one, and the prior is what
  // tells them apart.
  std::optional<double> prior_m;
  double prior_sigma_m = 0.05;
  double prior_gate_m = 0.3;
};

// One current line matched to one model line.
struct LineShift {
  int line = -1;                 // index into the current lines
  int model_line = -1;           // index into model.lines
  double shift_m = 0.0;          // S1
  double sigma_m = 0.0;          // from the line's noise (options)
  double d_shift_d_theta = 0.0;  // m / rad
  double d_shift_d_rho = 0.0;    // m / px
  double strength = 0.0;
};

// S1 for one current line and one model line (the seed's eq. 25 for its
// step 9). nullopt when the current line's plane is horizontal.
std::optional<LineShift> line_shift(const ImageLine& line, double pan_rad,
                                    const CorridorModel& model, int model_line,
                                    const ShiftOptions& options = {});

struct LateralShift {
  bool valid = false;
  double shift_m = 0.0;  // weighted mean of the matches (1 / sigma^2)
  double sigma_m = 0.0;  // its standard deviation (from the lines' noise)
  // Seed step 9: the shift from the strongest matched line alone.
  double strongest_shift_m = 0.0;
  double strongest_sigma_m = 0.0;
  std::vector<LineShift> matches;
};

// Matches the current lines (at pan `pan_rad`, from the vanishing line) to
// the model lines and combines them. Matching (the seed matches by rank,
// which breaks when a line is missing): every pair (current i, model j)
// proposes Delta-y_ij = h_j (q_j - q_i); the pairs that agree with a
// proposal (one-to-one, within match_tolerance_m) are its matches, and the
// proposal of the best score (ShiftOptions::prior_m) wins.
LateralShift lateral_shift(const std::vector<ImageLine>& lines, double pan_rad,
                           const CorridorModel& model, const ShiftOptions& options = {});

}  // namespace ceilnav::host::corridor
