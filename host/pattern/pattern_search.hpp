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

#include <vector>

namespace ceilnav::host::pattern {

// Seed 003 §V: "the search be performed in a helical motion, by varying the
// horizontal and vertical angles independently in a sinusoidal fashion with
// linear increases in amplitude", the amplitudes' growth per 360 deg obeying
// the scan rule (eq. 33-37). The pan/tilt mount turns the camera about the
// world's vertical (pan, CCW seen from above) and then about its own x axis
// (tilt, up positive). docs/pattern.md, "Helical search".
struct HelicalParams {
  double hfov_rad = 0.0, vfov_rad = 0.0;   // the camera's fields of view
  double video_rate_hz = 30.0;             // rho_v
  double pattern_half_width_m = 0.59;      // w (eq. 34 with w for R)
  double d_min_m = 1.0;                    // nearest distance of the pattern
  double robot_speed_mps = 0.0;            // v_max (eq. 36)
  double pan0_rad = 0.0, tilt0_rad = 0.0;  // where the scan starts (the expected direction)
  double tilt_range_rad = 0.0;             // the pattern lies within tilt0 +- this
  double max_abs_tilt_rad = 1.4;           // the mount's limit
  double fraction = 0.7;                   // pitch and step in footprints (kHelixFraction)
};
struct PanTilt {
  double pan_rad = 0.0, tilt_rad = 0.0;
};
// The pan/tilt of every frame of the scan, one per video frame, from
// (pan0, tilt0) outward until every direction with |tilt - tilt0| <=
// tilt_range (all pans) has the whole pattern (its angle phi_0 = eq. 34 plus
// the motion phi_m = eq. 36) inside some frame. pan(phi) = pan0 + a_p(phi)
// cos phi, tilt(phi) = tilt0 + a_t(phi) sin phi, a = pitch phi / 2 pi;
// per axis the pitch per turn and the frame-to-frame step, in units of the
// axis's free field F = fov - phi_0 - phi_m, are both kHelixFraction =
// 0.7 < 1/sqrt(2) (the 2-D condition that replaces the seed's 1-D rule,
// docs/seed_errata.md); a_t stops at tilt_range. Empty when F <= 0 on
// either axis or the tilt range exceeds the mount.
inline constexpr double kHelixFraction = 0.7;  // HelicalParams::fraction's default
std::vector<PanTilt> helical_scan(const HelicalParams& p);

// Whether the camera at `at` holds the whole cone of half-angle r_rad about
// the direction (pan, tilt) inside its field of view (exact: the cone's axis
// at angular distance >= r from each of the four edge planes).
bool cone_in_view(const PanTilt& at, double hfov_rad, double vfov_rad, const PanTilt& direction,
                  double r_rad);

// Eq. 15, the shadow's (side wall's) width in the image along the minor
// axis, exact in the plane of the axis and the camera (pinhole, optical axis
// through the disc centre), in pixels for focal length f_px: the side wall
// of depth T at radius R' = R + rim shows from R' to R' + (s - R') T / (h +
// T) on the face plane, s = D sin theta, h = D cos theta; 0 when s <= R'.
// The seed's t = T f sin theta / D is its limit for R' << D sin theta.
double shadow_width_px(double thickness_m, double outer_radius_m, double f_px, double d_m,
                       double theta_rad);
// Eq. 16: the least thickness T for which the shadow is n_px wide at D_max
// and theta = delta_theta (shadow_width_px solved for T); +inf when no
// thickness gives it (D_max sin(delta_theta) <= R' or more than f tan
// theta's limit).
double min_thickness_m(double n_px, double outer_radius_m, double f_px, double d_max_m,
                       double delta_theta_rad);

}  // namespace ceilnav::host::pattern
