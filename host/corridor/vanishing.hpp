// Vanishing points of the corridor's axis and cross directions from image
// lines, the vanishing line of the ceiling, and the camera's pan (seed 002
// section 3, eq. 7-16), in ceilnav's frames. docs/corridor.md, "Lines,
// vanishing points and pan"; the seed's errors in docs/seed_errata.md.
//
// Frames (golden/corridor/corridor.hpp, BRIEF section 5): world X along the
// corridor axis, Y left, Z up; the camera's pan phi about +Z from +X, tilt
// theta of the optical axis up from the horizontal, swing psi about the
// optical axis; R(phi, theta, psi) = golden::world_to_camera_rotation, camera
// axes x right, y down, z forward. Its rows at psi = 0 are
//   right   = ( sin phi,            -cos phi,            0          )
//   down    = ( sin theta cos phi,   sin theta sin phi,  -cos theta  )
//   forward = ( cos theta cos phi,   cos theta sin phi,   sin theta  )
// and the swing multiplies from the left by [c s 0; -s c 0; 0 0 1] (psi).
// The seed's (x, y) image axes are ours (u - cx, cy - v) for the same
// phi, theta, psi; its x (across) and z (axis) directions are our Y and X.
#pragma once

#include <Eigen/Core>
#include <numbers>
#include <vector>

#include "common/camera_config.hpp"
#include "host/corridor/corridor_types.hpp"

namespace ceilnav::host::corridor {

// eq. 11 (seed: vp_z, the axis direction) in our frames: the vanishing
// point of +X on the undistorted image,
//   u = cx + fx (cos psi sin phi + sin psi sin theta cos phi) / (cos theta cos phi)
//   v = cy + fy (cos psi sin theta cos phi - sin psi sin phi) / (cos theta cos phi)
// (R (1, 0, 0) = (sin phi, sin theta cos phi, cos theta cos phi) before the
// swing). Not finite at phi = +-90 deg.
ImagePoint axis_vanishing_point(const CameraConfig& camera, double pan_rad, const CameraMount& m);
// eq. 10 (seed: vp_x, across the corridor) in our frames: +Y,
//   u = cx + fx (sin psi sin theta sin phi - cos psi cos phi) / (cos theta sin phi)
//   v = cy + fy (sin psi cos phi + cos psi sin theta sin phi) / (cos theta sin phi)
// (R (0, 1, 0) = (-cos phi, sin theta sin phi, cos theta sin phi)). At infinity
// for phi = 0.
ImagePoint cross_vanishing_point(const CameraConfig& camera, double pan_rad, const CameraMount& m);

// A direction of the image (homogeneous normalised point P = K^-1 (u, v, 1)
// or a point at infinity) seen by a camera with the mount's tilt and swing:
// w = R(0, theta, psi)^T P. Since R(phi, theta, psi) = R(0, theta, psi)
// Rz(phi)^T (Rz: counter-clockwise about +Z), w is parallel to Rz(phi)^T D
// for the direction D whose vanishing point P is:
//   axis  D = X: w ~ ( cos phi, -sin phi, 0):  phi = atan2(-w_y, w_x)
//   cross D = Y: w ~ ( sin phi,  cos phi, 0):  phi = atan2( w_x, w_y)
// (mod 180 deg, the sign of P being free). These invert eq. 11 and eq. 10;
// with the point's normalised (x, y): tan phi = cos theta (cos psi x -
// sin psi y) for the axis (the single-point pan of section 3.3) and tan phi
// = -1 / (cos theta (cos psi x - sin psi y)) for the cross direction.
// elevation: the angle of w above the horizontal plane (0 for the
// vanishing point of any horizontal direction: the point lies on the
// horizon, the vanishing line of the ceiling).
struct Direction {
  double pan_rad = 0.0;  // in (-90, 90] deg
  double elevation_rad = 0.0;
};
Direction axis_pan_of(const Eigen::Vector3d& normalised_point, const CameraMount& m);
Direction cross_pan_of(const Eigen::Vector3d& normalised_point, const CameraMount& m);

// eq. 7, 12-15 in our frames: the vanishing line's vector d = p_axis -
// p_cross (normalised coordinates) is
//   d = (tan phi + cot phi) / cos theta (cos psi, -sin psi),
// whose direction is the horizon's, the same for every pan: the pan is in
// its length. Projected on (cos psi, -sin psi) (eq. 14 and 15 together,
// weighted by cos^2 psi and sin^2 psi), s = cos theta (cos psi d_x - sin psi
// d_y) = tan phi + cot phi = 2 / sin 2 phi, so tan phi is a root of t^2 - s
// t + 1 = 0: t = (s +- sqrt(s^2 - 4)) / 2 (eq. 14), i.e. phi1 = asin(2 / s)
// / 2 and phi2 = +-90 deg - phi1. Computed as 1 / s from the homogeneous
// points (finite at s = infinity, phi = 0). roots[0] is the small one
// (|phi| <= 45 deg); `chosen` the root nearest `predicted_pan_rad`. |s| < 2
// (no real root, noise) clamps to +-45 deg and sets clamped.
struct VanishingLinePan {
  double roots[2] = {0.0, 0.0};
  double chosen = 0.0;
  bool clamped = false;
};
VanishingLinePan pan_from_vanishing_line(const Eigen::Vector3d& axis_normalised,
                                         const Eigen::Vector3d& cross_normalised,
                                         const CameraMount& m, double predicted_pan_rad);

// eq. 16: the vehicle's heading relative to the corridor, Delta phi = phi -
// phi_CA.
inline double vehicle_heading(double camera_pan_rad, const CameraMount& m) {
  return camera_pan_rad - m.pan_on_vehicle_rad;
}

enum class PanSource {
  axis_point,      // the axis vanishing point alone (eq. 11 inverted): default, measured better
  vanishing_line,  // the two points (eq. 7, 14-15), the axis point when the cross one is missing
};

struct VanishingParams {
  // phi_r of section 3.3: the window is the pans predicted +- this.
  double pan_window_rad = 10.0 * std::numbers::pi / 180.0;
  // The window's other side: a candidate's elevation (its angle from the
  // predicted horizon) within this (the seed's rectangle has no height at
  // swing 0; errata).
  double horizon_window_rad = 2.0 * std::numbers::pi / 180.0;
  // Angles at the camera; x f = pixels near the image centre (f = 500 px:
  // 5 px and 3 px). A line supports the point when its plane passes within
  // inlier_rad of the point's ray after the re-weighting.
  double inlier_rad = 0.01;
  int min_axis_lines = 4;
  int min_cross_lines = 3;
  // The inliers' share of the strength of all lines given: a corridor's axis
  // lines are most of what the horizontal-gradient Hough sees (>= 0.79 on
  // every render of the accuracy sweeps; <= 0.55 where the real-image corpus
  // lines up 3 or 4 lines by chance).
  double min_axis_support = 0.65;
  double min_cross_support = 0.0;
  // The strength-weighted RMS of the inliers' distances must stay below this.
  double max_residual_rad = 0.006;
  PanSource source = PanSource::axis_point;
};

enum class PanStatus {
  ok,         // both vanishing points found (the vanishing line exists)
  one_point,  // only the axis point, or only the cross point, found
  not_found,  // too few lines, no supported point in a window
};
const char* to_string(PanStatus s);

struct VanishingEstimate {
  bool found = false;
  Eigen::Vector3d normalised{0.0, 0.0, 0.0};  // unit homogeneous K^-1 p
  ImagePoint point;                           // on the undistorted image
  std::vector<int> inliers;                   // indices into the lines
  double residual_rad = 0.0;                  // weighted RMS angular distance
  double support = 0.0;                       // the inliers' share of all lines' strength
  Direction direction;
};

struct PanEstimate {
  PanStatus status = PanStatus::not_found;
  double pan_rad = 0.0;        // the camera's pan phi (valid unless not_found)
  double heading_rad = 0.0;    // eq. 16
  double axis_pan_rad = 0.0;   // from the axis point (when found)
  double cross_pan_rad = 0.0;  // from the cross point (when found)
  double line_pan_rad = 0.0;   // from the vanishing line (status ok)
  VanishingLinePan line;       // its two roots
  VanishingEstimate axis, cross;
};

// The robust estimate of one vanishing point: all pairwise intersections
// (homogeneous, normalised coordinates), the lines of those inside the
// window (pan within predicted +- pan_window, elevation within
// horizon_window) as candidates, then the point nearest them (the smallest
// eigenvector of sum w l l^T over unit plane normals l, w the strength:
// angular least squares, finite or not), re-weighted (Tukey, c = 3
// inlier_rad) four times; found when at least min_*_lines inliers remain
// with min_*_support of the strength, their weighted RMS is below
// max_residual_rad and the point lies in the window.
VanishingEstimate find_vanishing_point(const std::vector<ImageLine>& lines,
                                       const CameraConfig& camera, const CameraMount& m,
                                       bool axis_direction, double predicted_pan_rad,
                                       const VanishingParams& params);

// Both points, the status and the pan (section 3.3): lines on the
// undistorted image; predicted_pan_rad the camera's pan expected (the last
// estimate, or phi_CA on a straight course).
PanEstimate estimate_pan(const std::vector<ImageLine>& lines, const CameraConfig& camera,
                         const CameraMount& m, double predicted_pan_rad,
                         const VanishingParams& params = {});

}  // namespace ceilnav::host::corridor
