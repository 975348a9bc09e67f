// Yaw and lateral offset from the runs of a ceiling tape (seed 000), and the
// zenith mode from image moments. Derivations: docs/host_maths.md.
//
// Frames (BRIEF §5): world X along the tape, Y left, Z up; camera yaw psi CCW
// from X, pitch p up from horizontal, no roll; OpenCV camera axes. World ->
// camera rotation rows
//   r = ( sin psi,        -cos psi,       0     )   (image x, right)
//   d = ( sin p cos psi,   sin p sin psi, -cos p )   (image y, down)
//   f = ( cos p cos psi,   cos p sin psi,  sin p )   (optical axis)
#pragma once

#include <optional>
#include <span>

#include <Eigen/Core>

#include "common/camera_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/status.hpp"

namespace ceilnav::host {

struct TapePoseOptions {
  int min_points = 8;            // centre-line points needed after outlier rejection
  double max_residual_px = 1.5;  // inlier gate on the centre-line residual (x, pixels)
  // A run wider than max_width_factor * (expected tape width at its row, from
  // tape_width_m and the ceiling height) + width_slack_px is not a centre-line
  // point (T-branch, tapes merged near the horizon, glare). <= 0 disables.
  double max_width_factor = 2.0;
  double width_slack_px = 3.0;
  // Candidate lines whose support is within this fraction of the best are tied;
  // the tie goes to the line nearest the principal point.
  double tie_fraction = 0.1;
  double min_row_span_px = 10.0;  // rows spanned by the inliers; shorter is degenerate
  double max_abs_yaw_deg = 80.0;  // beyond: the tape runs along the horizon -> degenerate
  // A fit whose yaw standard error (TapePose::yaw_sigma_rad) exceeds this is
  // too_few_points: a short piece of tape, a few rows of it.
  double max_yaw_sigma_deg = 0.05;
  int refine_iterations = 3;   // gather inliers / refit rounds per candidate
  bool estimate_pitch = true;  // fit the left/right edge lines for pitch_est_rad
  // Weight each run centre by its inverse noise variance sum_w^2 / sum (x - x_c)^2
  // (bright, narrow runs count more); false (default): every run counts the same.
  // The noise-only variance ignores the threshold clipping of dim, narrow far
  // runs, which then get too much weight where their leverage is largest; the
  // accuracy benchmark is better unweighted (docs/results.md).
  bool weighted_fit = false;
};

struct TapePose {
  Status status = Status::no_tape;
  const char* method = "";  // "runs_centre_line" or "zenith_moments"
  double yaw_rad = 0.0;
  double offset_m = 0.0;   // camera Y relative to the tape centre (positive: camera left)
  double pitch_rad = 0.0;  // pitch used (configured)
  bool pitch_est_valid = false;
  double pitch_est_rad = 0.0;  // from the left/right edge lines; biased, see docs
  bool vp_finite = false;
  double vp_u_px = 0.0, vp_v_px = 0.0;  // vanishing point of +X, ideal (undistorted) pixels
  int points_total = 0, points_used = 0;
  double residual_rms_px = 0.0;
  double yaw_sigma_rad = 0.0;                // standard error of the yaw from the inliers' scatter
  Eigen::Vector3d line_norm{0.0, 0.0, 0.0};  // centre line l, l . (x, y, 1) = 0, l1^2 + l2^2 = 1
};

// Yaw and offset from the centre line l (normalised coordinates) of a line on
// the ceiling parallel to world X, `ceiling_above_camera_m` above the camera:
//   tan psi = -(l2 sin p + l3 cos p) / l1,  offset = c cos psi (l2 cos p - l3 sin p) / l1.
// Valid for any pitch in (0, 90]. Returns degenerate (outputs untouched) when
// |psi| would exceed max_abs_yaw_rad or l is not finite.
Status pose_from_centre_line(const Eigen::Vector3d& line, double pitch_rad,
                             double ceiling_above_camera_m, double max_abs_yaw_rad, double& yaw_rad,
                             double& offset_m);

TapePose estimate_tape_pose(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                            const CameraConfig& cfg, const TapePoseOptions& opt = {});

// Zenith mode (seed 000, FIG. 3): the image rotation of the tape band gives yaw,
// the band's centroid line gives the offset. Uses the mask moments (or the grey
// moments), pixel coordinates, no undistortion (moments cannot be undistorted).
// Exact for pitch 90, no distortion, a band that crosses two opposite image
// sides and an infinitely thin tape; error bounds in docs/host_maths.md.
TapePose zenith_pose_from_moments(const stream::MomentResults& m, const CameraModel& cam,
                                  const CameraConfig& cfg, bool use_mask = true);

}  // namespace ceilnav::host
