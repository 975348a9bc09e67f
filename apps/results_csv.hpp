// The results table of `ceilnav run` and `ceilnav demo`: one row per frame.
#pragma once

#include <ostream>
#include <span>
#include <string>

#include "host/junction.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {

// Columns: frame,status,yaw_rad,offset_m,pitch_rad,vp_u,vp_v,pitch_est_rad,
// points_used,residual_px,threshold,passes,zenith_yaw_rad,zenith_offset_m,
// zenith_status,visible_length_m,coverage,width_consistent,ends_at_border,
// contrast_sigma,junction,junction_side,junction_distance_m. The pose columns of a result that is
// not ok are empty (the centre line's by `status`, the zenith's by `zenith_status`); the evidence
// columns (host::TapeEvidence: visible tape length, its coverage of the span,
// width-consistent / compared runs, ends at the image border, contrast in
// noise sigmas) are filled whenever a centre line was fitted, ok or not. A value
// that does not exist for the frame (failed status, vanishing point at
// infinity, no pitch estimate, not a zenith camera) is an empty field, never NaN.
// Junction columns (host::detect_junctions of the frame, nearest first): only
// when the pose is ok, the nearest junction's kind (none, t_branch, l_turn,
// tape_end), its side (left, right, both; empty for none and tape_end) and its
// distance along the tape from the camera's foot point (empty for none).
void write_results_header(std::ostream& out);
void write_results_row(std::ostream& out, const std::string& frame_name,
                       const host::FrameOutcome& outcome,
                       std::span<const host::Junction> junctions = {});

// The status word of a frame: "ok" or the reason.
std::string frame_status(const host::FrameOutcome& outcome);

}  // namespace ceilnav::app
