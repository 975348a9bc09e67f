#include "host/tape_pose.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "host/tape_pose_steps.hpp"

namespace ceilnav::host {
namespace {

using namespace tape_steps;

// The working storage of estimate_tape_pose, kept per thread so that a call
// allocates nothing once the buffers have grown to the frame's run count.
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// out.vp_* from the vanishing point of +X in normalised coordinates, when its
// ideal pixel is finite and within 1e9 px.
void set_vanishing_point(const Eigen::Vector2d& vp, const CameraModel& cam, TapePose& out) {
  const Eigen::Vector2d vp_px = cam.ideal_pixel(vp);
  if (vp_px.allFinite() && vp_px.cwiseAbs().maxCoeff() < 1e9) {
    out.vp_finite = true;
    out.vp_u_px = vp_px.x();
    out.vp_v_px = vp_px.y();
  }
}

}  // namespace

Status pose_from_centre_line(const Eigen::Vector3d& line, double pitch_rad,
                             double ceiling_above_camera_m, double max_abs_yaw_rad, double& yaw_rad,
                             double& offset_m) {
  if (!line.allFinite()) return Status::degenerate;
  const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
  const double l1 = line.x(), l2 = line.y(), l3 = line.z();
  // The back-projected plane has world normal n = R^T l; it contains +X:
  //   n_x = l1 sin psi + cos psi (l2 sin p + l3 cos p) = 0.
  const double num = -(l2 * sp + l3 * cp);
  if (!(std::abs(l1) > 0.0) || std::abs(num) > std::tan(max_abs_yaw_rad) * std::abs(l1)) {
    return Status::degenerate;
  }
  const double yaw = std::atan(num / l1);
  // It contains the tape (s, -offset, c) relative to the camera:
  //   offset = n_z c / n_y,  n_y = -l1 / cos psi,  n_z = -l2 cos p + l3 sin p.
  const double offset = ceiling_above_camera_m * std::cos(yaw) * (l2 * cp - l3 * sp) / l1;
  if (!std::isfinite(yaw) || !std::isfinite(offset)) return Status::degenerate;
  yaw_rad = yaw;
  offset_m = offset;
  return Status::ok;
}

TapePose estimate_tape_pose(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                            const CameraConfig& cfg, const TapePoseOptions& opt) {
  TapePose out;
  out.method = "runs_centre_line";
  out.pitch_rad = cfg.camera_pitch_deg * kDegToRad;
  out.points_total = static_cast<int>(runs.size());
  if (runs.empty()) {
    out.status = Status::no_tape;
    return out;
  }
  Geometry g;
  g.sp = std::sin(out.pitch_rad);
  g.cp = std::cos(out.pitch_rad);
  g.c = cfg.ceiling_above_camera_m();
  if (!(g.c > 0.0)) {
    out.status = Status::bad_config;
    return out;
  }
  g.width = cfg.image_width;
  g.height = cfg.image_height;

  Scratch& sc = scratch();
  const size_t n = runs.size();
  // Runs into chains, each chain's heading, the centre-line points.
  sort_runs(runs, sc);
  link_chains(n, sc);
  chain_extents(n, sc);
  undistort_run_centres(runs, cam, sc);
  fit_chain_headings(n, g, opt, sc);
  gate_centre_points(runs, cam, cfg, opt, g, sc);
  collect_points(runs, sc);
  const Points& pts = sc.pts;
  const int usable_total = static_cast<int>(pts.size());

  // Candidate lines from the largest chains; the tape among them.
  largest_chains(n, sc);
  const Status too_few = status_when_too_few(opt, sc);
  if (usable_total < opt.min_points || sc.comps.empty()) {
    out.status = too_few;
    out.points_used = usable_total;
    return out;
  }
  InlierFits fits(pts, opt.max_residual_px / cam.fx(), sc.memo);
  fit_candidates(opt, fits, sc);
  if (sc.cands.empty()) {
    out.status = Status::degenerate;
    return out;
  }
  LineFit line = choose_tape(sc.cands, opt.tie_fraction);

  // Final statistics on the inliers, the gates on them, yaw and offset.
  Mask& final_inliers = sc.mask_a;
  fits.inliers(line, final_inliers);
  const auto solve = [&]() -> Status {
    const InlierStats stats = inlier_statistics(pts, final_inliers, line, cam.fx());
    out.points_used = stats.used;
    out.residual_rms_px = stats.used > 0 ? std::sqrt(stats.ss / stats.used) : 0.0;
    const double norm = std::sqrt(1.0 + line.a * line.a);
    out.line_norm = Eigen::Vector3d(1.0, -line.a, -line.b) / norm;
    if (stats.used < opt.min_points) return too_few;
    if (stats.row_max - stats.row_min < opt.min_row_span_px) return Status::degenerate;
    out.yaw_sigma_rad = yaw_sigma(stats, line, cam.fx(), g);
    if (out.yaw_sigma_rad > opt.max_yaw_sigma_deg * kDegToRad) return Status::too_few_points;
    out.covariance = pose_covariance(stats, line, cam.fx(), g);
    return pose_from_centre_line(out.line_norm, out.pitch_rad, g.c, opt.max_abs_yaw_deg * kDegToRad,
                                 out.yaw_rad, out.offset_m);
  };
  Status st = solve();
  TapeEvidence& ev = out.evidence;
  // Pieces far from the main one are dropped and the line refitted on the
  // rest, until the carried set holds (at most 3 refits; a set that still
  // changes then is no stable line: inconsistent).
  int dropped = 0;
  for (int refit = 0; st == Status::ok; ++refit) {
    if (!select_pieces(pts, cfg.tape_width_m, opt, g, out.yaw_rad, final_inliers, sc, ev)) break;
    dropped += ev.pieces_dropped;
    if (refit == 3) st = Status::inconsistent;
    if (st != Status::ok) break;
    line = fit_x_on_y(pts, final_inliers);
    if (!line.ok) st = Status::degenerate;
    if (st != Status::ok) break;
    out.yaw_rad = out.offset_m = 0.0;
    st = solve();
  }
  ev.pieces += dropped - ev.pieces_dropped;
  ev.pieces_dropped = dropped;
  ev.runs = out.points_used;
  ev.residual_px = out.residual_rms_px;
  if (st != Status::ok) {
    out.yaw_rad = out.offset_m = 0.0;
    out.status = st;
    return out;
  }
  // The evidence that it is a tape of the configured size (host_maths.md 4, Evidence).
  // max_width_factor <= 0: the runs' widths are not a tape's (synthetic runs), no width check.
  const bool check_width = opt.max_width_factor > 0.0;
  if (check_width) {
    width_evidence(runs, cam, cfg, opt, g, out.yaw_rad, final_inliers, out.points_used, sc, ev);
  }
  if (ev.visible_length_m < opt.min_visible_length_m) {
    out.yaw_rad = out.offset_m = 0.0;
    out.status = Status::too_few_points;
    return out;
  }
  if (ev.visible_length_m < opt.min_coverage * ev.span_m ||
      (opt.require_border_end && ev.ends_at_border == 0) ||
      (check_width && ev.width_consistent < opt.min_width_consistent_fraction * ev.width_sampled)) {
    out.yaw_rad = out.offset_m = 0.0;
    out.status = Status::inconsistent;
    return out;
  }
  // Vanishing point of +X: normalised (tan psi / cos p, tan p) (seed 000 eq. 24-25,
  // with y down). At the zenith it is at infinity.
  if (g.cp > 1e-6) {
    set_vanishing_point(Eigen::Vector2d(std::tan(out.yaw_rad) / g.cp, g.sp / g.cp), cam, out);
  }
  if (opt.estimate_pitch) pitch_from_edges(runs, cam, final_inliers, out.points_used, sc, out);
  out.status = Status::ok;
  return out;
}

TapePose zenith_pose_from_moments(const stream::MomentResults& m, const CameraModel& cam,
                                  const CameraConfig& cfg, bool use_mask,
                                  const ZenithOptions& opt) {
  TapePose out;
  out.method = "zenith_moments";
  out.pitch_rad = cfg.camera_pitch_deg * kDegToRad;
  const auto& mm = use_mask ? m.mask : m.grey;
  if (mm[stream::kM00] == 0) {
    out.status = Status::no_tape;
    return out;
  }
  const double m00 = static_cast<double>(mm[stream::kM00]);
  const double xb = static_cast<double>(mm[stream::kM10]) / m00;
  const double yb = static_cast<double>(mm[stream::kM01]) / m00;
  const double mu20 = static_cast<double>(mm[stream::kM20]) / m00 - xb * xb;
  const double mu11 = static_cast<double>(mm[stream::kM11]) / m00 - xb * yb;
  const double mu02 = static_cast<double>(mm[stream::kM02]) / m00 - yb * yb;
  const double trace = mu20 + mu02;
  const double aniso = std::hypot(mu20 - mu02, 2.0 * mu11);
  // (l1 - l2) / (l1 + l2) of the covariance: 0 for a disc, -> 1 for a thin band.
  if (!(trace > 0.0) || !(aniso > opt.min_anisotropy * trace)) {
    out.status = Status::degenerate;
    return out;
  }
  // Major axis at angle theta from the +u axis towards +v (rows down), in pixels.
  const double theta = 0.5 * std::atan2(2.0 * mu11, mu20 - mu02);
  const Eigen::Vector2d dir(std::cos(theta) / cam.fx(), std::sin(theta) / cam.fy());
  const Eigen::Vector2d pt((xb - cam.cx()) / cam.fx(), (yb - cam.cy()) / cam.fy());
  const Eigen::Vector3d l(dir.y(), -dir.x(), dir.x() * pt.y() - dir.y() * pt.x());
  out.line_norm = l / l.head<2>().norm();
  if (out.line_norm.x() < 0.0) out.line_norm = -out.line_norm;
  out.points_total = out.points_used = 0;
  const Status st =
      pose_from_centre_line(out.line_norm, out.pitch_rad, cfg.ceiling_above_camera_m(),
                            85.0 * kDegToRad, out.yaw_rad, out.offset_m);
  if (st != Status::ok) {
    out.yaw_rad = out.offset_m = 0.0;
    out.status = st;
    return out;
  }
  // Evidence: one straight band of the tape's width crossing the image.
  TapeEvidence& ev = out.evidence;
  const double l1 = 0.5 * (trace + aniso), l2 = std::max(0.0, 0.5 * (trace - aniso));
  ev.band_width_px = std::sqrt(12.0 * l2);
  ev.band_length_px = std::sqrt(12.0 * l1);
  ev.band_fill = m00 / std::max(1e-9, ev.band_width_px * ev.band_length_px);
  // Width across the band of a tape W wide at c above a zenith camera: the
  // normal (sin theta, -cos theta) in pixels is W / c times fx, fy along it.
  const double nx = std::sin(theta), ny = -std::cos(theta);
  ev.band_width_predicted_px =
      cfg.tape_width_m / cfg.ceiling_above_camera_m() * std::hypot(cam.fx() * nx, cam.fy() * ny);
  {
    // Chord of the image rectangle [-0.5, W-0.5] x [-0.5, H-0.5] through the
    // centroid along (cos theta, sin theta).
    const double dx = std::cos(theta), dy = std::sin(theta);
    double t_lo = -1e18, t_hi = 1e18;
    const auto clip = [&](double p, double d, double lo, double hi) {
      if (std::abs(d) < 1e-12) return;
      const double a = (lo - p) / d, b = (hi - p) / d;
      t_lo = std::max(t_lo, std::min(a, b));
      t_hi = std::min(t_hi, std::max(a, b));
    };
    clip(xb, dx, -0.5, cfg.image_width - 0.5);
    clip(yb, dy, -0.5, cfg.image_height - 0.5);
    ev.band_chord_px = std::max(0.0, t_hi - t_lo);
  }
  const bool width_ok = std::abs(ev.band_width_px - ev.band_width_predicted_px) <=
                        opt.width_tolerance * ev.band_width_predicted_px + opt.width_slack_px;
  const bool crosses = ev.band_length_px >= opt.min_chord_fraction * ev.band_chord_px;
  const bool one_band = std::abs(ev.band_fill - 1.0) <= opt.fill_tolerance;
  if (!width_ok || !crosses || !one_band) {
    out.yaw_rad = out.offset_m = 0.0;
    out.status = Status::inconsistent;
    return out;
  }
  out.status = Status::ok;
  // Quantisation of the mask's edges (docs/host_maths.md section 5): each edge
  // of the band is placed to within a pixel, uniform in +-1/2 px, the same on
  // every row when the band runs along a pixel axis (the robot following the
  // tape); the centroid is their mean, sigma 1/sqrt(24) px across the band,
  // c / (focal length along the normal) metres per pixel. The axis, from the
  // two halves' centroids L/2 apart, each off by that much independently:
  // sigma sqrt(2) / sqrt(24) / (L/2) rad.
  const double across_px = 1.0 / std::sqrt(24.0);
  const double m_per_px = cfg.ceiling_above_camera_m() / std::hypot(cam.fx() * nx, cam.fy() * ny);
  const double yaw_sigma = 2.0 * std::sqrt(2.0) * across_px / std::max(1.0, ev.band_length_px);
  const double offset_sigma = across_px * m_per_px;
  out.covariance = Eigen::Vector2d(yaw_sigma * yaw_sigma, offset_sigma * offset_sigma).asDiagonal();
  const double cp = std::cos(out.pitch_rad);
  if (cp > 1e-6) {
    set_vanishing_point(Eigen::Vector2d(std::tan(out.yaw_rad) / cp, std::tan(out.pitch_rad)), cam,
                        out);
  }
  return out;
}

}  // namespace ceilnav::host
