#include "host/pattern/pattern_pose.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "host/pattern/pattern_axes.hpp"

namespace ceilnav::host::pattern {
namespace {

constexpr double kPi = std::numbers::pi;

double wrap_pi(double a) {
  return std::remainder(a, 2.0 * kPi);
}

// Image offset (normalised) of the shadow's centroid from the disc's centroid.
std::optional<Eigen::Vector2d> shadow_offset(const FrameMoments& m, const CameraModel& camera,
                                             const Ellipse& disc, const PoseOptions& o) {
  const ClassMoments& s = m[kShadow];
  if (s.m00 < o.min_shadow_pixels) return std::nullopt;
  const Eigen::Vector2d sc =
      camera.normalise(static_cast<double>(s.m10) / static_cast<double>(s.m00),
                       static_cast<double>(s.m01) / static_cast<double>(s.m00));
  const Eigen::Vector2d off(sc.x() - disc.cx, sc.y() - disc.cy);
  if (!(off.norm() >= o.min_shadow_offset * disc.b)) return std::nullopt;
  return off;
}

// Resolve beta between psi and psi - pi (eq. 13-14) by the shadow side: with
// the swing removed the shadow lies toward (sin beta, -cos beta) in the image.
void resolve_beta_by_shadow(const FrameMoments& m, const CameraModel& camera, const PoseOptions& o,
                            double psi, PatternPose& p) {
  const auto off = shadow_offset(m, camera, p.ellipse, o);
  p.beta_rad = wrap_pi(psi - o.swing_rad);  // candidate l = 0
  if (!off) {
    p.beta_resolved = false;
    p.status = p.theta_rad > o.small_theta_rad ? PatternStatus::ambiguous : PatternStatus::ok;
    return;
  }
  // Rotate the offset into the swing-free image.
  const double cs = std::cos(o.swing_rad), sn = std::sin(o.swing_rad);
  const Eigen::Vector2d d(cs * off->x() + sn * off->y(), -sn * off->x() + cs * off->y());
  const double b0 = wrap_pi(psi - o.swing_rad);
  const double score = d.x() * std::sin(b0) - d.y() * std::cos(b0);
  p.beta_rad = score >= 0.0 ? b0 : wrap_pi(b0 - kPi);
  p.beta_resolved = true;
  p.status = PatternStatus::ok;
}

// Centre and normal in camera coordinates from D, theta, beta, for a camera
// that looks at the disc centre along the ellipse centre's ray (moment and
// projection methods).
void fill_camera_frame(const Ellipse& e, const PoseOptions& o, PatternPose& p) {
  const Eigen::Vector3d ray = Eigen::Vector3d(e.cx, e.cy, 1.0).normalized();
  p.centre_cam = p.d_m * ray;
  // The normal makes theta with the ray back to the camera; its tilt
  // direction is beta from the up vector around that ray.
  const Eigen::Vector3d back = -ray;
  Eigen::Vector3d up = o.up_cam - o.up_cam.dot(back) * back;
  if (up.norm() < 1e-9) return;
  up.normalize();
  const Eigen::Vector3d right = up.cross(back);  // x_p for a frontal view
  // Camera seen from the disc at (sin t sin b, sin t cos b, cos t) in (x_p, y_p, z_p):
  // the normal is the rotation of `back` that makes this true.
  const double st = std::sin(p.theta_rad), ct = std::cos(p.theta_rad);
  const double sb = std::sin(p.beta_rad), cb = std::cos(p.beta_rad);
  p.normal_cam = (ct * back - st * (sb * right + cb * up)).normalized();
}

}  // namespace

std::string_view to_string(PatternStatus s) {
  switch (s) {
    case PatternStatus::ok:
      return "ok";
    case PatternStatus::no_pattern:
      return "no_pattern";
    case PatternStatus::partial:
      return "partial";
    case PatternStatus::unreadable:
      return "unreadable";
    case PatternStatus::ambiguous:
      return "ambiguous";
    case PatternStatus::degenerate:
      return "degenerate";
    case PatternStatus::unknown_pattern:
      return "unknown_pattern";
    case PatternStatus::uncalibrated:
      return "uncalibrated";
  }
  return "unknown";
}

namespace {
// The disc's ellipse from its moments, or nullopt with p.status telling why:
// too few disc pixels (status left as is: no pattern) or a degenerate region.
std::optional<Ellipse> disc_ellipse(const FrameMoments& m, const CameraModel& camera,
                                    const PoseOptions& o, PatternPose& p) {
  if (m[kDisc].m00 < o.min_disc_pixels) return std::nullopt;
  auto e = ellipse_from_moments(m[kDisc], camera);
  if (!e) p.status = PatternStatus::degenerate;
  return e;
}
}  // namespace

PatternPose moment_method(const FrameMoments& m, const CameraModel& camera, const PoseOptions& o) {
  PatternPose p;
  const auto e = disc_ellipse(m, camera, o, p);
  if (!e) return p;
  p.ellipse = *e;
  p.d_m = o.radius_m / e->b;                                   // eq. 6
  p.theta_rad = std::acos(std::clamp(e->a / e->b, 0.0, 1.0));  // eq. 10
  // Eq. 13 (psi = beta) holds only for beta in {0, +-90, 180} deg: the minor
  // axis is the image of the wall normal, whose image angle obeys
  // tan(psi) = tan(beta) / cos(theta) (docs/seed_errata.md). Inverted here.
  const double psi_wall = std::atan2(std::cos(p.theta_rad) * std::sin(e->psi), std::cos(e->psi));
  resolve_beta_by_shadow(m, camera, o, std::fmod(psi_wall + 2.0 * kPi, kPi), p);  // eq. 13-14
  fill_camera_frame(*e, o, p);
  return p;
}

PatternPose projection_method(const Extents& disc, const FrameMoments& m, const CameraModel& camera,
                              const PoseOptions& o) {
  PatternPose p;
  if (disc.empty()) return p;
  const auto e = disc_ellipse(m, camera, o, p);
  if (!e) return p;
  p.ellipse = *e;
  // Pixel counts of the projections (eq. 39, 49): N = max - min + 1.
  const double nb = disc.v_max - disc.v_min + 1, na = disc.u_max - disc.u_min + 1;
  const double b = 0.5 * nb / camera.fy(), a = 0.5 * na / camera.fx();
  p.d_m = o.radius_m / b;                                // eq. 40
  p.theta_rad = std::acos(std::clamp(a / b, 0.0, 1.0));  // eq. 49; a > b clips to 0
  p.ellipse.a = a;
  p.ellipse.b = b;
  // beta = +-90 deg: the shadow's side along x (Section IV).
  const auto off = shadow_offset(m, camera, p.ellipse, o);
  if (!off) {
    p.beta_rad = kPi / 2;
    p.beta_resolved = false;
    p.status = p.theta_rad > o.small_theta_rad ? PatternStatus::ambiguous : PatternStatus::ok;
  } else {
    p.beta_rad = off->x() >= 0.0 ? kPi / 2 : -kPi / 2;
    p.beta_resolved = true;
    p.status = PatternStatus::ok;
  }
  fill_camera_frame(*e, o, p);
  return p;
}

PatternPose conic_method(const FrameMoments& m, const CameraModel& camera, const PoseOptions& o) {
  PatternPose p;
  const auto e = disc_ellipse(m, camera, o, p);
  if (!e) return p;
  return conic_method(*e, m, camera, o);
}

PatternPose conic_method(const Ellipse& ellipse, const FrameMoments& m, const CameraModel& camera,
                         const PoseOptions& o) {
  PatternPose p;
  const Ellipse* e = &ellipse;
  p.ellipse = *e;
  const auto poses = circle_poses_from_conic(conic_from_ellipse(*e), o.radius_m);
  if (poses.empty()) {
    p.status = PatternStatus::degenerate;
    return p;
  }
  // For each solution: the predicted image offset of the side wall's middle
  // (rim point toward the camera, half-way back to the wall) from the disc's
  // image centroid; keep the one that points like the measured shadow.
  const auto off = shadow_offset(m, camera, *e, o);
  std::size_t best = 0;
  double best_score = -2.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector3d& c = poses[k].centre;
    const Eigen::Vector3d& n = poses[k].normal;
    Eigen::Vector3d toward = -c - (-c).dot(n) * n;
    double score = 0.0;
    if (toward.norm() > 1e-12 && off) {
      toward.normalize();
      const Eigen::Vector3d s = c + (o.radius_m + o.rim_m) * toward - 0.5 * o.thickness_m * n;
      const Eigen::Vector2d pred(s.x() / s.z() - e->cx, s.y() / s.z() - e->cy);
      score = pred.norm() > 0.0 ? pred.dot(*off) / (pred.norm() * off->norm()) : 0.0;
    }
    if (score > best_score) {
      best_score = score;
      best = k;
    }
  }
  const CirclePose& cp = poses[best];
  p.centre_cam = cp.centre;
  p.normal_cam = cp.normal;
  const auto axes = pattern_axes_cam(cp.normal, o.up_cam);
  if (!axes) {
    p.status = PatternStatus::degenerate;
    return p;
  }
  spherical_from_pose(cp.centre, *axes, p);
  const bool two = poses.size() == 2;
  p.beta_resolved = !two || (off.has_value() && best_score > 0.0);
  p.status = p.beta_resolved || p.theta_rad <= o.small_theta_rad ? PatternStatus::ok
                                                                 : PatternStatus::ambiguous;
  return p;
}

}  // namespace ceilnav::host::pattern
