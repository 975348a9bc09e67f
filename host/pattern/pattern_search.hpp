// Seed 003's scanning rule (eq. 33-37): how fast the camera may pan so that
// the whole pattern appears in at least one frame. Angles in radians, rates in
// radians per second, video rate in frames per second.
#pragma once

namespace ceilnav::host::pattern {

struct ScanParams {
  double fov_rad;                // phi_v: horizontal field of view
  double video_rate_hz;          // rho_v
  double pattern_half_width_m;   // half the pattern's width (the seed uses R, eq. 34)
  double d_min_m;                // nearest distance at which the pattern must be found
  double robot_speed_mps = 0.0;  // v_max (eq. 36)
};

// Eq. 34: the angle the pattern spans at D_min, 2 atan(w / D_min).
double pattern_angle_rad(const ScanParams& p);
// Eq. 36: the angle the pattern moves in one frame when the robot moves at
// v_max perpendicular to it, atan(v_max / (rho_v D_min)).
double motion_angle_rad(const ScanParams& p);
// Eq. 35/37 (corrected, docs/seed_errata.md): the pan per frame may be at most
// phi_v - phi_0 - phi_m, so rho_r,max = (phi_v - phi_0 - phi_m) rho_v. <= 0
// means no pan rate can guarantee a whole view (returns 0).
double max_pan_rate(const ScanParams& p);

}  // namespace ceilnav::host::pattern
