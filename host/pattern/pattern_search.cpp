#include "host/pattern/pattern_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

namespace ceilnav::host::pattern {

double pattern_angle_rad(const ScanParams& p) {
  if (!(p.d_min_m > 0.0) || !(p.pattern_half_width_m >= 0.0)) return 0.0;
  return 2.0 * std::atan(p.pattern_half_width_m / p.d_min_m);
}

double motion_angle_rad(const ScanParams& p) {
  if (!(p.d_min_m > 0.0) || !(p.video_rate_hz > 0.0)) return 0.0;
  return std::atan(std::abs(p.robot_speed_mps) / (p.video_rate_hz * p.d_min_m));
}

double max_pan_rate(const ScanParams& p) {
  if (!(p.video_rate_hz > 0.0) || !(p.fov_rad > 0.0)) return 0.0;
  const double per_frame = p.fov_rad - pattern_angle_rad(p) - motion_angle_rad(p);
  return std::max(0.0, per_frame) * p.video_rate_hz;
}

namespace {

// Unit direction of (pan, tilt): x forward at pan 0, y left, z up.
Eigen::Vector3d direction(double pan, double tilt) {
  return {std::cos(tilt) * std::cos(pan), std::cos(tilt) * std::sin(pan), std::sin(tilt)};
}

}  // namespace

bool cone_in_view(const PanTilt& at, double hfov_rad, double vfov_rad, const PanTilt& direction_pt,
                  double r_rad) {
  const Eigen::Vector3d f = direction(at.pan_rad, at.tilt_rad);
  const Eigen::Vector3d right(std::sin(at.pan_rad), -std::cos(at.pan_rad), 0.0);
  const Eigen::Vector3d up = right.cross(f);
  const Eigen::Vector3d g = direction(direction_pt.pan_rad, direction_pt.tilt_rad);
  const double x = g.dot(right), y = g.dot(up), z = g.dot(f);
  // Inward normals of the edge planes x = +-z tan(h/2), y = +-z tan(v/2).
  const double ch = std::cos(0.5 * hfov_rad), sh = std::sin(0.5 * hfov_rad);
  const double cv = std::cos(0.5 * vfov_rad), sv = std::sin(0.5 * vfov_rad);
  const double margin = std::sin(r_rad);
  return -x * ch + z * sh >= margin && x * ch + z * sh >= margin && -y * cv + z * sv >= margin &&
         y * cv + z * sv >= margin;
}

std::vector<PanTilt> helical_scan(const HelicalParams& p) {
  const ScanParams sp{p.hfov_rad, p.video_rate_hz, p.pattern_half_width_m, p.d_min_m,
                      p.robot_speed_mps};
  const double lost = pattern_angle_rad(sp) + motion_angle_rad(sp);
  const double free_p = p.hfov_rad - lost, free_t = p.vfov_rad - lost;
  if (!(p.fraction > 0.0) || !(free_p > 0.0) || !(free_t > 0.0) || !(p.tilt_range_rad >= 0.0) ||
      !(std::abs(p.tilt0_rad) + p.tilt_range_rad <= p.max_abs_tilt_rad) ||
      !(p.max_abs_tilt_rad < 0.5 * std::numbers::pi)) {
    return {};
  }
  // The footprint in (pan, tilt): the largest box, a fraction of the free
  // fields, whose every direction has the pattern's cone inside the view of a
  // camera at its centre, for every camera tilt the scan uses (at a tilt the
  // image's edges are great circles, not lines of constant pan and tilt).
  auto box_fits = [&](double hp, double ht) {
    for (int i = 0; i <= 10; ++i) {
      const double tc = p.tilt0_rad + p.tilt_range_rad * (i - 5) / 5.0;
      for (int su = -1; su <= 1; ++su) {
        for (int sv = -1; sv <= 1; ++sv) {
          if (!cone_in_view({0.0, tc}, p.hfov_rad, p.vfov_rad, {su * hp, tc + sv * ht},
                            0.5 * lost)) {
            return false;
          }
        }
      }
    }
    return true;
  };
  double scale = 1.0;
  while (scale > 0.05 && !box_fits(0.5 * scale * free_p, 0.5 * scale * free_t)) scale *= 0.98;
  if (!(scale > 0.05)) return {};
  const double foot_p = scale * free_p, foot_t = scale * free_t;
  const double pitch_p = p.fraction * foot_p, pitch_t = p.fraction * foot_t;
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const double need_p = std::numbers::pi, need_t = p.tilt_range_rad;
  std::vector<PanTilt> out;
  double phi = 0.0;
  for (;;) {
    const double a_p = pitch_p * phi / kTwoPi;
    const double a_t = pitch_t * phi / kTwoPi;
    // The tilt is held at the range's edges (the helix slides along them).
    out.push_back({p.pan0_rad + a_p * std::cos(phi),
                   p.tilt0_rad + std::clamp(a_t * std::sin(phi), -need_t, need_t)});
    // Done when the pan amplitude has passed half a turn and the helix
    // reaches the tilt range's edges at the back (pan0 +- 180 deg) too.
    const double back = std::min(1.0, need_p / a_p);
    if (a_p >= need_p && a_t * std::sqrt(1.0 - back * back) >= need_t) break;
    // The next frame moves at most kHelixFraction of the free field in the
    // footprint's units: |d(pan / F_p, tilt / F_t) / d phi| is at most the
    // bound below.
    const double rate =
        std::hypot((a_p + pitch_p / kTwoPi) / free_p, (a_t + pitch_t / kTwoPi) / free_t);
    phi += std::min(0.25 * std::numbers::pi, p.fraction / rate);
  }
  return out;
}

double shadow_width_px(double thickness_m, double outer_radius_m, double f_px, double d_m,
                       double theta_rad) {
  const double s = d_m * std::sin(theta_rad), h = d_m * std::cos(theta_rad);
  if (!(thickness_m > 0.0) || !(s > outer_radius_m) || !(h > 0.0)) return 0.0;
  // In the plane of the axis and the camera (x along the camera's foot, z
  // out of the wall), camera at (s, h) looking at the origin: the side
  // wall's top edge (R', 0) and its bottom (R', -T).
  const Eigen::Vector2d c(s, h), axis = -c.normalized();
  auto image_x = [&](const Eigen::Vector2d& q) {
    const Eigen::Vector2d v = q - c;
    const double along = v.dot(axis);
    const double across = v.x() * axis.y() - v.y() * axis.x();
    return f_px * across / along;
  };
  return std::abs(image_x({outer_radius_m, -thickness_m}) - image_x({outer_radius_m, 0.0}));
}

double min_thickness_m(double n_px, double outer_radius_m, double f_px, double d_max_m,
                       double delta_theta_rad) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!(n_px > 0.0)) return 0.0;
  double lo = 0.0, hi = 100.0;
  if (shadow_width_px(hi, outer_radius_m, f_px, d_max_m, delta_theta_rad) < n_px) return kInf;
  for (int i = 0; i < 200 && hi - lo > 1e-12; ++i) {
    const double mid = 0.5 * (lo + hi);
    (shadow_width_px(mid, outer_radius_m, f_px, d_max_m, delta_theta_rad) < n_px ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace ceilnav::host::pattern
