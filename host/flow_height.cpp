#include "host/flow_height.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace ceilnav::host {

HeightEstimate ceiling_height_from_flow(double v1_norm, double v2_norm, double pitch_rad,
                                        double distance_m, double motion_angle_rad) {
  HeightEstimate out;
  if (!std::isfinite(v1_norm) || !std::isfinite(v2_norm) || !std::isfinite(pitch_rad) ||
      !std::isfinite(distance_m) || !std::isfinite(motion_angle_rad)) {
    return out;
  }
  const double forward_m = distance_m * std::cos(motion_angle_rad);
  // No forward motion (sideways motion leaves the rows unchanged): no parallax.
  if (!(forward_m > 1e-6 * std::abs(distance_m)) || !(forward_m > 0.0)) return out;
  const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
  // A ceiling point c above the camera and w ahead projects to
  //   y = (w sin p - c cos p) / (w cos p + c sin p)  =>  w / c = g(y).
  const double den1 = sp - v1_norm * cp, den2 = sp - v2_norm * cp;
  if (!(den1 > 1e-9) || !(den2 > 1e-9)) return out;  // on or below the horizon
  const double g1 = (cp + v1_norm * sp) / den1;
  const double g2 = (cp + v2_norm * sp) / den2;
  const double dg = g1 - g2;
  if (!(dg > 1e-12 * (1.0 + std::abs(g1)))) return out;  // no parallax (or moved backwards)
  const double c = forward_m / dg;
  if (!std::isfinite(c) || !(c > 0.0)) return out;
  out.status = Status::ok;
  out.ceiling_above_camera_m = c;
  out.range_m = c * g1;
  return out;
}

std::optional<Eigen::Vector2d> find_tape_end(std::span<const stream::RunRecord> runs,
                                             const CameraModel& cam, const CameraConfig& cfg,
                                             const TapePose& pose, const TapeEndOptions& opt) {
  if (pose.status != Status::ok || runs.empty()) return std::nullopt;
  const Eigen::Vector3d& l = pose.line_norm;
  const double sp = std::sin(pose.pitch_rad), cp = std::cos(pose.pitch_rad);
  const double c = cfg.ceiling_above_camera_m();

  // Per row: tape mass and mass-weighted centre of the runs on the centre line.
  struct RowSum {
    double mass = 0.0, xw = 0.0;
  };
  std::map<int, RowSum> rows;
  for (const auto& r : runs) {
    if (r.sum_w == 0) continue;
    const double xc = static_cast<double>(r.sum_xw) / static_cast<double>(r.sum_w);
    const Eigen::Vector2d p = cam.normalise(xc, r.row);
    const double dist_px = std::abs(l.x() * p.x() + l.y() * p.y() + l.z()) * cam.fx();
    if (dist_px > opt.max_residual_px + 0.5 * (r.x_end - r.x_start + 1.0)) continue;
    RowSum& s = rows[r.row];
    s.mass += static_cast<double>(r.sum_w);
    s.xw += static_cast<double>(r.sum_xw);
  }
  if (rows.empty()) return std::nullopt;

  // First chain from the top and its last row.
  std::vector<int> chain;
  for (const auto& [row, s] : rows) {
    if (!chain.empty() && row != chain.back() + 1) break;
    chain.push_back(row);
  }
  const int last = chain.back();
  if (last + 1 >= cfg.image_height) return std::nullopt;  // runs off the bottom: no end
  // Expected tape width just below the end: W (sin p - y cos p) / c (cos psi ~ 1).
  {
    const double y_next = (last + 1.0 - cam.cy()) / cam.fy();
    const double width_px = cam.fx() * cfg.tape_width_m * (sp - y_next * cp) / c;
    if (width_px < opt.min_visible_width_px) return std::nullopt;  // fading at the horizon
  }
  // End rows: the tape end crosses rows over about its width times the tilt of
  // the cut; allow half the tape width plus 3 rows.
  const double y_last = (last - cam.cy()) / cam.fy();
  const double width_last_px = cam.fx() * cfg.tape_width_m * std::max(0.0, sp - y_last * cp) / c;
  const int span = 3 + static_cast<int>(std::ceil(0.5 * width_last_px));
  const int n_chain = static_cast<int>(chain.size());
  if (n_chain < opt.min_rows + span + opt.reference_rows / 2) return std::nullopt;
  const int ref_end = n_chain - span;  // chain[ref_end - 1] is the last full row
  const int ref_begin = std::max(0, ref_end - opt.reference_rows);
  if (ref_end - ref_begin < 2) return std::nullopt;
  // Linear fits over the reference rows: mass(row) and centre(row), pixels.
  double n = 0, sr = 0, srr = 0, sm = 0, srm = 0, sx = 0, srx = 0;
  for (int k = ref_begin; k < ref_end; ++k) {
    const int row = chain[static_cast<size_t>(k)];
    const RowSum& s = rows.at(row);
    const double xc = s.xw / s.mass;
    n += 1;
    sr += row;
    srr += static_cast<double>(row) * row;
    sm += s.mass;
    srm += row * s.mass;
    sx += xc;
    srx += row * xc;
  }
  const double det = n * srr - sr * sr;
  if (!(det > 0.0)) return std::nullopt;
  const double mass_slope = (n * srm - sr * sm) / det, mass_icpt = (sm - mass_slope * sr) / n;
  const double x_slope = (n * srx - sr * sx) / det, x_icpt = (sx - x_slope * sr) / n;
  double v_end = chain[static_cast<size_t>(ref_end - 1)] + 0.5;
  for (int k = ref_end; k < n_chain; ++k) {
    const int row = chain[static_cast<size_t>(k)];
    const double full = mass_icpt + mass_slope * row;
    if (!(full > 0.0)) return std::nullopt;
    v_end += rows.at(row).mass / full;
  }
  const double u_end = x_icpt + x_slope * v_end;
  const Eigen::Vector2d p = cam.normalise(u_end, v_end);
  if (!p.allFinite()) return std::nullopt;
  return p;
}

}  // namespace ceilnav::host
