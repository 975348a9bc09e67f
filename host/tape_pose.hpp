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
  // Evidence gates (TapeEvidence; docs/host_maths.md section 4, "Evidence").
  // A run's width is consistent when |measured - predicted| <= width_tolerance
  // * predicted + width_slack_px (predicted: tape_width_m at the ceiling height
  // through the camera model at the run's row and the fitted yaw). Tunable:
  // the threshold cuts a blurred edge anywhere between its foot and its top.
  double width_tolerance = 0.5;
  // Fraction of the sampled inlier runs that must be width-consistent: most
  // rows of a tape show its width (glare, a branch crossing spoil a few).
  double min_width_consistent_fraction = 0.5;
  // Inliers more than max_gap_m apart along the tape (from their rows at the
  // fitted yaw) are separate pieces; only the longest piece and the pieces
  // chained to it by gaps <= max_gap_m carry the line. Tunable: the longest gap
  // the installation has (golden corridor: 1.2 m). <= 0 disables.
  double max_gap_m = 1.5;
  // The carried pieces must cover at least this fraction of the length they
  // span: tape is laid continuously with gaps shorter than its pieces; a row of
  // lamps (pieces with gaps longer than themselves) is not tape.
  double min_coverage = 0.5;
  // Tape visible (sum of the carried pieces' lengths along the tape) below
  // this is too_few_points: pieces of 0.1-0.2 m are no evidence of a tape (a
  // lamp, a sign) and their yaw is off by 0.3-1 deg (docs/scene_faults.md).
  // A zenith band leaving through the image side after ~0.4 m must pass.
  double min_visible_length_m = 0.3;
  // The tape is longer than the view: the carried line must reach the image
  // border at one end at least (the chain of its first or last inlier along
  // the tape touches it). A lamp, a sign, a piece of anything wholly inside
  // the image is not tape. false: no such check.
  bool require_border_end = true;
};

// What a centre-line result rests on (filled whenever a line was fitted).
struct TapeEvidence {
  int runs = 0;                       // inlier runs carrying the line (= TapePose::points_used)
  double residual_px = 0.0;           // RMS of their centres about the line
  int width_sampled = 0;              // inlier runs whose width was compared (at most 32)
  int width_consistent = 0;           // of those, within the tolerance of the predicted width
  double width_ratio_median = 0;      // median measured / predicted width
  double width_excess_px_median = 0;  // median measured - predicted width, image pixels
  // Perspective taper along the line: median width of the sampled runs
  // predicted wider half minus that of the narrower half, predicted and measured.
  double taper_predicted_px = 0, taper_measured_px = 0;
  int pieces = 0;               // pieces along the line (split at gaps > 2 rows and 2 widths)
  int pieces_dropped = 0;       // pieces beyond max_gap_m from the main piece (not used)
  double visible_length_m = 0;  // sum of the carried pieces' lengths along the tape
  double span_m = 0;            // first to last carried inlier, along the tape
  double max_gap_m = 0;         // largest gap between carried pieces
  int ends_at_border = 0;       // ends of the carried line whose chain reaches the image border
  // Median sum_w / pixels of the compared runs (their mean grey - background_level),
  // and the Navigator's contrast: (that + background_level - background) / noise sigma.
  double run_weight_median = 0, contrast_sigma = 0;
  // Zenith mode (moments of the mask): the band's width sqrt(12 lambda2) and
  // length sqrt(12 lambda1) (a uniform band), the width a tape of the
  // configured size predicts, the chord of the image through the centroid
  // along the band, and the fill m00 / (width length): 1 for one straight band.
  double band_width_px = 0, band_width_predicted_px = 0, band_length_px = 0, band_chord_px = 0;
  double band_fill = 0;
};

struct ZenithOptions {
  double min_anisotropy = 0.5;   // (l1 - l2) / (l1 + l2) of the covariance; below: not elongated
  double width_tolerance = 0.5;  // as TapePoseOptions::width_tolerance, on the band width
  double width_slack_px = 3.0;   // as TapePoseOptions::width_slack_px
  // The band must cross the image: its length at least this fraction of the
  // image chord through its centroid along its direction (a tape is longer
  // than the field of view; a lamp or a blob is not).
  double min_chord_fraction = 0.8;
  // m00 / (width length) within 1 +- this: one straight uniform band (two
  // blobs far apart have a large length but little area; a mask full of
  // texture fills more than a band).
  double fill_tolerance = 0.35;
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
  double yaw_sigma_rad = 0.0;  // standard error of the yaw from the inliers' scatter
  // Covariance of (yaw_rad, offset_m) from the inliers' scatter about the
  // line (centre-line method), or from the mask's pixel quantisation (zenith
  // moments, docs/host_maths.md section 5): the statistical part only — the ceiling height's and
  // the pitch's errors scale the offset and tilt the yaw on top of it (docs/host_maths.md).
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  Eigen::Vector3d line_norm{0.0, 0.0, 0.0};  // centre line l, l . (x, y, 1) = 0, l1^2 + l2^2 = 1
  TapeEvidence evidence;
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
// Status `inconsistent` when the band is not one straight band of the
// configured tape's width crossing the image (ZenithOptions).
TapePose zenith_pose_from_moments(const stream::MomentResults& m, const CameraModel& cam,
                                  const CameraConfig& cfg, bool use_mask = true,
                                  const ZenithOptions& opt = {});

}  // namespace ceilnav::host
