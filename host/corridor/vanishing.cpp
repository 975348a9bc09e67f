#include "host/corridor/vanishing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "host/corridor/corridor_model.hpp"

namespace ceilnav::host::corridor {
namespace {

constexpr double kPi = std::numbers::pi;

// R(0, theta, psi)^T P: the rows of R(0, theta, 0) are right (0, -1, 0),
// down (sin theta, 0, -cos theta), forward (cos theta, 0, sin theta); the
// swing is [c s 0; -s c 0; 0 0 1] on the left.
Eigen::Vector3d unpan(const Eigen::Vector3d& p, const CameraMount& m) {
  const double ct = std::cos(m.tilt_rad), st = std::sin(m.tilt_rad);
  const double cs = std::cos(m.swing_rad), ss = std::sin(m.swing_rad);
  Eigen::Matrix3d r0;
  r0 << 0.0, -1.0, 0.0, st, 0.0, -ct, ct, 0.0, st;
  Eigen::Matrix3d roll;
  roll << cs, ss, 0.0, -ss, cs, 0.0, 0.0, 0.0, 1.0;
  return (roll * r0).transpose() * p;
}

// An angle mod 180 deg into (-90, 90].
double half_turn(double a) {
  a = std::remainder(a, kPi);
  return a <= -0.5 * kPi ? a + kPi : a;
}

Direction direction_of(const Eigen::Vector3d& w, bool axis) {
  Direction d;
  d.pan_rad = half_turn(axis ? std::atan2(-w.y(), w.x()) : std::atan2(w.x(), w.y()));
  d.elevation_rad = std::atan2(w.z(), std::hypot(w.x(), w.y()));
  return d;
}

ImagePoint to_pixels(const CameraConfig& camera, const Eigen::Vector3d& n) {
  ImagePoint p;
  const Eigen::Vector3d h(camera.fx() * n.x() + camera.cx() * n.z(),
                          camera.fy() * n.y() + camera.cy() * n.z(), n.z());
  if (std::abs(h.z()) <= 1e-12 * h.head<2>().norm()) {
    p.finite = false;
    p.direction = h.head<2>().normalized();
  } else {
    p.finite = true;
    p.px = h.head<2>() / h.z();
  }
  return p;
}

// The plane through the camera centre of an image line, unit normal: the
// line (a, b, c) on pixels is K^T-mapped to normalised coordinates.
Eigen::Vector3d plane_of(const ImageLine& l, const CameraConfig& camera) {
  const Eigen::Vector3d h = l.homogeneous();
  const Eigen::Vector3d n(h.x() * camera.fx(), h.y() * camera.fy(),
                          h.x() * camera.cx() + h.y() * camera.cy() + h.z());
  return n.normalized();
}

}  // namespace

const char* to_string(PanStatus s) {
  switch (s) {
    case PanStatus::ok:
      return "ok";
    case PanStatus::one_point:
      return "one-point";
    case PanStatus::not_found:
      return "not-found";
  }
  return "?";
}

ImagePoint axis_vanishing_point(const CameraConfig& camera, double pan_rad, const CameraMount& m) {
  // R (1, 0, 0) before the swing, then the swing (see the header).
  const double cp = std::cos(pan_rad), sp = std::sin(pan_rad);
  const double ct = std::cos(m.tilt_rad), st = std::sin(m.tilt_rad);
  const double cs = std::cos(m.swing_rad), ss = std::sin(m.swing_rad);
  const Eigen::Vector3d n(cs * sp + ss * st * cp, cs * st * cp - ss * sp, ct * cp);
  return to_pixels(camera, n);
}

ImagePoint cross_vanishing_point(const CameraConfig& camera, double pan_rad, const CameraMount& m) {
  const double cp = std::cos(pan_rad), sp = std::sin(pan_rad);
  const double ct = std::cos(m.tilt_rad), st = std::sin(m.tilt_rad);
  const double cs = std::cos(m.swing_rad), ss = std::sin(m.swing_rad);
  const Eigen::Vector3d n(ss * st * sp - cs * cp, ss * cp + cs * st * sp, ct * sp);
  return to_pixels(camera, n);
}

Direction axis_pan_of(const Eigen::Vector3d& p, const CameraMount& m) {
  return direction_of(unpan(p, m), true);
}

Direction cross_pan_of(const Eigen::Vector3d& p, const CameraMount& m) {
  return direction_of(unpan(p, m), false);
}

VanishingLinePan pan_from_vanishing_line(const Eigen::Vector3d& axis_n,
                                         const Eigen::Vector3d& cross_n, const CameraMount& m,
                                         double predicted_pan_rad) {
  // Coordinate along the horizon (cos psi, -sin psi) of a homogeneous point:
  // A = cos psi X - sin psi Y, the point's coordinate A / Z. Then
  //   s = cos theta (A_a / Z_a - A_c / Z_c)
  //   1 / s = Z_a Z_c / (cos theta (A_a Z_c - A_c Z_a)) = sin 2 phi / 2.
  const double cs = std::cos(m.swing_rad), ss = std::sin(m.swing_rad);
  const double aa = cs * axis_n.x() - ss * axis_n.y();
  const double ac = cs * cross_n.x() - ss * cross_n.y();
  const double num = axis_n.z() * cross_n.z();
  const double den = std::cos(m.tilt_rad) * (aa * cross_n.z() - ac * axis_n.z());
  VanishingLinePan out;
  double sin2 = den == 0.0 ? 0.0 : 2.0 * num / den;
  if (std::abs(sin2) > 1.0) {
    out.clamped = true;
    sin2 = std::clamp(sin2, -1.0, 1.0);
  }
  // eq. 14's two roots tan phi = (s -+ sqrt(s^2 - 4)) / 2: phi1 and
  // sign(s) 90 deg - phi1 (tan phi2 = 1 / tan phi1).
  const double phi1 = 0.5 * std::asin(sin2);
  const double phi2 = (sin2 >= 0.0 ? 0.5 : -0.5) * kPi - phi1;
  out.roots[0] = phi1;
  out.roots[1] = phi2;
  out.chosen =
      std::abs(phi1 - predicted_pan_rad) <= std::abs(phi2 - predicted_pan_rad) ? phi1 : phi2;
  return out;
}

VanishingEstimate find_vanishing_point(const std::vector<ImageLine>& lines,
                                       const CameraConfig& camera, const CameraMount& m,
                                       bool axis_direction, double predicted_pan_rad,
                                       const VanishingParams& params) {
  VanishingEstimate out;
  const int n = static_cast<int>(lines.size());
  std::vector<Eigen::Vector3d> planes;
  planes.reserve(lines.size());
  for (const ImageLine& l : lines) planes.push_back(plane_of(l, camera));
  auto dir = [&](const Eigen::Vector3d& p) {
    return axis_direction ? axis_pan_of(p, m) : cross_pan_of(p, m);
  };
  auto in_window = [&](const Direction& d) {
    return std::abs(half_turn(d.pan_rad - predicted_pan_rad)) <= params.pan_window_rad &&
           std::abs(d.elevation_rad) <= params.horizon_window_rad;
  };
  // Candidates: the lines of the intersections in the window (section 3.3).
  std::vector<bool> candidate(lines.size(), false);
  for (int i = 0; i < n; ++i) {
    for (int k = i + 1; k < n; ++k) {
      const Eigen::Vector3d p =
          planes[static_cast<size_t>(i)].cross(planes[static_cast<size_t>(k)]);
      if (p.norm() < 1e-9) continue;  // the same line
      if (!in_window(dir(p.normalized()))) continue;
      candidate[static_cast<size_t>(i)] = candidate[static_cast<size_t>(k)] = true;
    }
  }
  std::vector<int> idx;
  for (int i = 0; i < n; ++i) {
    if (candidate[static_cast<size_t>(i)]) idx.push_back(i);
  }
  if (static_cast<int>(idx.size()) <
      std::max(2, axis_direction ? params.min_axis_lines : params.min_cross_lines)) {
    return out;
  }
  // Angular least squares, re-weighted: weights strength x Tukey biweight.
  std::vector<double> w(idx.size(), 1.0);
  Eigen::Vector3d p(0.0, 0.0, 1.0);
  const double tukey_c = 3.0 * params.inlier_rad;
  for (int iter = 0; iter < 5; ++iter) {
    Eigen::Matrix3d m3 = Eigen::Matrix3d::Zero();
    double wsum = 0.0;
    for (size_t k = 0; k < idx.size(); ++k) {
      const Eigen::Vector3d& l = planes[static_cast<size_t>(idx[k])];
      const double s = std::max(lines[static_cast<size_t>(idx[k])].strength, 1e-9);
      m3 += w[k] * s * l * l.transpose();
      wsum += w[k] * s;
    }
    if (!(wsum > 0.0)) return out;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m3);
    p = es.eigenvectors().col(0);
    for (size_t k = 0; k < idx.size(); ++k) {
      const double r =
          std::asin(std::min(1.0, std::abs(planes[static_cast<size_t>(idx[k])].dot(p))));
      const double u = r / tukey_c;
      w[k] = u < 1.0 ? (1.0 - u * u) * (1.0 - u * u) : 0.0;
    }
  }
  double sum = 0.0, wsum = 0.0;
  for (size_t k = 0; k < idx.size(); ++k) {
    const double r = std::asin(std::min(1.0, std::abs(planes[static_cast<size_t>(idx[k])].dot(p))));
    if (r <= params.inlier_rad) {
      out.inliers.push_back(idx[k]);
      const double s = std::max(lines[static_cast<size_t>(idx[k])].strength, 1e-9);
      sum += s * r * r;
      wsum += s;
    }
  }
  out.normalised = p;
  out.point = to_pixels(camera, p);
  out.direction = dir(p);
  out.residual_rad = wsum > 0.0 ? std::sqrt(sum / wsum) : 0.0;
  // The share is of the lines the vertical direction does not explain: the
  // images of vertical edges (door jambs, corners) pass through its
  // vanishing point, which the tilt and swing alone fix (no pan), and are
  // part of any building, not evidence against the corridor's axis.
  const Eigen::Vector3d up =
      world_to_camera(0.0, m.tilt_rad, m.swing_rad) * Eigen::Vector3d::UnitZ();
  double total = 0.0;
  for (int i = 0; i < n; ++i) {
    const bool vertical =
        std::asin(std::min(1.0, std::abs(planes[static_cast<size_t>(i)].dot(up)))) <=
        params.inlier_rad;
    if (axis_direction && vertical &&
        std::find(out.inliers.begin(), out.inliers.end(), i) == out.inliers.end()) {
      continue;
    }
    total += std::max(lines[static_cast<size_t>(i)].strength, 1e-9);
  }
  out.support = wsum / total;
  const int need = axis_direction ? params.min_axis_lines : params.min_cross_lines;
  out.found =
      static_cast<int>(out.inliers.size()) >= std::max(2, need) &&
      out.support >= (axis_direction ? params.min_axis_support : params.min_cross_support) &&
      out.residual_rad <= params.max_residual_rad && in_window(out.direction);
  return out;
}

PanEstimate estimate_pan(const std::vector<ImageLine>& lines, const CameraConfig& camera,
                         const CameraMount& m, double predicted_pan_rad,
                         const VanishingParams& params) {
  PanEstimate out;
  out.axis = find_vanishing_point(lines, camera, m, true, predicted_pan_rad, params);
  out.cross = find_vanishing_point(lines, camera, m, false, predicted_pan_rad, params);
  if (out.axis.found) out.axis_pan_rad = out.axis.direction.pan_rad;
  if (out.cross.found) out.cross_pan_rad = out.cross.direction.pan_rad;
  if (out.axis.found && out.cross.found) {
    out.status = PanStatus::ok;
    out.line =
        pan_from_vanishing_line(out.axis.normalised, out.cross.normalised, m, predicted_pan_rad);
    out.line_pan_rad = out.line.chosen;
    out.pan_rad = params.source == PanSource::vanishing_line ? out.line_pan_rad : out.axis_pan_rad;
  } else if (out.axis.found || out.cross.found) {
    // Single-point fallback (section 3.3, eq. 11 or 10 with 16).
    out.status = PanStatus::one_point;
    out.pan_rad = out.axis.found ? out.axis_pan_rad : out.cross_pan_rad;
  } else {
    return out;
  }
  out.heading_rad = vehicle_heading(out.pan_rad, m);
  return out;
}

}  // namespace ceilnav::host::corridor
