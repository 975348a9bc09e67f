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
  const LineFit line = choose_tape(sc.cands, opt.tie_fraction);

  // Final statistics on the inliers; the gates on them.
  Mask& final_inliers = sc.mask_a;
  fits.inliers(line, final_inliers);
  const InlierStats stats = inlier_statistics(pts, final_inliers, line, cam.fx());
  out.points_used = stats.used;
  out.residual_rms_px = stats.used > 0 ? std::sqrt(stats.ss / stats.used) : 0.0;
  {
    const double norm = std::sqrt(1.0 + line.a * line.a);
    out.line_norm = Eigen::Vector3d(1.0, -line.a, -line.b) / norm;
  }
  if (stats.used < opt.min_points) {
    out.status = too_few;
    return out;
  }
  if (stats.row_max - stats.row_min < opt.min_row_span_px) {
    out.status = Status::degenerate;
    return out;
  }
  out.yaw_sigma_rad = yaw_sigma(stats, line, cam.fx(), g);
  if (out.yaw_sigma_rad > opt.max_yaw_sigma_deg * kDegToRad) {
    out.status = Status::too_few_points;
    return out;
  }

  // Yaw and offset, the vanishing point, the pitch estimate.
  const Status st =
      pose_from_centre_line(out.line_norm, out.pitch_rad, g.c, opt.max_abs_yaw_deg * kDegToRad,
                            out.yaw_rad, out.offset_m);
  if (st != Status::ok) {
    out.status = st;
    return out;
  }
  // Vanishing point of +X: normalised (tan psi / cos p, tan p) (seed 000 eq. 24-25,
  // with y down). At the zenith it is at infinity.
  if (g.cp > 1e-6) {
    set_vanishing_point(Eigen::Vector2d(std::tan(out.yaw_rad) / g.cp, g.sp / g.cp), cam, out);
  }
  if (opt.estimate_pitch) pitch_from_edges(runs, cam, final_inliers, stats.used, sc, out);
  out.status = Status::ok;
  return out;
}

TapePose zenith_pose_from_moments(const stream::MomentResults& m, const CameraModel& cam,
                                  const CameraConfig& cfg, bool use_mask) {
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
  if (!(trace > 0.0) || !(aniso > 0.5 * trace)) {
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
  out.status = st;
  if (st != Status::ok) return out;
  const double cp = std::cos(out.pitch_rad);
  if (cp > 1e-6) {
    set_vanishing_point(Eigen::Vector2d(std::tan(out.yaw_rad) / cp, std::tan(out.pitch_rad)), cam,
                        out);
  }
  return out;
}

}  // namespace ceilnav::host
