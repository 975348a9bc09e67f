#include "host/pattern/pattern_pose.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

namespace ceilnav::host::pattern {
namespace {

constexpr double kPi = std::numbers::pi;

double wrap_pi(double a) {
  return std::remainder(a, 2.0 * kPi);
}

// Pattern frame (x right, y up, z toward the viewer) of the circle pose
// (centre c, normal n toward the camera) given the world vertical in camera
// coordinates: columns x_p, y_p, z_p in camera coordinates.
std::optional<Eigen::Matrix3d> pattern_axes_cam(const Eigen::Vector3d& n,
                                                const Eigen::Vector3d& up) {
  Eigen::Vector3d y = up - up.dot(n) * n;
  if (!(y.norm() > 1e-9)) return std::nullopt;
  y.normalize();
  Eigen::Matrix3d a;
  a.col(0) = y.cross(n);
  a.col(1) = y;
  a.col(2) = n;
  return a;
}

// D, theta, beta of the camera from the circle pose (camera at the origin).
void spherical_from_pose(const Eigen::Vector3d& c, const Eigen::Matrix3d& axes, PatternPose& p) {
  const Eigen::Vector3d cam = axes.transpose() * (-c);  // camera in the pattern frame
  p.d_m = cam.norm();
  p.theta_rad = std::acos(std::clamp(cam.z() / p.d_m, -1.0, 1.0));
  p.beta_rad = std::atan2(cam.x(), cam.y());
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
  }
  return "unknown";
}

FrameMoments device_moments(const stream::ClassMomentResults& r) {
  FrameMoments out{};
  for (int c = 1; c < kClasses; ++c) {
    const auto& m = r.of(c);
    auto as_int = [](uint64_t v) { return static_cast<int64_t>(v); };
    out[static_cast<std::size_t>(c)] = {as_int(m[stream::kM00]), as_int(m[stream::kM10]),
                                        as_int(m[stream::kM01]), as_int(m[stream::kM20]),
                                        as_int(m[stream::kM11]), as_int(m[stream::kM02])};
  }
  return out;
}

Extents disc_extents_from_runs(std::span<const stream::RunRecord> disc_runs) {
  Extents e;
  bool any = false;
  for (const auto& r : disc_runs) {
    if (!any) {
      e = {r.x_start, r.x_end, r.row, r.row};
      any = true;
      continue;
    }
    e.u_min = std::min<int>(e.u_min, r.x_start);
    e.u_max = std::max<int>(e.u_max, r.x_end);
    e.v_min = std::min<int>(e.v_min, r.row);
    e.v_max = std::max<int>(e.v_max, r.row);
  }
  return e;
}

FrameMoments class_moments(const uint8_t* classes, int width, int height, std::size_t stride) {
  FrameMoments m{};
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = classes + static_cast<std::size_t>(y) * stride;
    std::array<int64_t, kClasses> n{}, sx{}, sxx{};
    for (int x = 0; x < width; ++x) {
      const unsigned c = row[x];
      if (c >= kClasses) continue;
      ++n[c];
      sx[c] += x;
      sxx[c] += static_cast<int64_t>(x) * x;
    }
    for (std::size_t c = 0; c < kClasses; ++c) {
      m[c].m00 += n[c];
      m[c].m10 += sx[c];
      m[c].m01 += n[c] * y;
      m[c].m20 += sxx[c];
      m[c].m11 += sx[c] * y;
      m[c].m02 += n[c] * static_cast<int64_t>(y) * y;
    }
  }
  return m;
}

Extents class_extents(const uint8_t* classes, int width, int height, std::size_t stride, int cls) {
  Extents e{width, -1, height, -1};
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = classes + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < width; ++x) {
      if (row[x] != cls) continue;
      e.u_min = std::min(e.u_min, x);
      e.u_max = std::max(e.u_max, x);
      e.v_min = std::min(e.v_min, y);
      e.v_max = std::max(e.v_max, y);
    }
  }
  if (e.u_max < 0) return Extents{};
  return e;
}

namespace {

// Centroid and covariance (pixels) -> normalised: the centroid through the
// model, the covariance through the Jacobian of the undistortion there
// (central differences, 1 px).
bool to_normalised(const CameraModel& camera, double u, double v, const Eigen::Matrix2d& cov_px,
                   Eigen::Vector2d& c, Eigen::Matrix2d& cov) {
  c = camera.normalise(u, v);
  Eigen::Matrix2d jac;
  jac.col(0) = 0.5 * (camera.normalise(u + 1.0, v) - camera.normalise(u - 1.0, v));
  jac.col(1) = 0.5 * (camera.normalise(u, v + 1.0) - camera.normalise(u, v - 1.0));
  cov = jac * cov_px * jac.transpose();
  return cov.allFinite() && c.allFinite();
}

// Area, centroid and central second moments (pixels) of the region bounded by
// the lens-distorted image of the ellipse (c, cov) given in normalised
// coordinates: a 720-gon through the model, moments by Green's theorem.
bool distorted_region_moments(const CameraModel& camera, const Eigen::Vector2d& c,
                              const Eigen::Matrix2d& cov, double& u, double& v,
                              Eigen::Matrix2d& cov_px) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  if (!(es.eigenvalues()(0) > 0.0)) return false;
  const Eigen::Vector2d ax0 = 2.0 * std::sqrt(es.eigenvalues()(0)) * es.eigenvectors().col(0);
  const Eigen::Vector2d ax1 = 2.0 * std::sqrt(es.eigenvalues()(1)) * es.eigenvectors().col(1);
  constexpr int kVertices = 720;
  std::array<Eigen::Vector2d, kVertices> p;
  for (int k = 0; k < kVertices; ++k) {
    const double t = 2.0 * kPi * k / kVertices;
    p[static_cast<std::size_t>(k)] =
        camera.distort_to_pixel(c + std::cos(t) * ax1 + std::sin(t) * ax0);
    if (!p[static_cast<std::size_t>(k)].allFinite()) return false;
  }
  // Moments about the first vertex's neighbourhood (the mean) for precision.
  Eigen::Vector2d o = Eigen::Vector2d::Zero();
  for (const auto& q : p) o += q;
  o /= kVertices;
  double a = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (int k = 0; k < kVertices; ++k) {
    const Eigen::Vector2d p0 = p[static_cast<std::size_t>(k)] - o;
    const Eigen::Vector2d p1 = p[static_cast<std::size_t>((k + 1) % kVertices)] - o;
    const double cr = p0.x() * p1.y() - p1.x() * p0.y();
    a += cr;
    sx += cr * (p0.x() + p1.x());
    sy += cr * (p0.y() + p1.y());
    sxx += cr * (p0.x() * p0.x() + p0.x() * p1.x() + p1.x() * p1.x());
    syy += cr * (p0.y() * p0.y() + p0.y() * p1.y() + p1.y() * p1.y());
    sxy += cr * (p0.x() * p1.y() + 2.0 * p0.x() * p0.y() + 2.0 * p1.x() * p1.y() + p1.x() * p0.y());
  }
  a *= 0.5;
  if (!(std::abs(a) > 0.0)) return false;
  const double mx = sx / (6.0 * a), my = sy / (6.0 * a);
  cov_px(0, 0) = sxx / (12.0 * a) - mx * mx;
  cov_px(1, 1) = syy / (12.0 * a) - my * my;
  cov_px(0, 1) = cov_px(1, 0) = sxy / (24.0 * a) - mx * my;
  u = mx + o.x();
  v = my + o.y();
  return cov_px.allFinite();
}

}  // namespace

// Eq. 17-18: b, a = 2 sqrt(eigenvalues) (the seed's form divided by mu00 / 2);
// psi is the minor axis (eigenvector of the smaller eigenvalue) from image up
// toward +x, in [0, pi).
std::optional<Ellipse> ellipse_from_covariance(const Eigen::Vector2d& c,
                                               const Eigen::Matrix2d& cov) {
  const double tr = cov(0, 0) + cov(1, 1);
  const double disc = std::hypot(cov(0, 0) - cov(1, 1), 2.0 * cov(0, 1));
  const double l1 = 0.5 * (tr + disc), l2 = 0.5 * (tr - disc);
  if (!(l2 > 0.0)) return std::nullopt;
  Ellipse e;
  e.cx = c.x();
  e.cy = c.y();
  e.b = 2.0 * std::sqrt(l1);
  e.a = 2.0 * std::sqrt(l2);
  e.cov = cov;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  const Eigen::Vector2d minor = es.eigenvectors().col(0);
  e.psi = std::fmod(std::atan2(minor.x(), -minor.y()) + 2.0 * kPi, kPi);
  return e;
}

std::optional<Ellipse> ellipse_from_moments(const ClassMoments& m, const CameraModel& camera) {
  if (m.m00 < 5) return std::nullopt;
  const double n = static_cast<double>(m.m00);
  const double u = static_cast<double>(m.m10) / n, v = static_cast<double>(m.m01) / n;
  // Eq. 30-32 (divided by mu00): central second moments in pixels^2, plus
  // Sheppard's 1/12 px^2: the moments of pixel centres are those of the
  // region less the spread of one pixel (docs/pattern.md).
  const double c20 = static_cast<double>(m.m20) / n - u * u + 1.0 / 12.0;
  const double c11 = static_cast<double>(m.m11) / n - u * v;
  const double c02 = static_cast<double>(m.m02) / n - v * v + 1.0 / 12.0;
  Eigen::Matrix2d cov_px;
  cov_px << c20, c11, c11, c02;
  Eigen::Vector2d c;
  Eigen::Matrix2d cov;
  if (!to_normalised(camera, u, v, cov_px, c, cov)) return std::nullopt;
  if (camera.has_distortion()) {
    // The disc's image is an ellipse in undistorted coordinates, not in
    // pixels: refine (c, cov) until the distorted image of that ellipse has
    // the measured pixel moments (fixed point; the affine map above is the
    // first step).
    const Eigen::Vector2d c_meas = c;
    const Eigen::Matrix2d cov_meas = cov;
    for (int iteration = 0; iteration < 6; ++iteration) {
      double pu = 0, pv = 0;
      Eigen::Matrix2d pcov;
      Eigen::Vector2d pc;
      Eigen::Matrix2d pcn;
      if (!distorted_region_moments(camera, c, cov, pu, pv, pcov)) break;
      if (!to_normalised(camera, pu, pv, pcov, pc, pcn)) break;
      c += c_meas - pc;
      cov += cov_meas - pcn;
      if ((c_meas - pc).norm() < 1e-12 && (cov_meas - pcn).norm() < 1e-14) break;
    }
  }
  return ellipse_from_covariance(c, cov);
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

Eigen::Matrix3d conic_from_ellipse(const Ellipse& e) {
  // Uniform ellipse {x : (x - c)^T M (x - c) <= 1} has covariance M^-1 / 4.
  const Eigen::Matrix2d mm = (4.0 * e.cov).inverse();
  const Eigen::Vector2d c(e.cx, e.cy);
  Eigen::Matrix3d q;
  q.topLeftCorner<2, 2>() = mm;
  q.topRightCorner<2, 1>() = -mm * c;
  q.bottomLeftCorner<1, 2>() = (-mm * c).transpose();
  q(2, 2) = c.dot(mm * c) - 1.0;
  return q;
}

std::vector<CirclePose> circle_poses_from_conic(const Eigen::Matrix3d& q_in, double r) {
  std::vector<CirclePose> out;
  if (!q_in.allFinite() || !(r > 0.0)) return out;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (q_in + q_in.transpose()));
  Eigen::Vector3d lam = es.eigenvalues();  // ascending
  Eigen::Matrix3d v = es.eigenvectors();
  // Two eigenvalues of one sign, one of the other: make two positive.
  int positive = 0;
  for (int k = 0; k < 3; ++k) positive += lam[k] > 0.0;
  if (positive == 1) {
    lam = -lam;
    lam = Eigen::Vector3d(lam[2], lam[1], lam[0]);
    v = Eigen::Matrix3d(v.rowwise().reverse());
  } else if (positive != 2) {
    return out;
  }
  // Now lam ascending: lam[0] < 0 < lam[1] <= lam[2]. Name l1 >= l2 > 0 > l3.
  const double l1 = lam[2], l2 = lam[1], l3 = lam[0];
  if (!(l3 < 0.0 && l2 > 0.0)) return out;
  const Eigen::Vector3d e1 = v.col(2), e2 = v.col(1), e3 = v.col(0);
  // In the eigenbasis the cone is l1 x^2 + l2 y^2 + l3 z^2 = 0; Q - l2 I
  // factors into the planes sqrt(l1 - l2) x = +-sqrt(l2 - l3) z, and a plane
  // parallel to one of them cuts the cone in a circle (docs/pattern.md).
  const double g = std::sqrt(std::max(0.0, l1 - l2)), h = std::sqrt(l2 - l3);
  for (int sign : {1, -1}) {
    if (sign == -1 && g == 0.0) break;  // frontal circle: one solution
    const Eigen::Vector3d a(g * sign, 0.0, -h), b(g * sign, 0.0, h);
    // Plane a . X = 1 (eigenbasis): on the cone, l2 |X|^2 = -(a . X)(b . X) =
    // -(b . X): the sphere |X|^2 + (b . X) / l2 = 0, centre s = -b / (2 l2).
    const Eigen::Vector3d s = -b / (2.0 * l2);
    const double an2 = a.squaredNorm();
    const Eigen::Vector3d centre1 = s + ((1.0 - a.dot(s)) / an2) * a;
    const double dist2 = std::pow(1.0 - a.dot(s), 2) / an2;
    const double r1sq = s.squaredNorm() - dist2;
    if (!(r1sq > 0.0)) continue;
    double k = r / std::sqrt(r1sq);  // scale of the plane a . X = k
    Eigen::Vector3d centre = k * centre1;
    const Eigen::Vector3d centre_cam =
        v.col(2) * 0.0 + e1 * centre.x() + e2 * centre.y() + e3 * centre.z();
    Eigen::Vector3d c = centre_cam;
    if (c.z() < 0.0) c = -c;  // the other nappe: the circle in front of the camera
    Eigen::Vector3d n = (e1 * a.x() + e2 * a.y() + e3 * a.z()).normalized();
    if (n.dot(c) > 0.0) n = -n;  // toward the camera
    out.push_back({c, n});
  }
  return out;
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

std::pair<std::vector<stream::RunRecord>, std::vector<stream::RunRecord>> split_disc_runs(
    std::span<const stream::RunRecord> runs, const ClassMoments& disc) {
  std::pair<std::vector<stream::RunRecord>, std::vector<stream::RunRecord>> out;
  Eigen::Matrix2d shape_inv = Eigen::Matrix2d::Zero();
  double u = 0, v = 0;
  bool have = disc.m00 >= 5;
  if (have) {
    const double n = static_cast<double>(disc.m00);
    u = static_cast<double>(disc.m10) / n;
    v = static_cast<double>(disc.m01) / n;
    Eigen::Matrix2d cov;
    cov << static_cast<double>(disc.m20) / n - u * u + 1.0 / 12.0,
        static_cast<double>(disc.m11) / n - u * v, static_cast<double>(disc.m11) / n - u * v,
        static_cast<double>(disc.m02) / n - v * v + 1.0 / 12.0;
    // The ellipse x^T (4 cov)^-1 x <= 1, enlarged 1.1 x.
    const Eigen::Matrix2d shape = 4.0 * 1.21 * cov;
    have = shape.determinant() > 0.0 && shape(0, 0) > 0.0;
    if (have) shape_inv = shape.inverse();
  }
  for (const auto& r : runs) {
    const Eigen::Vector2d d(0.5 * (r.x_start + r.x_end) - u, static_cast<double>(r.row) - v);
    if (have && d.dot(shape_inv * d) <= 1.0) {
      out.first.push_back(r);
    } else {
      out.second.push_back(r);
    }
  }
  return out;
}

namespace {

// Fewer usable rows: the disc is too flat in the image for row chords (its
// edges shallow over most of the outline); the moments' ellipse is kept.
constexpr std::size_t kMinOutlineRows = 24;
// Rows whose chord needs a larger curvature correction (px) are left out.
constexpr double kMaxChordCorrection = 0.3;

// Integral of round(t) over [a, a + len] (round half up): t^2 / 2 less the
// periodic part (t - round(t))^2 / 2.
double round_integral(double a, double len) {
  auto prim = [](double t) {
    const double f = t - std::floor(t + 0.5);
    return 0.5 * t * t - 0.5 * f * f;
  };
  return prim(a + len) - prim(a);
}

}  // namespace

std::optional<Ellipse> ellipse_from_disc_runs(std::span<const stream::RunRecord> disc_runs,
                                              const ClassMoments& disc, uint32_t k, int width,
                                              double psf_sigma_px, const CameraModel& camera) {
  if (k == 0 || disc.m00 < 5 || disc_runs.size() < 12) return std::nullopt;
  const double n = static_cast<double>(disc.m00);
  const double u0 = static_cast<double>(disc.m10) / n, v0 = static_cast<double>(disc.m01) / n;
  const double c20 = static_cast<double>(disc.m20) / n - u0 * u0 + 1.0 / 12.0;
  const double c11 = static_cast<double>(disc.m11) / n - u0 * v0;
  const double c02 = static_cast<double>(disc.m02) / n - v0 * v0 + 1.0 / 12.0;
  Eigen::Matrix2d shape;  // x^T shape x = 1 on the outline (pixels)
  shape << 4.0 * c20, 4.0 * c11, 4.0 * c11, 4.0 * c02;
  if (!(shape.determinant() > 0.0)) return std::nullopt;
  const Eigen::Matrix2d mm = shape.inverse();
  const double m11 = mm(0, 0), det = mm.determinant();
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(2 * disc_runs.size());
  for (const auto& r : disc_runs) {
    if (r.x_start == 0 || r.x_end + 1 >= width || r.sum_w == 0) continue;
    const double y = static_cast<double>(r.row) - v0;
    // Half-width h(y) = sqrt(m11 - det y^2) / m11 about the chord's midpoint;
    // keep rows whose strip lies 1 px inside the top and bottom.
    const double g_lo = m11 - det * (std::abs(y) + 1.5) * (std::abs(y) + 1.5);
    if (!(g_lo > 0.0)) continue;
    const double g = m11 - det * y * y;
    const double h2 = (-det / std::sqrt(g) - det * det * y * y / (g * std::sqrt(g))) / m11;
    const double len_strip = static_cast<double>(r.sum_w) / k;
    const double s = static_cast<double>(r.sum_xw) / k;
    // Left edge a of [a, a + len] with integral of round(t) = s (monotone in a).
    double a = s / len_strip - 0.5 * len_strip;
    for (int it = 0; it < 20; ++it) {
      const double step = (s - round_integral(a, len_strip)) / len_strip;
      a += step;
      if (std::abs(step) < 1e-9) break;
    }
    // The strip's mean chord, through the lens's blur (Gaussian, psf_sigma_px
    // rows), is the centre line's plus chord'' (1 / 24 + sigma^2 / 2).
    const double bias = 2.0 * h2 * (1.0 / 24.0 + 0.5 * psf_sigma_px * psf_sigma_px);
    if (std::abs(bias) > kMaxChordCorrection) continue;
    const double len = len_strip - bias;
    a -= 0.5 * (len - len_strip);
    pts.push_back(camera.normalise(a, static_cast<double>(r.row)));
    pts.push_back(camera.normalise(a + len, static_cast<double>(r.row)));
  }
  if (pts.size() < 2 * kMinOutlineRows) return std::nullopt;
  // Conic A x^2 + B xy + C y^2 + D x + E y + F = 0 about the points' mean,
  // scaled; smallest singular vector, reweighted by 1 / |grad|^2 (Sampson).
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  double scale = 0.0;
  for (const auto& p : pts) scale += (p - mean).norm();
  scale = static_cast<double>(pts.size()) / scale;
  Eigen::VectorXd coef(6);
  std::vector<double> wts(pts.size(), 1.0);
  for (int pass = 0; pass < 4; ++pass) {
    Eigen::MatrixXd a_mat(pts.size(), 6);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector2d q = (pts[i] - mean) * scale;
      a_mat.row(static_cast<Eigen::Index>(i)) << q.x() * q.x(), q.x() * q.y(), q.y() * q.y(), q.x(),
          q.y(), 1.0;
      a_mat.row(static_cast<Eigen::Index>(i)) *= wts[i];
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a_mat, Eigen::ComputeThinV);
    coef = svd.matrixV().col(5);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Eigen::Vector2d q = (pts[i] - mean) * scale;
      const double gx = 2.0 * coef(0) * q.x() + coef(1) * q.y() + coef(3);
      const double gy = coef(1) * q.x() + 2.0 * coef(2) * q.y() + coef(4);
      wts[i] = 1.0 / std::max(1e-9, std::sqrt(gx * gx + gy * gy));
    }
  }
  // Back to normalised coordinates: centre and shape matrix.
  Eigen::Matrix2d mq;
  mq << coef(0), 0.5 * coef(1), 0.5 * coef(1), coef(2);
  if (!(mq.determinant() > 0.0)) return std::nullopt;
  const Eigen::Vector2d lin(coef(3), coef(4));
  const Eigen::Vector2d cq = -0.5 * mq.inverse() * lin;
  const double rhs = cq.dot(mq * cq) - coef(5);
  if (!(rhs / mq.trace() > 0.0)) return std::nullopt;
  // (q - cq)^T (mq / rhs) (q - cq) = 1, q = (x - mean) * scale.
  const Eigen::Matrix2d m_norm = mq / rhs * scale * scale;
  const Eigen::Vector2d c = mean + cq / scale;
  return ellipse_from_covariance(c, 0.25 * m_norm.inverse());
}

// ------------------------------------------------------------------ bar code

namespace {

constexpr int kBarsPerBlock = 6;
constexpr std::array<std::pair<int, int>, 10> kPairs{
    {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 2}, {1, 3}, {1, 4}, {2, 3}, {2, 4}, {3, 4}}};

// Edge positions in units from the block's outer end (wide bar first), 12 edges.
std::array<double, 2 * kBarsPerBlock> block_edges(int value) {
  std::array<double, 2 * kBarsPerBlock> e{};
  e[0] = 0.0;
  e[1] = 3.0;
  double x = 3.0;
  for (int k = 0; k < 5; ++k) {
    const auto [i, j] = kPairs[static_cast<std::size_t>(value)];
    const int w = (k == i || k == j) ? 2 : 1;
    x += 1.0;
    e[static_cast<std::size_t>(2 + 2 * k)] = x;
    x += w;
    e[static_cast<std::size_t>(3 + 2 * k)] = x;
  }
  return e;
}

// Least-squares fit of measured edges u (left, right alternating, image order)
// to model positions X (same order) by u = (a X + b) / (c X + 1) + s delta,
// s = +1 on left edges, -1 on right edges (threshold bias). Returns the RMS
// residual in units of the model (divided by the local scale du/dX).
double fit_residual(const std::array<double, 12>& u, const std::array<double, 12>& x) {
  Eigen::Matrix<double, 12, 4> a;
  Eigen::Matrix<double, 12, 1> rhs;
  for (int k = 0; k < 12; ++k) {
    const double s = (k % 2 == 0) ? 1.0 : -1.0;
    a(k, 0) = x[static_cast<std::size_t>(k)];
    a(k, 1) = 1.0;
    a(k, 2) = -x[static_cast<std::size_t>(k)] * u[static_cast<std::size_t>(k)];
    a(k, 3) = s;
    rhs(k) = u[static_cast<std::size_t>(k)];
  }
  const Eigen::Vector4d p = a.colPivHouseholderQr().solve(rhs);
  double sum = 0.0, scale = 0.0;
  for (int k = 0; k < 12; ++k) {
    const double xk = x[static_cast<std::size_t>(k)];
    const double den = p(2) * xk + 1.0;
    if (!(std::abs(den) > 1e-6)) return 1e9;
    const double pred = (p(0) * xk + p(1)) / den + ((k % 2 == 0) ? 1.0 : -1.0) * p(3);
    sum += std::pow(pred - u[static_cast<std::size_t>(k)], 2);
    scale += std::abs((p(0) - p(1) * p(2)) / (den * den));  // du/dX
  }
  scale /= 12.0;
  if (!(scale > 0.0) || !std::isfinite(sum)) return 1e9;
  return std::sqrt(sum / 12.0) / scale;
}

struct BlockRead {
  bool ok = false;
  bool left_type = false;  // wide bar on the left in the image
  int value = -1;
};

BlockRead decode_block(const std::array<double, 12>& u, const BarcodeOptions& o) {
  double best = 1e18, second = 1e18;
  BlockRead r;
  for (int type = 0; type < 2; ++type) {
    for (int v = 0; v < 10; ++v) {
      const auto e = block_edges(v);
      std::array<double, 12> x{};
      if (type == 0) {
        x = e;  // left block: outer end on the left, image order = model order
      } else {
        // Right block: outer end on the right; image order left to right is
        // the model reversed, with left/right edges swapped.
        for (int k = 0; k < 12; ++k)
          x[static_cast<std::size_t>(k)] = -e[static_cast<std::size_t>(11 - k)];
      }
      const double res = fit_residual(u, x);
      if (res < best) {
        second = best;
        best = res;
        r.left_type = type == 0;
        r.value = v;
      } else if (res < second) {
        second = res;
      }
    }
  }
  r.ok = best <= o.max_fit_residual && second >= o.min_fit_ratio * best;
  return r;
}

}  // namespace

BarcodeRead read_barcode(std::span<const stream::RunRecord> runs, const CameraModel& camera,
                         int image_width, const BarcodeOptions& o) {
  BarcodeRead out;
  if (runs.empty()) return out;
  std::map<int, std::vector<const stream::RunRecord*>> rows;
  for (const auto& r : runs) {
    if (o.bar_contrast > 0.0 && r.sum_w < o.min_bar_run_weight) continue;  // the disc's runs
    rows[r.row].push_back(&r);
  }
  std::map<int, int> votes;
  // Bar centres per decoded block, keyed by (side: 0 left, 1 right; value).
  std::map<std::pair<int, int>, std::vector<BarEdge>> block_edges_seen;
  int left_seen = 0, right_seen = 0, any_block = 0;
  for (auto& row_runs : rows) {
    // Not a structured binding: lambdas below capture the row (clang 14
    // cannot capture bindings).
    const int row = row_runs.first;
    auto& rs = row_runs.second;
    std::sort(rs.begin(), rs.end(),
              [](const auto* a, const auto* b) { return a->x_start < b->x_start; });
    // Edges in normalised x along the row; runs touching the border are cut.
    std::vector<std::array<double, 2>> bars;
    std::vector<std::array<Eigen::Vector2d, 2>> points;
    std::vector<bool> cut;
    for (const auto* r : rs) {
      // Sub-pixel edges from the run's ink: centre sum(x w) / sum(w), width
      // sum(w) / contrast (w = the bar's darkness below the plate); the
      // integer bounds when no contrast is configured.
      double u0 = r->x_start - 0.5, u1 = r->x_end + 0.5;
      if (o.bar_contrast > 0.0 && r->sum_w > 0) {
        const double centre = static_cast<double>(r->sum_xw) / static_cast<double>(r->sum_w);
        const double width = static_cast<double>(r->sum_w) / o.bar_contrast;
        u0 = centre - 0.5 * width;
        u1 = centre + 0.5 * width;
      }
      const Eigen::Vector2d l = camera.normalise(u0, row);
      const Eigen::Vector2d rr = camera.normalise(u1, row);
      bars.push_back({l.x(), rr.x()});
      points.push_back({l, rr});
      cut.push_back(r->x_start == 0 || r->x_end + 1 >= image_width);
    }
    // Split into blocks at gaps much larger than the median gap.
    std::vector<double> gaps;
    for (std::size_t k = 1; k < bars.size(); ++k) gaps.push_back(bars[k][0] - bars[k - 1][1]);
    std::vector<std::pair<std::size_t, std::size_t>> groups;  // [first, last]
    if (!gaps.empty()) {
      std::vector<double> sorted = gaps;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                       sorted.end());
      const double med = sorted[sorted.size() / 2];
      std::size_t first = 0;
      for (std::size_t k = 0; k < gaps.size(); ++k) {
        if (gaps[k] > 3.0 * med) {
          groups.emplace_back(first, k);
          first = k + 1;
        }
      }
      groups.emplace_back(first, bars.size() - 1);
    }
    std::vector<BlockRead> blocks;
    std::vector<std::size_t> block_first;
    for (const auto& [first, last] : groups) {
      if (last - first + 1 != kBarsPerBlock) continue;
      bool any_cut = false;
      for (std::size_t k = first; k <= last; ++k) any_cut = any_cut || cut[k];
      if (any_cut) continue;
      std::array<double, 12> u{};
      for (std::size_t k = 0; k < kBarsPerBlock; ++k) {
        u[2 * k] = bars[first + k][0];
        u[2 * k + 1] = bars[first + k][1];
      }
      const BlockRead b = decode_block(u, o);
      if (b.ok) {
        blocks.push_back(b);
        block_first.push_back(first);
      }
    }
    if (blocks.empty()) continue;
    ++any_block;
    // Bar centres (sum(x w) / sum(w): unbiased by the threshold and by the
    // ink-width estimate) with their pattern-frame x, kept per block for the
    // identity chosen below.
    auto keep_block = [&](std::size_t b) {
      const double u = o.bar_unit_m;
      const double outer = o.radius_m + o.bar_gap_m + 15.0 * u;
      const bool left = blocks[b].left_type;
      const auto e = block_edges(blocks[b].value);
      auto& dst = block_edges_seen[{left ? 0 : 1, blocks[b].value}];
      for (std::size_t k = 0; k < 6; ++k) {
        const auto& pts = points[block_first[b] + k];
        const Eigen::Vector2d mid = 0.5 * (pts[0] + pts[1]);
        const double x0 = left ? -outer + e[2 * k] * u : outer - e[11 - 2 * k] * u;
        const double x1 = left ? -outer + e[2 * k + 1] * u : outer - e[10 - 2 * k] * u;
        dst.push_back({mid.x(), mid.y(), x0, x1, row, pts[1].x() - pts[0].x()});
      }
    };
    if (blocks.size() == 2 && blocks[0].left_type && !blocks[1].left_type) {
      const int left = blocks[0].value, right = blocks[1].value;
      const int low = right / 2;
      if (right % 2 == (left + low) % 2) {
        ++votes[left * 5 + low];
        ++out.full_rows;
        keep_block(0);
        keep_block(1);
      } else {
        ++out.bad_rows;
      }
    } else if (blocks.size() == 1) {
      ++out.partial_rows;
      (blocks[0].left_type ? left_seen : right_seen)++;
      keep_block(0);  // used when its value is the identity's (a row need not cross both blocks)
    } else {
      ++out.bad_rows;  // inconsistent block order or count
    }
  }
  // The identity read: every row's block of the identity's values gives bar
  // centres, full rows or not (with the view slanted few rows cross both
  // blocks); rows at the ends of a block's bars are partly covered: left out.
  auto accept = [&](int identity) {
    out.status = PatternStatus::ok;
    out.identity = identity;
    const int left = identity / 5, low = identity % 5;
    const int right = 2 * low + (left + low) % 2;
    for (const auto& key : {std::pair{0, left}, std::pair{1, right}}) {
      const auto it = block_edges_seen.find(key);
      if (it == block_edges_seen.end()) continue;
      int first_row = 1 << 30, last_row = -1;
      for (const BarEdge& e : it->second) {
        first_row = std::min(first_row, e.row);
        last_row = std::max(last_row, e.row);
      }
      for (const BarEdge& e : it->second) {
        if (e.row > first_row + 2 && e.row < last_row - 2) out.edges.push_back(e);
      }
    }
    return out;
  };
  if (out.full_rows > 0) {
    auto best = std::max_element(votes.begin(), votes.end(),
                                 [](const auto& a, const auto& b) { return a.second < b.second; });
    const int agree = best->second;
    const int disagree = out.full_rows - agree + out.bad_rows;
    if (agree >= o.min_full_rows && disagree <= o.max_bad_row_fraction * (agree + disagree)) {
      return accept(best->first);
    }
  }
  // Per block: the left value and the right value each read on enough rows,
  // by the same majority rule (rows with an inconsistent block pair count
  // against both), then the parity across the blocks.
  std::map<int, int> side_votes[2];
  int side_rows[2] = {0, 0};
  for (const auto& [key, seen] : block_edges_seen) {
    const int n = static_cast<int>(seen.size() / kBarsPerBlock);
    side_votes[key.first][key.second] = n;
    side_rows[key.first] += n;
  }
  if (!side_votes[0].empty() && !side_votes[1].empty()) {
    int value[2] = {-1, -1};
    bool consistent = true;
    for (int side = 0; side < 2; ++side) {
      const auto best =
          std::max_element(side_votes[side].begin(), side_votes[side].end(),
                           [](const auto& a, const auto& b) { return a.second < b.second; });
      const int agree = best->second;
      const int disagree = side_rows[side] - agree + out.bad_rows;
      consistent = consistent && agree >= o.min_full_rows &&
                   disagree <= o.max_bad_row_fraction * (agree + disagree);
      value[side] = best->first;
    }
    const int low = value[1] / 2;
    if (consistent && value[1] % 2 == (value[0] + low) % 2) return accept(value[0] * 5 + low);
  }
  if (out.full_rows > 0) {
    out.status = PatternStatus::unreadable;
    return out;
  }
  if (left_seen + right_seen > 0) {
    out.status = PatternStatus::partial;
    out.disc_direction = left_seen > right_seen ? 1 : (right_seen > left_seen ? -1 : 0);
    return out;
  }
  out.status = any_block > 0 || out.bad_rows > 0 || !rows.empty() ? PatternStatus::unreadable
                                                                  : PatternStatus::no_pattern;
  return out;
}

BarcodeRead read_barcode_with_pose(std::span<const stream::RunRecord> runs, const PatternPose& pose,
                                   const CameraModel& camera, int image_width,
                                   const BarcodeOptions& o) {
  BarcodeRead out;
  if (pose.status != PatternStatus::ok && pose.status != PatternStatus::ambiguous) return out;
  const auto axes = pattern_axes_cam(pose.normal_cam, o.up_cam);
  if (!axes || !(o.bar_contrast > 0.0)) return out;
  const Eigen::Vector3d t = pose.centre_cam, n = axes->col(2);
  const double u = o.bar_unit_m;
  const double outer = o.radius_m + o.bar_gap_m + 15.0 * u;
  // Every bar run's ink edges onto the pattern plane, in units from its
  // block's outer end (side 0 left, 1 right).
  struct Mapped {
    const stream::RunRecord* run;
    double e0, e1;  // extent along the block, units from the outer end
    Eigen::Vector2d mid;
    double width;  // normalised, along the row
  };
  std::vector<Mapped> mapped[2];
  auto to_plane = [&](const Eigen::Vector2d& xy, Eigen::Vector2d& pat) {
    const Eigen::Vector3d ray(xy.x(), xy.y(), 1.0);
    const double den = n.dot(ray);
    if (!(std::abs(den) > 1e-12)) return false;
    const Eigen::Vector3d x = (n.dot(t) / den) * ray - t;
    pat = Eigen::Vector2d(axes->col(0).dot(x), axes->col(1).dot(x));
    return true;
  };
  for (const auto& r : runs) {
    if (r.sum_w < o.min_bar_run_weight || r.sum_w == 0) continue;
    if (r.x_start == 0 || r.x_end + 1 >= image_width) continue;
    const double centre = static_cast<double>(r.sum_xw) / static_cast<double>(r.sum_w);
    const double width = static_cast<double>(r.sum_w) / o.bar_contrast;
    const Eigen::Vector2d l = camera.normalise(centre - 0.5 * width, r.row);
    const Eigen::Vector2d rr = camera.normalise(centre + 0.5 * width, r.row);
    Eigen::Vector2d pl, pr;
    if (!to_plane(l, pl) || !to_plane(rr, pr)) continue;
    if (std::abs(0.5 * (pl.y() + pr.y())) > 0.5 * o.bar_height_m + 2.0 * u) continue;
    const double xm = 0.5 * (pl.x() + pr.x());
    const int side = xm < 0.0 ? 0 : 1;
    auto units = [&](double x) { return side == 0 ? (x + outer) / u : (outer - x) / u; };
    const double a = units(pl.x()), b = units(pr.x());
    if (std::max(a, b) < -1.0 || std::min(a, b) > 16.0) continue;
    mapped[side].push_back({&r, std::min(a, b), std::max(a, b), 0.5 * (l + rr), rr.x() - l.x()});
  }
  // Per block: how many runs cover each 0.1-unit bin; bars are the bins
  // covered by more than a third of the block's typical count.
  constexpr double kBin = 0.1, kFrom = -1.0, kTol = 0.35;
  constexpr int kBins = 170;
  int value[2] = {-1, -1};
  std::vector<BarEdge> edges;
  for (int side = 0; side < 2; ++side) {
    if (mapped[side].size() < 3 * kBarsPerBlock) continue;
    std::vector<int> count(kBins, 0);
    for (const Mapped& m : mapped[side]) {
      const int b0 = std::max(0, static_cast<int>(std::ceil((m.e0 - kFrom) / kBin - 0.5)));
      const int b1 = std::min(kBins - 1, static_cast<int>(std::floor((m.e1 - kFrom) / kBin - 0.5)));
      for (int b = b0; b <= b1; ++b) ++count[static_cast<std::size_t>(b)];
    }
    std::vector<int> sorted(count.begin(), count.end());
    std::sort(sorted.begin(), sorted.end());
    const int high = sorted[static_cast<std::size_t>(kBins * 9 / 10)];
    if (high < 3) continue;
    // Segments above the threshold: [start, end) in units.
    std::vector<std::pair<double, double>> seg;
    for (int b = 0; b < kBins; ++b) {
      const bool on = 3 * count[static_cast<std::size_t>(b)] > high;
      const bool prev = b > 0 && 3 * count[static_cast<std::size_t>(b - 1)] > high;
      const double edge = kFrom + b * kBin;
      if (on && !prev) seg.emplace_back(edge, edge);
      if (on) seg.back().second = edge + kBin;
    }
    if (seg.size() != kBarsPerBlock) continue;
    // The start bar at 0..3, then gap 1, bar 1 or 2, ..., ending at 15.
    bool good = std::abs(seg[0].first) <= kTol && std::abs(seg[0].second - 3.0) <= kTol;
    std::array<int, 5> widths{};
    double expect = 3.0;
    for (std::size_t k = 1; k < kBarsPerBlock && good; ++k) {
      const double w = seg[k].second - seg[k].first;
      const int wi = static_cast<int>(std::lround(w));
      good = (wi == 1 || wi == 2) && std::abs(w - wi) <= kTol &&
             std::abs(seg[k].first - seg[k - 1].second - 1.0) <= kTol &&
             std::abs(seg[k].first - (expect + 1.0)) <= kTol;
      widths[k - 1] = wi;
      expect += 1.0 + wi;
    }
    if (!good || std::abs(expect - 15.0) > 0.0) continue;
    std::array<int, 5> w5{};
    std::copy(widths.begin(), widths.end(), w5.begin());
    // Block values: widths from the outer end inward (golden block_widths).
    int v = -1;
    for (int cand = 0; cand < 10; ++cand) {
      const auto [i, j] = kPairs[static_cast<std::size_t>(cand)];
      bool match = true;
      for (int k = 0; k < 5; ++k)
        match = match && w5[static_cast<std::size_t>(k)] == ((k == i || k == j) ? 2 : 1);
      if (match) v = cand;
    }
    if (v < 0) continue;
    // Each bar needs three runs across its whole width.
    const auto e = block_edges(v);
    std::array<int, kBarsPerBlock> across{};
    std::vector<BarEdge> side_edges;
    for (const Mapped& m : mapped[side]) {
      for (std::size_t k = 0; k < kBarsPerBlock; ++k) {
        const double b0 = e[2 * k], b1 = e[2 * k + 1];
        const double mid = 0.5 * (m.e0 + m.e1);
        if (mid < b0 || mid > b1 || m.e1 - m.e0 < 0.8 * (b1 - b0)) continue;
        ++across[k];
        const double x0 = side == 0 ? -outer + b0 * u : outer - b1 * u;
        const double x1 = side == 0 ? -outer + b1 * u : outer - b0 * u;
        side_edges.push_back({m.mid.x(), m.mid.y(), x0, x1, m.run->row, m.width});
      }
    }
    if (*std::min_element(across.begin(), across.end()) < 3) continue;
    value[side] = v;
    edges.insert(edges.end(), side_edges.begin(), side_edges.end());
  }
  if (value[0] >= 0 && value[1] >= 0) {
    const int low = value[1] / 2;
    if (value[1] % 2 == (value[0] + low) % 2) {
      out.status = PatternStatus::ok;
      out.identity = value[0] * 5 + low;
      out.edges = std::move(edges);
      return out;
    }
    out.status = PatternStatus::unreadable;
    return out;
  }
  if (value[0] >= 0 || value[1] >= 0) {
    out.status = PatternStatus::partial;
    out.disc_direction = value[0] >= 0 ? 1 : -1;
    return out;
  }
  out.status = mapped[0].empty() && mapped[1].empty() ? PatternStatus::no_pattern
                                                      : PatternStatus::unreadable;
  return out;
}

namespace {
// The image of the pattern's disc for a pose (centre t, axes a of the pattern
// in the camera) as fit_disc_coverage's parameters (centre, S = 4 cov):
// the unit circle's conic diag(1, 1, -1) through H = [R a1, R a2, t].
std::optional<Eigen::Matrix<double, 5, 1>> disc_image_params(const Eigen::Matrix3d& a,
                                                             const Eigen::Vector3d& t, double r) {
  Eigen::Matrix3d h;
  h.col(0) = r * a.col(0);
  h.col(1) = r * a.col(1);
  h.col(2) = t;
  const Eigen::Matrix3d hi = h.inverse();
  const Eigen::Matrix3d q = hi.transpose() * Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal() * hi;
  const Eigen::Matrix2d m = q.topLeftCorner<2, 2>();
  if (!(std::abs(m.determinant()) > 0.0) || !q.allFinite()) return std::nullopt;
  const Eigen::Vector2d x0 = -m.inverse() * q.topRightCorner<2, 1>();
  const Eigen::Matrix2d s = (x0.dot(m * x0) - q(2, 2)) * m.inverse();
  Eigen::Matrix<double, 5, 1> e;
  e << x0.x(), x0.y(), s(0, 0), s(0, 1), s(1, 1);
  return e;
}
}  // namespace

std::optional<CirclePose> mirror_pose(const PatternPose& p, double radius_m) {
  for (const CirclePose& cp : circle_poses_from_conic(conic_from_ellipse(p.ellipse), radius_m)) {
    if (cp.normal.dot(p.normal_cam) < 1.0 - 1e-12) return cp;
  }
  return std::nullopt;
}

PatternPose refine_with_bars(const PatternPose& conic, std::span<const BarEdge> edges,
                             const CameraModel& camera, const PoseOptions& o) {
  if ((conic.status != PatternStatus::ok && conic.status != PatternStatus::ambiguous) ||
      edges.size() < 48) {
    return conic;
  }
  const auto axes0 = pattern_axes_cam(conic.normal_cam, o.up_cam);
  if (!axes0) return conic;
  const double f = std::sqrt(camera.fx() * camera.fy());
  // Per row, a bar's ink centroid scatters by about 0.15 px; every row of one
  // bar shares the same pixel phase, so the bar's mean carries a common error
  // of about 0.03 px that its rows do not average away (docs/pattern.md).
  const double sigma_row = 0.15 / f, sigma_bar = 0.03 / f;  // normalised units
  // The disc: with the coverage fit's covariance the prior is the disc's own
  // image (5 constraints on the pose, weighted by what the fit measured);
  // without it, the conic's centre (0.3 % of D in each coordinate) and normal
  // (1 deg).
  const double sigma_slide = 0.003 * conic.centre_cam.norm();
  const double sigma_normal = 1.0 * kPi / 180.0;
  const Eigen::Vector3d c0 = conic.centre_cam, n0 = conic.normal_cam;
  const Eigen::Matrix<double, 5, 5>& pc = conic.ellipse.param_cov;
  Eigen::Matrix<double, 5, 1> e_meas;
  e_meas << conic.ellipse.cx, conic.ellipse.cy, 4.0 * conic.ellipse.cov(0, 0),
      4.0 * conic.ellipse.cov(0, 1), 4.0 * conic.ellipse.cov(1, 1);
  const Eigen::LLT<Eigen::Matrix<double, 5, 5>> disc_llt(pc);
  const bool disc_prior = (pc.array() != 0.0).any() && disc_llt.info() == Eigen::Success;
  // Bars narrower than 2 px are left out: their gaps are about as narrow, so
  // the run's one-pixel margin takes in the neighbours' ink and biases the
  // centroid (measured: up to 0.6 % in D at 3 m, 67.5 deg).
  std::vector<int> bar_of(edges.size(), -1);
  std::map<double, int> bar_index;
  std::size_t used = 0;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (edges[i].width * f < 2.0) continue;
    bar_of[i] =
        bar_index.try_emplace(edges[i].x0_m, static_cast<int>(bar_index.size())).first->second;
    ++used;
  }
  if (used < 48) return conic;
  const std::size_t n_bars = bar_index.size();
  const std::size_t n_prior = disc_prior ? 5 : 6;
  const std::size_t n_res = edges.size() + n_bars + n_prior + 1;
  std::vector<double> weight(edges.size(), 1.0);
  auto residuals = [&](const Eigen::Matrix3d& aa, const Eigen::Vector3d& tt, double bb,
                       Eigen::VectorXd& r) {
    r.setZero(static_cast<Eigen::Index>(n_res));
    const Eigen::Vector3d a1 = aa.col(0), a2 = aa.col(1), a3 = aa.col(2);
    std::vector<double> dist(edges.size(), 0.0), sum(n_bars, 0.0), wsum(n_bars, 0.0);
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (bar_of[i] < 0) continue;
      const BarEdge& e = edges[i];
      // The ink centroid along the row is the midpoint of the bar's two
      // projected edges (not the projection of its centre line): the mean
      // of the signed distances to the two edge lines vanishes there.
      double d = 0.0;
      for (const double xe : {e.x0_m, e.x1_m}) {
        const Eigen::Vector3d l = (tt + (xe + bb) * a1).cross(a2);
        const double norm = std::sqrt(l.x() * l.x() + l.y() * l.y());
        d += norm > 0.0 ? 0.5 * (l.x() * e.x + l.y() * e.y + l.z()) / norm : 0.0;
      }
      dist[i] = d;
      const auto b = static_cast<std::size_t>(bar_of[i]);
      sum[b] += weight[i] * d;
      wsum[b] += weight[i];
    }
    // Each row about its bar's mean; each bar's mean against its own sigma.
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (bar_of[i] < 0) continue;
      const auto b = static_cast<std::size_t>(bar_of[i]);
      r(static_cast<Eigen::Index>(i)) = weight[i] * (dist[i] - sum[b] / wsum[b]) / sigma_row;
    }
    auto k = static_cast<Eigen::Index>(edges.size());
    for (std::size_t b = 0; b < n_bars; ++b, ++k) {
      if (wsum[b] > 0.0) {
        r(k) =
            sum[b] / wsum[b] / std::sqrt(sigma_bar * sigma_bar + sigma_row * sigma_row / wsum[b]);
      }
    }
    if (disc_prior) {
      const auto e = disc_image_params(aa, tt, o.radius_m);
      r.segment<5>(k) = e ? Eigen::Matrix<double, 5, 1>(disc_llt.matrixL().solve(*e - e_meas))
                          : Eigen::Matrix<double, 5, 1>::Constant(1e6);
    } else {
      r.segment<3>(k) = (tt - c0) / sigma_slide;
      r.segment<3>(k + 3) = (a3 - n0) / sigma_normal;
    }
    r(static_cast<Eigen::Index>(n_res) - 1) =
        bb / 1e-4;  // a shift along x is a translation along a1: pinned
  };
  auto apply = [](const Eigen::Matrix3d& aa, const Eigen::Vector3d& tt, double bb,
                  const Eigen::Matrix<double, 7, 1>& d, Eigen::Matrix3d& a2, Eigen::Vector3d& t2,
                  double& b2) {
    const Eigen::Vector3d w = d.head<3>();
    const double angle = w.norm();
    a2 = angle > 0.0 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, w / angle) * aa) : aa;
    t2 = tt + d.segment<3>(3);
    b2 = bb + d(6);
  };
  // Gauss-Newton from a start pose; the robust cost at the end (Huber at 3
  // sigma on the rows, squares elsewhere) to compare starts.
  auto solve = [&](Eigen::Matrix3d& a, Eigen::Vector3d& t, double& cost) {
    double bias = 0.0;  // metres: a common shift along x (pattern printing offset)
    std::fill(weight.begin(), weight.end(), 1.0);
    Eigen::VectorXd r0, r1;
    for (int iteration = 0; iteration < 12; ++iteration) {
      residuals(a, t, bias, r0);
      // Robust: down-weight rows beyond 3 sigma of their bar's mean (once per iteration).
      for (std::size_t i = 0; i < edges.size(); ++i) {
        if (bar_of[i] < 0) continue;
        const double ri = std::abs(r0(static_cast<Eigen::Index>(i))) / weight[i];
        weight[i] = ri > 3.0 ? 3.0 / ri : 1.0;
      }
      residuals(a, t, bias, r0);
      Eigen::MatrixXd jac(static_cast<Eigen::Index>(n_res), 7);
      const double steps[7] = {1e-6, 1e-6, 1e-6, 1e-6 * t.norm(), 1e-6 * t.norm(), 1e-6 * t.norm(),
                               1e-6};
      for (int j = 0; j < 7; ++j) {
        Eigen::Matrix<double, 7, 1> d = Eigen::Matrix<double, 7, 1>::Zero();
        d(j) = steps[j];
        Eigen::Matrix3d a2;
        Eigen::Vector3d t2;
        double b2 = 0.0;
        apply(a, t, bias, d, a2, t2, b2);
        residuals(a2, t2, b2, r1);
        jac.col(j) = (r1 - r0) / steps[j];
      }
      Eigen::Matrix<double, 7, 7> h = jac.transpose() * jac;
      h.diagonal() *= 1.0 + 1e-9;
      const Eigen::Matrix<double, 7, 1> g = jac.transpose() * r0;
      const Eigen::Matrix<double, 7, 1> delta = -h.ldlt().solve(g);
      if (!delta.allFinite()) return false;
      apply(a, t, bias, delta, a, t, bias);
      if (delta.head<3>().norm() < 1e-10 && delta.segment<3>(3).norm() < 1e-10 * t.norm()) break;
    }
    if (!a.allFinite() || !t.allFinite() || !(t.z() > 0.0)) return false;
    std::fill(weight.begin(), weight.end(), 1.0);
    residuals(a, t, bias, r0);
    cost = 0.0;
    for (Eigen::Index i = 0; i < r0.size(); ++i) {
      const double z = std::abs(r0(i));
      cost += i < static_cast<Eigen::Index>(edges.size()) && z > 3.0 ? 6.0 * z - 9.0 : z * z;
    }
    return true;
  };
  // Starts: the conic's pose and, with the disc's own prior, the other circle
  // pose of the same ellipse (the seed's two-way ambiguity, eq. 14): the
  // bars' perspective tells them apart where no side wall shows.
  struct Start {
    Eigen::Matrix3d a;
    Eigen::Vector3d t;
    Eigen::Vector3d n0;
  };
  std::vector<Start> starts{{*axes0, c0, n0}};
  if (disc_prior) {
    if (const auto cp = mirror_pose(conic, o.radius_m)) {
      const auto ax = pattern_axes_cam(cp->normal, o.up_cam);
      if (ax) starts.push_back({*ax, cp->centre, cp->normal});
    }
  }
  double best_cost = std::numeric_limits<double>::infinity(), other_cost = best_cost;
  std::optional<std::pair<Eigen::Matrix3d, Eigen::Vector3d>> best;
  for (Start& st : starts) {
    double cost = 0.0;
    if (!solve(st.a, st.t, cost)) continue;
    // A fit that wandered far from its start is not trusted.
    if (std::abs(st.t.norm() / c0.norm() - 1.0) > 0.05 ||
        st.a.col(2).dot(st.n0) < std::cos(5.0 * kPi / 180.0)) {
      continue;
    }
    if (cost < best_cost) {
      other_cost = best_cost;
      best_cost = cost;
      best = {st.a, st.t};
    } else {
      other_cost = std::min(other_cost, cost);
    }
  }
  if (!best) return conic;
  PatternPose p = conic;
  p.centre_cam = best->second;
  p.normal_cam = best->first.col(2);
  p.up_cam = best->first.col(1);
  spherical_from_pose(best->second, best->first, p);
  // Resolved by the bars when the other start fits worse by > 5 sigma.
  if (starts.size() == 2 && other_cost - best_cost > 25.0 && !p.beta_resolved) {
    p.beta_resolved = true;
    p.status = PatternStatus::ok;
  }
  return p;
}

WorldFix world_fix(const PatternPose& pose, const Placement& placement,
                   const Eigen::Vector3d& up_cam) {
  WorldFix f;
  const double st = std::sin(pose.theta_rad);
  const Eigen::Vector3d cam_pat =
      pose.d_m * Eigen::Vector3d(st * std::sin(pose.beta_rad), st * std::cos(pose.beta_rad),
                                 std::cos(pose.theta_rad));
  const Eigen::Vector3d z(std::cos(placement.facing_rad), std::sin(placement.facing_rad), 0.0);
  const Eigen::Vector3d y(0.0, 0.0, 1.0);
  Eigen::Matrix3d axes;
  axes.col(0) = y.cross(z);
  axes.col(1) = y;
  axes.col(2) = z;
  const Eigen::Vector3d w =
      Eigen::Vector3d(placement.x_m, placement.y_m, placement.z_m) + axes * cam_pat;
  f.x_m = w.x();
  f.y_m = w.y();
  f.z_m = w.z();
  // TRIAD: (direction to the disc, up) in the camera <-> (-cam_pat, y_p) in
  // the pattern frame gives the camera's rotation; its forward axis in the
  // world gives the yaw.
  auto triad = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    Eigen::Matrix3d t;
    t.col(0) = a.normalized();
    t.col(1) = a.cross(b).normalized();
    t.col(2) = t.col(0).cross(t.col(1));
    return t;
  };
  const Eigen::Matrix3d tc = triad(pose.centre_cam, up_cam);
  const Eigen::Matrix3d tp = triad(-cam_pat, Eigen::Vector3d::UnitY());
  const Eigen::Matrix3d pat_from_cam = tp * tc.transpose();
  const Eigen::Vector3d fwd = axes * (pat_from_cam * Eigen::Vector3d::UnitZ());
  f.camera_yaw_rad = std::atan2(fwd.y(), fwd.x());
  if (!std::isfinite(f.camera_yaw_rad)) f.camera_yaw_rad = 0.0;
  return f;
}

}  // namespace ceilnav::host::pattern
