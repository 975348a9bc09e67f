// Junctions of the followed tape seen in a frame: a T-branch (a strip of the
// tape's width leaving the line to one side, or crossing it), an L-turn (the
// line ends in view and a strip continues from its end to one side) and a tape
// end (the line ends in view and nothing continues: a gap or the end of the
// course). From the frame's runs, the camera model and configuration and the
// frame's ok centre-line pose. Derivation: docs/host_maths.md section 9.
//
// Every run pixel is mapped onto the ceiling plane in the tape's frame: s
// along the tape (+X) from the camera's foot point, l across it from the
// fitted centre line (positive left). Pixels farther than the tape band from
// the line form branch candidates (connected per side); pixels in the band
// give the line's coverage along s.
#pragma once

#include <span>
#include <string_view>
#include <vector>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "host/auto_threshold.hpp"
#include "host/camera_model.hpp"
#include "host/navigator.hpp"
#include "host/tape_pose.hpp"

namespace ceilnav::host {

enum class JunctionKind { none, t_branch, l_turn, tape_end };
enum class JunctionSide { none, left, right, both };

std::string_view to_string(JunctionKind k);
std::string_view to_string(JunctionSide s);

// What a junction rests on. Branch fields are 0 for a tape end.
struct JunctionEvidence {
  int branch_runs = 0;           // runs with pixels in the branch strip(s)
  double branch_area_m2 = 0.0;   // ceiling area of those pixels
  double branch_length_m = 0.0;  // strip length seen, sqrt(12 lambda1) (longest side)
  // Strip thickness across its axis, sqrt(12 lambda2), and the allowed
  // difference from the tape width (tolerance * W + slack pixels at the strip).
  double branch_thickness_m = 0.0;
  double thickness_allowance_m = 0.0;
  double branch_fill = 0.0;  // area / (thickness length): 1 for one straight strip
  // The line along s: where its coverage ends before the junction (l_turn,
  // tape_end) or continues past it (t_branch), and how far beyond its end
  // the band is seen empty (the view of the band ends at view_end_m).
  double line_end_m = 0.0;
  double empty_beyond_m = 0.0;
  double view_end_m = 0.0;
  // Contrast of the line's last 0.2 m before its end (l_turn, tape_end): the
  // median run weight per pixel above the threshold's, in noise sigmas.
  double end_contrast_sigma = 0.0;
  // The median width across the tape of the line's runs in that window, over W.
  double end_width_ratio = 0.0;
  // Tape end: how far the runs reach past the end (the threshold's cut into
  // the blurred edge, from the width's excess); distance_m is line_end_m
  // minus it.
  double end_reach_m = 0.0;
};

struct Junction {
  JunctionKind kind = JunctionKind::none;
  JunctionSide side = JunctionSide::none;
  // Along the tape from the camera's foot point to the junction centre: the
  // branch's centre line crossing the tape's (t_branch, l_turn), the end of
  // the line's coverage (tape_end). Positive ahead (+X).
  double distance_m = 0.0;
  // Angle from the tape's +X to the branch, towards its side (pi/2:
  // perpendicular; less: leaning forward). 0 for a tape end; for a crossing
  // the mean of the two sides.
  double branch_angle_rad = 0.0;
  // The distance's standard deviation from the pixel quantisation at the
  // junction (docs/host_maths.md section 9): what the frame's own geometry
  // allows, not counting the pose's error.
  double distance_sigma_m = 0.0;
  JunctionEvidence evidence;
};

struct JunctionOptions {
  // The tape band: |l| <= W/2 + max(band_margin_widths W, band_margin_px
  // pixels across the tape at that point). Outside: branch pixels.
  double band_margin_widths = 0.6;
  double band_margin_px = 2.0;
  // A branch strip: at least this long (seen), metres...
  double min_branch_length_m = 0.15;
  // ... its thickness within width_tolerance W + width_slack_px (pixels
  // across the strip) of the tape width W, as TapePoseOptions...
  double width_tolerance = 0.5;
  double width_slack_px = 3.0;
  // ... one straight strip: fill within 1 +- fill_tolerance ...
  double fill_tolerance = 0.35;
  // ... within max_angle_error_deg of perpendicular to the tape ...
  double max_angle_error_deg = 30.0;
  // ... and joined to the band: its inner end within this many tape widths
  // (or 2 pixels) of the band's edge.
  double max_attach_widths = 1.0;
  // The line's coverage along s splits where consecutive band pixels are more
  // than this many tape widths (and 3 pixel footprints) apart.
  double gap_split_widths = 2.0;
  // A line end is claimed only when the band is seen empty for at least this
  // long beyond it (m; and 3 pixel footprints) inside the view.
  double min_empty_beyond_m = 0.15;
  // ... and when the line's last end_window_m before its end is bright: the
  // median of its runs' sum_w over the tape's predicted width along the row
  // (the tape's grey above background_level) exceeds the threshold's by at
  // least this many noise sigmas. Dimmer, the tape fades under the threshold
  // farther on (1 / r^2) and its end in the runs is no end of the tape.
  double min_end_contrast_sigma = 6.0;
  double end_window_m = 0.2;
  // A tape end only where the line's runs in that window are the tape's
  // width across: median extent within (1 - end_width_tolerance) W and
  // (1 + end_width_tolerance) W + 2 px (bright tape is cut near the foot of its
  // blurred edges). A narrower strip (a 3 cm tube) ending is no tape end.
  double end_width_tolerance = 0.15;
  // A tape end, or a branch on one side only: no more branch pixels than
  // this many W^2 within 2 W of it (on the other side for a branch):
  // something leaves the line there that is no confirmed strip: not decided.
  double max_end_branch_area_widths2 = 1.0;
  // The tape beyond the junction (t_branch) must cover this long, m.
  double min_continuation_m = 0.1;
  // The analysis stops where the tape is narrower than this in the image, px
  // (the far tape dims and breaks up: no ends are claimed there).
  double min_tape_width_px = 2.0;
};

// Every junction of the followed tape in the frame, nearest (|distance_m|)
// first. Empty unless pose.status is ok and pose.method is the centre line.
// `settings`: the threshold the runs were cut with (FrameOutcome::settings).
std::vector<Junction> detect_junctions(std::span<const stream::RunRecord> runs,
                                       const ThresholdSettings& settings, const CameraModel& cam,
                                       const CameraConfig& cfg, const TapePose& pose,
                                       const JunctionOptions& opt = {});
// The same on a Navigator's frame (its runs, settings and centre-line pose).
std::vector<Junction> detect_junctions(const FrameOutcome& frame, const CameraModel& cam,
                                       const CameraConfig& cfg, const JunctionOptions& opt = {});

}  // namespace ceilnav::host
