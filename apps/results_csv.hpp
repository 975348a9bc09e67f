// The results table of `ceilnav run` and `ceilnav demo`: one row per frame.
#pragma once

#include <optional>
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
// tape_end), its side (left, right, both; empty for none and tape_end), its
// distance along the tape from the camera's foot point (empty for none) and
// the branch's angle.
// Then the odometry columns of `run --odometry` (apps/odometry_height.hpp),
// empty when not measured (always, without --odometry): flow_ceiling_m,
// flow_ceiling_se_m, flow_range_m, flow_frames, width_ceiling_m, odometry_scale.
struct OdometryColumns {
  std::optional<double> flow_ceiling_m;     // tape-end track fit with the measured odometry
  std::optional<double> flow_ceiling_se_m;  // its standard error from the fit's residuals
  std::optional<double> flow_range_m;       // the tracked tape end's range ahead (eq. 57)
  std::optional<int> flow_frames;           // frames in that track
  std::optional<double> width_ceiling_m;    // this frame, from the tape's image width
  std::optional<double> odometry_scale;     // flow height / width height, drive so far
};
void write_results_header(std::ostream& out);
void write_results_row(std::ostream& out, const std::string& frame_name,
                       const host::FrameOutcome& outcome,
                       std::span<const host::Junction> junctions = {},
                       const OdometryColumns& odometry = {});

// The status word of a frame: "ok" or the reason.
std::string frame_status(const host::FrameOutcome& outcome);

}  // namespace ceilnav::app
