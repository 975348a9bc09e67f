// Seed 004's template tracking (section 3.2, figure 5): a homing site is the
// patch of ceiling recorded above the camera when the robot stood at it; on
// the way back the tracker finds that patch in the current frame: where
// (X, Y: the site point's pixel, the seed's template position) and turned by
// how much (gamma over 360 deg). The major orientation of the frame (seed:
// FindOrientation, -45 .. 45 deg) against the site's narrows gamma to four
// candidates 90 deg apart; a bank of the site's patch turned in 11.25 deg
// steps gives the template nearest each; normalised cross-correlation
// (TM_CCOEFF_NORMED, host/homing/ncc.hpp; the seed's FindModel) picks the
// quadrant; then the peak is refined: position to a sub-pixel, angle by a
// parabola through the scores of the patch turned by the estimate and +-
// the refinement step. Coarse to fine: candidates on a quarter-resolution
// pyramid level, refinement at full resolution in a small window (the
// window's block sums shared by all its scores, each angle's peak climbed
// to from the last one's).
// docs/homing.md, "Tracking".
//
// Angles: the image's (u right, v down, clockwise positive on the screen);
// gamma is the turn of the site's content in the current frame. The camera
// looks up: a robot turned by +dpsi (counter-clockwise seen from above)
// sees the ceiling turned by gamma = -dpsi (golden/ceiling tests).
#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "common/camera_config.hpp"

namespace ceilnav::host::homing {

struct SiteOptions {
  int template_px = 96;         // the matched patch, square (the seed: 64)
  int bank_size = 32;           // templates over 360 deg (11.25 deg apart)
  int orientation_bins = 90;    // of the major orientation's histogram
  double min_magnitude = 16.0;  // gradients voting into it
};

// A recorded homing site: its patch (a square wide enough to be turned
// without losing corners), centred on the principal point (the ceiling
// point above the camera), and the frame's major orientation.
struct Site {
  SiteOptions options;
  cv::Mat patch;                       // CV_32FC1, side ceil(template_px * sqrt 2) + 4
  double major_orientation_deg = 0.0;  // of the recorded frame, [-45, 45)
  // How well the site can be told apart (from the recorded frame): the best
  // NCC of the template elsewhere in the frame (outside half a template of
  // its own place) and against its own 90, 180, 270 deg turns.
  double self_similarity = 0.0;
  double rotational_similarity = 0.0;
};

// The major orientation of a frame as the device reports it: the folded
// histogram (bins over 90 deg, magnitude-weighted). The tracker takes it as
// an input; without the device, golden::orientation_histogram_ref.
using OrientationHistogram = std::vector<double>;

// Records the site of `frame` (CV_8UC1 of the camera's size) with its
// orientation histogram. Throws std::invalid_argument when the patch does
// not fit in the frame or the options are out of range.
Site record_site(const cv::Mat& frame, const OrientationHistogram& histogram,
                 const CameraConfig& camera, const SiteOptions& options = {});

// The site's patch turned by gamma (image angle, degrees) about its centre,
// moved by (shift_x, shift_y) pixels, cropped to `side` x `side` (CV_32FC1):
// bilinear at exact coordinates, the patch's edge replicated beyond it.
cv::Mat turned_template(const Site& site, double gamma_deg, int side, double shift_x_px = 0.0,
                        double shift_y_px = 0.0);

struct TrackerOptions {
  // The search: the frame's area within search_radius_px of `centre` (the
  // predicted site point; default the principal point), on the quarter
  // resolution level.
  double search_radius_px = 1e9;  // default: the whole frame
  // Refinement window at full resolution, +- px around the coarse peak. The
  // quarter-resolution level smooths a grille's slats away, and its peak on
  // a grille can lie two slats (26 px on the 2.6 m study ceiling) from the
  // site: a narrower window refines a slat-shifted match (0.83) and misses
  // the site (0.999).
  int refine_px = 32;
  double refine_step_deg = 2.0;  // the angle parabola's step
  // Status: a match at or above min_score is the site; the best quadrant
  // must beat the second by min_quadrant_margin and the best place the
  // next (outside half a template) by min_place_margin, else ambiguous.
  double min_score = 0.7;
  double min_quadrant_margin = 0.02;
  // The coarse level's slack: candidates (and frames) whose quarter-
  // resolution score is more than this below the best (below min_score)
  // are not refined. Smoothing and the quarter resolution lower a true
  // match's score by less (0.02 - 0.08 on renders).
  double coarse_margin = 0.15;
  double min_place_margin = 0.05;
};

enum class TrackStatus {
  ok,
  ambiguous,  // a match, but another quadrant or place scores as well
  not_found,  // no match at min_score
};
const char* to_string(TrackStatus s);

struct TrackResult {
  TrackStatus status = TrackStatus::not_found;
  double x_px = 0.0, y_px = 0.0;  // the site point in the frame (distorted pixels)
  double gamma_deg = 0.0;         // [0, 360)
  double score = 0.0;             // the refined match's NCC
  double quadrant_margin = 0.0;   // best quadrant's coarse score - the second's
  double place_margin = 0.0;      // best place's coarse score - the next place's
  int quadrant = 0;               // k of gamma' + k 90
};

class SiteTracker {
 public:
  SiteTracker(const Site& site, const TrackerOptions& options = {});
  // frame: CV_8UC1; histogram: its orientation histogram (as Site's).
  // centre: the predicted site point (default: the frame's centre).
  // gamma_prediction_deg: the seed's fast mode (section 4.1): no quadrant
  // search, three templates 10 deg apart about the prediction.
  TrackResult track(const cv::Mat& frame, const OrientationHistogram& histogram,
                    std::optional<cv::Point2d> centre = std::nullopt,
                    std::optional<double> gamma_prediction_deg = std::nullopt) const;

 private:
  Site site_;
  TrackerOptions options_;
  // The bank: the patch turned by 360 k / bank_size deg, at a quarter of the
  // resolution (the coarse search; the refinement turns the patch itself).
  std::vector<cv::Mat> bank_coarse_;
};

}  // namespace ceilnav::host::homing
