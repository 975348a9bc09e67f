#include "apps/results_csv.hpp"

#include <cmath>
#include <cstdio>

namespace ceilnav::app {

namespace {

std::string number(double v) {
  if (!std::isfinite(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// File names may contain commas or quotes: quote them as RFC 4180 says.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

}  // namespace

std::string frame_status(const host::FrameOutcome& outcome) {
  if (!outcome.results.valid) return std::string(host::to_string(host::Status::frame_invalid));
  return std::string(host::to_string(outcome.pose.status));
}

void write_results_header(std::ostream& out) {
  out << "frame,status,yaw_rad,offset_m,pitch_rad,vp_u,vp_v,pitch_est_rad,points_used,"
         "residual_px,threshold,passes,zenith_yaw_rad,zenith_offset_m\n";
}

void write_results_row(std::ostream& out, const std::string& frame_name,
                       const host::FrameOutcome& o) {
  const std::string status = frame_status(o);
  const bool ok = status == "ok";
  const host::TapePose& p = o.pose;
  out << csv_field(frame_name) << ',' << status << ',';
  out << (ok ? number(p.yaw_rad) : "") << ',' << (ok ? number(p.offset_m) : "") << ',';
  out << (ok ? number(p.pitch_rad) : "") << ',';
  out << (ok && p.vp_finite ? number(p.vp_u_px) : "") << ','
      << (ok && p.vp_finite ? number(p.vp_v_px) : "") << ',';
  out << (ok && p.pitch_est_valid ? number(p.pitch_est_rad) : "") << ',';
  out << p.points_used << ',' << (ok ? number(p.residual_rms_px) : "") << ',';
  out << static_cast<int>(o.settings.threshold) << ',' << o.passes << ',';
  const bool zenith_ok = o.zenith && o.zenith->status == host::Status::ok;
  out << (zenith_ok ? number(o.zenith->yaw_rad) : "") << ','
      << (zenith_ok ? number(o.zenith->offset_m) : "") << '\n';
}

}  // namespace ceilnav::app
