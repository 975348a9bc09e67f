#include "golden/corridor/corridor.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "golden/scene.hpp"

namespace ceilnav::golden::corridor {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  throw CorridorError(source + ": " + key + ": " + what);
}

void positive(double v, const std::string& source, const std::string& key) {
  if (!(v > 0.0) || !std::isfinite(v)) fail(source, key, "must be finite and > 0");
}

void non_negative(double v, const std::string& source, const std::string& key) {
  if (!(v >= 0.0) || !std::isfinite(v)) fail(source, key, "must be finite and >= 0");
}

void finite(double v, const std::string& source, const std::string& key) {
  if (!std::isfinite(v)) fail(source, key, "must be finite");
}

std::string at(const std::string& key, std::size_t i) {
  return key + "[" + std::to_string(i) + "]";
}

// The number of lamps in a row (centres first_x + k spacing, k = 0..n-1,
// each ending before the far wall).
int lamp_count(const Corridor& c) {
  const Lamps& l = c.lamps;
  if (l.rows_y_m.empty()) return 0;
  return static_cast<int>(
             std::floor((c.x_end_m() - 0.5 * l.length_m - l.first_x_m) / l.spacing_m + 1e-9)) +
         1;
}

// The seam positions along one axis: origin + k pitch with the whole strip
// inside (lo, hi).
std::vector<double> seam_positions(double origin, double pitch, double half_width, double lo,
                                   double hi) {
  std::vector<double> out;
  if (!(pitch > 0.0)) return out;
  const auto k0 = static_cast<long>(std::ceil((lo + half_width - origin) / pitch));
  const auto k1 = static_cast<long>(std::floor((hi - half_width - origin) / pitch));
  for (long k = k0; k <= k1; ++k) {
    const double p = origin + static_cast<double>(k) * pitch;
    if (p - half_width > lo && p + half_width < hi) out.push_back(p);
  }
  return out;
}

Eigen::Matrix3d camera_matrix(const host::CameraConfig& camera) {
  Eigen::Matrix3d k;
  k << camera.fx(), 0.0, camera.cx(), 0.0, camera.fy(), camera.cy(), 0.0, 0.0, 1.0;
  return k;
}

VanishingPoint vanishing_point(const Eigen::Matrix3d& k, const Eigen::Matrix3d& r,
                               const Eigen::Vector3d& direction) {
  VanishingPoint vp;
  vp.homogeneous = (k * (r * direction)).normalized();
  vp.finite = std::abs(vp.homogeneous.z()) > 1e-12;
  if (vp.finite) {
    vp.u_px = vp.homogeneous.x() / vp.homogeneous.z();
    vp.v_px = vp.homogeneous.y() / vp.homogeneous.z();
  }
  return vp;
}

// The box, in normalised undistorted coordinates, that holds the undistorted
// image of the whole frame: the box of its undistorted border (every pixel
// of it, where the distortion is invertible).
struct NormalisedBox {
  double x0, x1, y0, y1;
};
NormalisedBox frame_box(const host::CameraConfig& camera) {
  NormalisedBox box{1e300, -1e300, 1e300, -1e300};
  const double w = camera.image_width, h = camera.image_height;
  auto add = [&](double u, double v) {
    const std::optional<Eigen::Vector2d> xy = undistort_pixel(camera, {u, v});
    if (!xy) return;
    box.x0 = std::min(box.x0, xy->x());
    box.x1 = std::max(box.x1, xy->x());
    box.y0 = std::min(box.y0, xy->y());
    box.y1 = std::max(box.y1, xy->y());
  };
  for (int i = 0; i <= camera.image_width; ++i) {
    add(i - 0.5, -0.5);
    add(i - 0.5, h - 0.5);
  }
  for (int j = 0; j <= camera.image_height; ++j) {
    add(-0.5, j - 0.5);
    add(w - 0.5, j - 0.5);
  }
  // One pixel of margin.
  box.x0 -= 1.0 / camera.fx();
  box.x1 += 1.0 / camera.fx();
  box.y0 -= 1.0 / camera.fy();
  box.y1 += 1.0 / camera.fy();
  return box;
}

// Liang-Barsky: clips a + t (b - a), t in [t0, t1], to the box.
bool clip_to_box(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const NormalisedBox& box,
                 double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  const Eigen::Vector2d d = b - a;
  const std::array<double, 4> p{-d.x(), d.x(), -d.y(), d.y()};
  const std::array<double, 4> q{a.x() - box.x0, box.x1 - a.x(), a.y() - box.y0, box.y1 - a.y()};
  for (std::size_t i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
  }
  return t0 <= t1;
}

// Which part of the line is seen: its extent clipped to the camera's front
// (z >= 1 mm), projected onto the undistorted image, clipped to the frame's
// box and sampled every ~1/1024 of that; a sample is seen when its
// distorted pixel lies in the frame.
void find_visible(const host::CameraConfig& camera, const NormalisedBox& box,
                  const Eigen::Matrix3d& r, const Eigen::Vector3d& centre, ImageLine& line) {
  Eigen::Vector3d a = r * (line.line.point + Eigen::Vector3d(line.line.x0_m, 0, 0) - centre);
  Eigen::Vector3d b = r * (line.line.point + Eigen::Vector3d(line.line.x1_m, 0, 0) - centre);
  constexpr double kNear = 1e-3;
  if (a.z() < kNear && b.z() < kNear) return;
  if (a.z() < kNear) a += (kNear - a.z()) / (b.z() - a.z()) * (b - a);
  if (b.z() < kNear) b += (kNear - b.z()) / (a.z() - b.z()) * (a - b);
  const Eigen::Vector2d na(a.x() / a.z(), a.y() / a.z()), nb(b.x() / b.z(), b.y() / b.z());
  double t0 = 0.0, t1 = 0.0;
  if (!clip_to_box(na, nb, box, t0, t1)) return;
  constexpr int kSamples = 1024;
  bool any = false;
  for (int s = 0; s <= kSamples; ++s) {
    const Eigen::Vector2d n = na + (t0 + (t1 - t0) * s / kSamples) * (nb - na);
    const Eigen::Vector2d d = camera.has_distortion() ? distort_normalised(camera, n) : n;
    const double u = camera.fx() * d.x() + camera.cx(), v = camera.fy() * d.y() + camera.cy();
    if (!(u >= -0.5 && u < camera.image_width - 0.5 && v >= -0.5 && v < camera.image_height - 0.5))
      continue;
    // Beyond the radius where the lens model folds over, a point far outside
    // the view can distort into the frame: it is seen only if the frame's
    // pixel undistorts back to it.
    if (camera.has_distortion()) {
      const std::optional<Eigen::Vector2d> back = undistort_pixel(camera, {u, v});
      if (!back || (*back - n).norm() > 1e-9 * (1.0 + n.norm())) continue;
    }
    const Eigen::Vector2d px(camera.fx() * n.x() + camera.cx(), camera.fy() * n.y() + camera.cy());
    if (!any) line.from_px = px;
    line.to_px = px;
    any = true;
  }
  line.visible = any;
}

}  // namespace

const char* line_kind_name(LineKind kind) {
  switch (kind) {
    case LineKind::lamp_edge:
      return "lamp_edge";
    case LineKind::seam:
      return "seam";
    case LineKind::junction:
      return "junction";
    case LineKind::cornice_edge:
      return "cornice_edge";
    case LineKind::skirting_edge:
      return "skirting_edge";
    case LineKind::floor_junction:
      return "floor_junction";
    case LineKind::door_top:
      return "door_top";
  }
  return "?";
}

void validate(const Corridor& c, const std::string& source) {
  positive(c.width_m, source, "geometry.width_m");
  positive(c.ceiling_height_m, source, "geometry.ceiling_height_m");
  positive(c.length_m, source, "geometry.length_m");
  finite(c.x_start_m, source, "geometry.x_start_m");
  non_negative(c.ceiling_albedo, source, "surfaces.ceiling_albedo");
  non_negative(c.wall_albedo, source, "surfaces.wall_albedo");
  non_negative(c.floor_albedo, source, "surfaces.floor_albedo");
  non_negative(c.end_wall_albedo, source, "surfaces.end_wall_albedo");
  const Lighting& li = c.lighting;
  non_negative(li.ceiling_light, source, "lighting.ceiling_light");
  non_negative(li.wall_light_floor, source, "lighting.wall_light_floor");
  non_negative(li.wall_light_ceiling, source, "lighting.wall_light_ceiling");
  non_negative(li.floor_light, source, "lighting.floor_light");
  non_negative(li.open_radiance, source, "lighting.open_radiance");
  const double half = 0.5 * c.width_m;
  const Lamps& l = c.lamps;
  if (!l.rows_y_m.empty()) {
    positive(l.length_m, source, "lamps.length_m");
    positive(l.width_m, source, "lamps.width_m");
    positive(l.spacing_m, source, "lamps.spacing_m");
    finite(l.first_x_m, source, "lamps.first_x_m");
    non_negative(l.radiance, source, "lamps.radiance");
    if (!(l.length_m < l.spacing_m)) fail(source, "lamps.length_m", "must be < spacing_m");
    if (!(l.first_x_m - 0.5 * l.length_m > c.x_start_m) ||
        !(l.first_x_m + 0.5 * l.length_m < c.x_end_m())) {
      fail(source, "lamps.first_x_m", "the first lamp must lie inside the corridor");
    }
    for (std::size_t i = 0; i < l.rows_y_m.size(); ++i) {
      finite(l.rows_y_m[i], source, at("lamps.rows_y_m", i));
      if (!(std::abs(l.rows_y_m[i]) + 0.5 * l.width_m < half)) {
        fail(source, at("lamps.rows_y_m", i), "the row must lie inside the ceiling");
      }
      if (i > 0 && !(l.rows_y_m[i] - l.rows_y_m[i - 1] > l.width_m)) {
        fail(source, at("lamps.rows_y_m", i), "rows must increase and not overlap");
      }
    }
  }
  const Seams& s = c.seams;
  non_negative(s.along_pitch_m, source, "seams.along_pitch_m");
  non_negative(s.across_pitch_m, source, "seams.across_pitch_m");
  finite(s.along_origin_m, source, "seams.along_origin_m");
  finite(s.across_origin_m, source, "seams.across_origin_m");
  non_negative(s.albedo, source, "seams.albedo");
  if (s.along_pitch_m > 0.0 || s.across_pitch_m > 0.0) {
    positive(s.width_m, source, "seams.width_m");
    for (double pitch : {s.along_pitch_m, s.across_pitch_m}) {
      if (pitch > 0.0 && !(s.width_m < pitch)) fail(source, "seams.width_m", "must be < the pitch");
    }
  }
  non_negative(c.cornice.height_m, source, "cornice.height_m");
  non_negative(c.cornice.albedo, source, "cornice.albedo");
  non_negative(c.skirting.height_m, source, "skirting.height_m");
  non_negative(c.skirting.albedo, source, "skirting.albedo");
  if (!(c.cornice.height_m + c.skirting.height_m < c.ceiling_height_m)) {
    fail(source, "cornice.height_m", "cornice and skirting must leave some wall between them");
  }
  for (std::size_t i = 0; i < c.doors.size(); ++i) {
    const Door& d = c.doors[i];
    const std::string key = at("doors", i);
    positive(d.width_m, source, key + ".width_m");
    positive(d.height_m, source, key + ".height_m");
    non_negative(d.frame_width_m, source, key + ".frame_width_m");
    non_negative(d.albedo, source, key + ".albedo");
    non_negative(d.frame_albedo, source, key + ".frame_albedo");
    finite(d.x_m, source, key + ".x_m");
    if (!(d.x_m - d.frame_width_m > c.x_start_m) ||
        !(d.x_m + d.width_m + d.frame_width_m < c.x_end_m())) {
      fail(source, key + ".x_m", "the door and its frame must lie on the wall");
    }
    if (!(d.height_m + d.frame_width_m < c.ceiling_height_m - c.cornice.height_m)) {
      fail(source, key + ".height_m", "the door and its frame must end below the cornice");
    }
  }
}

void validate(const Pose& p, const Corridor& c, const std::string& source) {
  for (double v : {p.x_m, p.y_m, p.height_m, p.pan_rad, p.tilt_rad, p.swing_rad}) {
    if (!std::isfinite(v)) fail(source, "camera", "position and angles must be finite");
  }
  if (!(p.x_m > c.x_start_m && p.x_m < c.x_end_m())) {
    fail(source, "camera.x_m", "must lie inside the corridor");
  }
  if (!(std::abs(p.y_m) < 0.5 * c.width_m))
    fail(source, "camera.y_m", "must lie between the walls");
  if (!(p.height_m > 0.0 && p.height_m < c.ceiling_height_m)) {
    fail(source, "camera.height_m", "must lie between floor and ceiling");
  }
}

CameraView view_of(const Pose& pose) {
  return {Eigen::Vector3d(pose.x_m, pose.y_m, pose.height_m),
          world_to_camera_rotation(pose.pan_rad, pose.tilt_rad, pose.swing_rad)};
}

Corridor default_corridor() {
  Corridor c;
  c.name = "default";
  c.lamps.rows_y_m = {-0.6, 0.6};
  c.lamps.first_x_m = 1.0;
  c.seams.along_pitch_m = 0.6;
  c.seams.along_origin_m = 0.0;
  c.seams.across_pitch_m = 0.6;
  c.seams.across_origin_m = 0.3;
  c.cornice = {0.06, 0.92};
  c.skirting = {0.10, 0.15};
  c.doors = {{Wall::left, 4.0, 0.9, 2.05, 0.06, 0.25, 0.85},
             {Wall::right, 9.5, 0.9, 2.05, 0.06, 0.25, 0.85},
             {Wall::left, 16.0, 1.8, 2.10, 0.08, 0.2, 0.9},
             {Wall::right, 24.0, 0.9, 2.05, 0.06, 0.3, 0.85}};
  return c;
}

Pose default_pose() {
  return {0.0, 0.3, 1.0, 4.0 * kDeg, 35.0 * kDeg, 0.0};
}

std::vector<AxisLine> axis_lines(const Corridor& c) {
  std::vector<AxisLine> out;
  const double half = 0.5 * c.width_m, h = c.ceiling_height_m;
  const double x0 = c.x_start_m, x1 = c.x_end_m();
  const int lamps = lamp_count(c);
  for (std::size_t i = 0; i < c.lamps.rows_y_m.size() && lamps > 0; ++i) {
    const Lamps& l = c.lamps;
    const double a = l.first_x_m - 0.5 * l.length_m;
    const double b = l.first_x_m + (lamps - 1) * l.spacing_m + 0.5 * l.length_m;
    const std::string row = at("lamp_row", i);
    out.push_back(
        {LineKind::lamp_edge, row + ".right", {0.0, l.rows_y_m[i] - 0.5 * l.width_m, h}, a, b});
    out.push_back(
        {LineKind::lamp_edge, row + ".left", {0.0, l.rows_y_m[i] + 0.5 * l.width_m, h}, a, b});
  }
  const std::vector<double> seams = seam_positions(c.seams.along_origin_m, c.seams.along_pitch_m,
                                                   0.5 * c.seams.width_m, -half, half);
  for (std::size_t i = 0; i < seams.size(); ++i) {
    out.push_back({LineKind::seam, at("seam", i), {0.0, seams[i], h}, x0, x1});
  }
  for (int side = 0; side < 2; ++side) {
    const double y = side == 0 ? half : -half;
    const std::string wall = side == 0 ? ".left" : ".right";
    out.push_back({LineKind::junction, "junction" + wall, {0.0, y, h}, x0, x1});
  }
  if (c.cornice.height_m > 0.0) {
    for (int side = 0; side < 2; ++side) {
      out.push_back({LineKind::cornice_edge,
                     side == 0 ? "cornice.left" : "cornice.right",
                     {0.0, side == 0 ? half : -half, h - c.cornice.height_m},
                     x0,
                     x1});
    }
  }
  if (c.skirting.height_m > 0.0) {
    for (int side = 0; side < 2; ++side) {
      out.push_back({LineKind::skirting_edge,
                     side == 0 ? "skirting.left" : "skirting.right",
                     {0.0, side == 0 ? half : -half, c.skirting.height_m},
                     x0,
                     x1});
    }
  }
  for (int side = 0; side < 2; ++side) {
    out.push_back({LineKind::floor_junction,
                   side == 0 ? "floor.left" : "floor.right",
                   {0.0, side == 0 ? half : -half, 0.0},
                   x0,
                   x1});
  }
  for (std::size_t i = 0; i < c.doors.size(); ++i) {
    const Door& d = c.doors[i];
    const double y = d.wall == Wall::left ? half : -half;
    const double fw = d.frame_width_m;
    if (fw > 0.0) {
      out.push_back({LineKind::door_top,
                     at("door", i) + ".frame_top",
                     {0.0, y, d.height_m + fw},
                     d.x_m - fw,
                     d.x_m + d.width_m + fw});
    }
    out.push_back({LineKind::door_top,
                   at("door", i) + ".top",
                   {0.0, y, d.height_m},
                   d.x_m,
                   d.x_m + d.width_m});
  }
  return out;
}

void normal_form(const Eigen::Vector3d& line, double& theta_rad, double& rho_px) {
  const double n = std::hypot(line.x(), line.y());
  double theta = std::atan2(line.y(), line.x());
  double rho = -line.z() / n;
  if (theta < 0.0) {
    theta += std::numbers::pi;
    rho = -rho;
  }
  if (theta >= std::numbers::pi) {
    theta -= std::numbers::pi;
    rho = -rho;
  }
  theta_rad = theta;
  rho_px = rho;
}

FrameTruth truth_for(const host::CameraConfig& camera, const Corridor& corridor, const Pose& pose) {
  validate(corridor);
  validate(pose, corridor);
  FrameTruth truth;
  truth.pose = pose;
  const CameraView view = view_of(pose);
  const Eigen::Matrix3d& r = view.world_to_camera;
  truth.world_to_camera = r;
  const Eigen::Matrix3d k = camera_matrix(camera);
  const Eigen::Matrix3d k_inv_t = k.inverse().transpose();
  truth.axis = vanishing_point(k, r, Eigen::Vector3d::UnitX());
  truth.cross = vanishing_point(k, r, Eigen::Vector3d::UnitY());
  truth.vertical = vanishing_point(k, r, Eigen::Vector3d::UnitZ());
  const NormalisedBox box = frame_box(camera);
  for (const AxisLine& line : axis_lines(corridor)) {
    ImageLine image;
    image.line = line;
    // The plane through the camera centre and the line, in camera axes, is
    // the line's image in normalised coordinates; K^-T takes it to pixels.
    const Eigen::Vector3d p = r * (line.point - view.centre);
    const Eigen::Vector3d d = r * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d plane = p.cross(d);
    image.defined = plane.norm() > 1e-12 * p.norm();
    if (image.defined) {
      normal_form(k_inv_t * plane, image.theta_rad, image.rho_px);
      find_visible(camera, box, r, view.centre, image);
    }
    truth.lines.push_back(image);
  }
  return truth;
}

}  // namespace ceilnav::golden::corridor
