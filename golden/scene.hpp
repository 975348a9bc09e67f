// Ceiling scenes with a known camera pose: the tape layout, the camera pose, the
// ideal projection (equal to cv::projectPoints) and the per-frame truth that the
// accuracy tests compare the host's estimates with. See docs/renderer.md.
//
// World frame (BRIEF §5): X forward along the tape, Y left, Z up; floor Z = 0,
// ceiling Z = ceiling_height_m. Camera centre C = (x_m, y_m, camera_height_m),
// heading yaw counter-clockwise from +X, optical axis pitched up by the pitch of
// the CameraConfig, no roll; OpenCV camera axes (x right, y down, z forward).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/camera_config.hpp"

namespace ceilnav::golden {

// A straight strip on the ceiling between two centre-line end points.
struct TapeSegment {
  double x0_m, y0_m, x1_m, y1_m;
  double width_m;
  double reflectance = 1.0;
  // The height above the floor of the ceiling this strip is on; 0: the
  // CameraConfig's ceiling_height_m (a ceiling with height steps,
  // docs/renderer.md "Height zones").
  double ceiling_height_m = 0.0;
};

struct CeilingScene {
  // tapes[0] is (a piece of) the reference tape along +X; its centre line is
  // y = reference_y_m. Where strips overlap, the brighter one is seen.
  std::vector<TapeSegment> tapes;
  double reference_y_m = 0.0;
};

// Pitch and heights come from the CameraConfig.
struct CameraPose {
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
};

struct FrameTruth {
  double yaw_rad;    // heading relative to the reference tape (+X), as given
  double offset_m;   // camera Y - reference_y_m; positive: camera left of the tape
  double pitch_rad;  // from CameraConfig::camera_pitch_deg
  // Ideal (undistorted) pixel coordinates of the vanishing point of direction
  // +X; NaN when !vp_finite (pitch 90 deg, or +X parallel to the image plane).
  double vp_u_px, vp_v_px;
  bool vp_finite;
  double ceiling_above_camera_m;
};

// Options of corridor_scene. Gaps are [start, end) x-intervals cut out of the
// reference tape.
struct CorridorOptions {
  double reference_y_m = 0.0;
  double x_start_m = -5.0;
  double x_end_m = 60.0;
  std::vector<std::pair<double, double>> gaps_m{{6.0, 6.8}, {15.0, 16.2}, {27.0, 27.5}};
  // T-branch: a strip along Y at x = branch_x_m from the reference centre line
  // to branch_length_m on the right (negative Y) side.
  double branch_x_m = 10.0;
  double branch_length_m = 3.0;
  bool second_tape = false;
  double second_tape_y_m = 2.0;  // absolute Y of the optional parallel tape
};

// A long reference tape along X with gaps, one T-branch and optionally a second
// parallel tape. tapes[0] is the first piece of the reference tape.
CeilingScene corridor_scene(double tape_width_m, const CorridorOptions& options = {});

// One unbroken tape along X (x from -10 m to 100 m) on y = 0, for accuracy tests.
CeilingScene single_tape_scene(double tape_width_m);

// Ceiling lights without any tape (distractors for the tape path): a grid of
// rectangular fixtures, each `length_m` along X by `width_m` along Y, centres
// every `pitch_x_m` along X and `pitch_y_m` along Y over x in [x_min, x_max],
// y in [y_min, y_max], rendered as strips of `reflectance` (bright under the
// flash like a lamp's diffuser; a lamp's own light adds a constant, which the
// threshold does not tell from reflected flash). tapes[0] is a lamp, not a
// reference tape: truth_for has no meaning for this scene.
struct LampGridOptions {
  double length_m = 0.6, width_m = 0.1;
  double pitch_x_m = 1.6, pitch_y_m = 1.2;
  double x_min = -4.0, x_max = 20.0, y_min = -4.0, y_max = 4.0;
  double reflectance = 3.0;
};
CeilingScene lamp_grid_scene(const LampGridOptions& options = {});

// Ceilings without the configured tape that a threshold still sees as bright
// strips: the distractors of the tape evidence tests and survey
// (docs/results.md, "Evidence"). In order: a lamp grid (0.6 x 0.1 m), square
// panels (0.6 m), bare tubes of 1.2 m x 3 cm ("tubes 3 cm", a known false
// accept when they run out of the view), a row of 1.2 x 0.15 m bars end to
// end, 5 cm dashes 0.3 m on / 0.9 m off, and a 10 cm strip (twice the tape).
std::vector<std::pair<std::string, CeilingScene>> distractor_scenes();

double pitch_rad(const host::CameraConfig& camera);
Eigen::Vector3d camera_centre(const host::CameraConfig& camera, const CameraPose& pose);

// World -> camera rotation; its rows are the camera's right, down and forward
// axes in world coordinates:
//   r = (sin psi, -cos psi, 0)
//   d = (sin(pitch) cos psi, sin(pitch) sin psi, -cos(pitch))
//   f = (cos(pitch) cos psi, cos(pitch) sin psi, sin(pitch))
// X_cam = R (X_world - C).
Eigen::Matrix3d world_to_camera_rotation(double yaw_rad, double pitch_rad);
// The same camera rolled about its optical axis by roll_rad: M(roll) R(yaw,
// pitch), M(roll) = [c s 0; -s c 0; 0 0 1]. Positive roll turns the camera's
// x axis toward its y axis, so the image content turns counter-clockwise on
// the screen (v down). roll_rad = 0 gives exactly the two-angle rotation.
Eigen::Matrix3d world_to_camera_rotation(double yaw_rad, double pitch_rad, double roll_rad);

// OpenCV's distortion model (k1, k2, p1, p2, k3) on normalised coordinates.
Eigen::Vector2d distort_normalised(const host::CameraConfig& camera, const Eigen::Vector2d& xy);

// Pixel coordinates of a world point, exactly as cv::projectPoints computes
// them (the skew entry camera_matrix[1] is ignored, as there). nullopt when
// the point is not in front of the camera (camera z <= 0).
std::optional<Eigen::Vector2d> project_point(const host::CameraConfig& camera,
                                             const CameraPose& pose,
                                             const Eigen::Vector3d& world_point,
                                             bool apply_distortion);

// Throws std::invalid_argument when tapes[0] is not along +X on reference_y_m
// or when the ceiling is not above the camera.
FrameTruth truth_for(const host::CameraConfig& camera, const CeilingScene& scene,
                     const CameraPose& pose);

// CSV with a header row: frame,yaw_rad,offset_m,pitch_rad,vp_u_px,vp_v_px,
// vp_finite,ceiling_above_camera_m. Written to "<path>.tmp" and renamed, so a
// failure leaves no partial file; throws std::runtime_error on failure.
void write_truth_csv(const std::string& path,
                     const std::vector<std::pair<std::string, FrameTruth>>& rows);

}  // namespace ceilnav::golden
