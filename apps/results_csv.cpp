#include "apps/results_csv.hpp"

#include <limits>
#include <numbers>

#include "common/csv.hpp"

namespace ceilnav::app {

std::string frame_status(const host::FrameOutcome& outcome) {
  if (!outcome.results.valid) return std::string(host::to_string(host::Status::frame_invalid));
  return std::string(host::to_string(outcome.pose.status));
}

void write_results_header(std::ostream& out) {
  CsvWriter(out).row({"frame",
                      "status",
                      "yaw_rad",
                      "offset_m",
                      "pitch_rad",
                      "vp_u",
                      "vp_v",
                      "pitch_est_rad",
                      "points_used",
                      "residual_px",
                      "threshold",
                      "passes",
                      "zenith_yaw_rad",
                      "zenith_offset_m",
                      "zenith_status",
                      "visible_length_m",
                      "coverage",
                      "width_consistent",
                      "ends_at_border",
                      "contrast_sigma",
                      "junction",
                      "junction_side",
                      "junction_distance_m",
                      "junction_angle_deg",
                      "flow_ceiling_m",
                      "flow_ceiling_se_m",
                      "flow_range_m",
                      "flow_frames",
                      "width_ceiling_m",
                      "odometry_scale"});
}

void write_results_row(std::ostream& out, const std::string& frame_name,
                       const host::FrameOutcome& o, std::span<const host::Junction> junctions,
                       const OdometryColumns& odo) {
  constexpr int kDigits = 10;  // significant digits of every real column
  const std::string status = frame_status(o);
  const bool ok = status == "ok";
  const host::TapePose& p = o.pose;
  // An absent value is an empty field; NaN never reaches the file.
  const auto value = [&](bool present, double v) -> double {
    return present ? v : std::numeric_limits<double>::quiet_NaN();
  };
  // A zenith result counts only when it is ok itself; its columns are empty otherwise.
  const bool zenith_ok = o.zenith && o.zenith->status == host::Status::ok;
  CsvWriter w(out);
  w.text(frame_name).text(status);
  w.general(value(ok, p.yaw_rad), kDigits).general(value(ok, p.offset_m), kDigits);
  w.general(value(ok, p.pitch_rad), kDigits);
  w.general(value(ok && p.vp_finite, p.vp_u_px), kDigits)
      .general(value(ok && p.vp_finite, p.vp_v_px), kDigits);
  w.general(value(ok && p.pitch_est_valid, p.pitch_est_rad), kDigits);
  w.integer(p.points_used).general(value(ok, p.residual_rms_px), kDigits);
  w.integer(static_cast<int>(o.settings.threshold)).integer(o.passes);
  w.general(value(zenith_ok, zenith_ok ? o.zenith->yaw_rad : 0.0), kDigits)
      .general(value(zenith_ok, zenith_ok ? o.zenith->offset_m : 0.0), kDigits);
  if (o.zenith) {
    w.text(std::string(host::to_string(o.zenith->status)));
  } else {
    w.empty();
  }
  // Evidence of the centre line, whenever one was fitted (it explains the status).
  const host::TapeEvidence& ev = p.evidence;
  const bool fitted = ev.runs > 0 && ev.span_m > 0.0;
  w.general(value(fitted, ev.visible_length_m), 4)
      .general(value(fitted, fitted ? ev.visible_length_m / ev.span_m : 0.0), 4);
  if (fitted && ev.width_sampled > 0) {
    w.text(std::to_string(ev.width_consistent) + "/" + std::to_string(ev.width_sampled));
  } else {
    w.empty();
  }
  if (fitted) {
    w.integer(ev.ends_at_border);
  } else {
    w.empty();
  }
  w.general(value(fitted, ev.contrast_sigma), 4);
  // The nearest junction, only for an ok pose.
  if (ok) {
    const host::Junction none;
    const host::Junction& j = junctions.empty() ? none : junctions.front();
    const bool branch =
        j.kind == host::JunctionKind::t_branch || j.kind == host::JunctionKind::l_turn;
    w.text(std::string(host::to_string(j.kind)));
    if (branch) {
      w.text(std::string(host::to_string(j.side)));
    } else {
      w.empty();
    }
    w.general(value(j.kind != host::JunctionKind::none, j.distance_m), 4);
    w.general(value(branch, j.branch_angle_rad * 180.0 / std::numbers::pi), 4);
  } else {
    w.empty().empty().empty().empty();
  }
  const auto opt = [&](const std::optional<double>& v) {
    w.general(value(v.has_value(), v.value_or(0.0)), kDigits);
  };
  opt(odo.flow_ceiling_m);
  opt(odo.flow_ceiling_se_m);
  opt(odo.flow_range_m);
  if (odo.flow_frames) {
    w.integer(*odo.flow_frames);
  } else {
    w.empty();
  }
  opt(odo.width_ceiling_m);
  opt(odo.odometry_scale);
  w.end_row();
}

}  // namespace ceilnav::app
