#include "sim/course_render.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "golden/scene.hpp"

namespace ceilnav::sim {
namespace {

// Pinhole projection of a world point through a view (no distortion):
// nullopt behind the camera.
std::optional<Eigen::Vector2d> project_pinhole(const host::CameraConfig& camera,
                                               const golden::CameraView& view,
                                               const Eigen::Vector3d& world) {
  const Eigen::Vector3d p = view.world_to_camera * (world - view.centre);
  if (!(p.z() > 0.0)) return std::nullopt;
  return Eigen::Vector2d(camera.fx() * p.x() / p.z() + camera.cx(),
                         camera.fy() * p.y() / p.z() + camera.cy());
}

// Composites one pattern station into `radiance` (what the tape renderer
// made for `view`); returns the pixels it covered.
int composite_station(const host::CameraConfig& camera, const Course& course,
                      const PatternStation& station, const golden::CameraView& view,
                      const DriveRenderParams& params, cv::Mat& radiance) {
  namespace gp = golden::pattern;
  const gp::PatternGeometry& g = params.pattern_geometry;
  const StationFrame frame = station_frame(course, station, g);
  // X_cam = R (O + A X_p - C) = (R A) (X_p - A^T (C - O)).
  const gp::PatternView pv{frame.axes.transpose() * (view.centre - frame.origin),
                           view.world_to_camera * frame.axes};
  if (!(pv.centre.z() > 0.0)) return 0;  // the camera is above the pattern's face
  const double half_w = std::abs(gp::block_outer_x_m(g)) + g.plate_margin_m;
  const double half_h = 0.5 * g.bar_height_m + g.plate_margin_m;
  // Quick rejection: the panel's corners all in front and their bounding box
  // off the image, or all behind the camera (z <= 0: the panel is convex, so
  // no ray in front meets it).
  bool all_in_front = true;
  int in_front = 0;
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (int c = 0; c < 4; ++c) {
    const Eigen::Vector3d local((c & 1) ? half_w : -half_w, (c & 2) ? half_h : -half_h, 0.0);
    const Eigen::Vector3d p = pv.rotation * (local - pv.centre);
    if (!(p.z() > 0.0)) {
      all_in_front = false;
      continue;
    }
    ++in_front;
    u0 = std::min(u0, camera.fx() * p.x() / p.z() + camera.cx());
    u1 = std::max(u1, camera.fx() * p.x() / p.z() + camera.cx());
    v0 = std::min(v0, camera.fy() * p.y() / p.z() + camera.cy());
    v1 = std::max(v1, camera.fy() * p.y() / p.z() + camera.cy());
  }
  if (in_front == 0) return 0;
  // A margin for the lens distortion: the pinhole box may be off by some pixels.
  const double margin = 0.25 * std::max(camera.image_width, camera.image_height);
  if (all_in_front && (u1 < -margin || u0 > camera.image_width + margin || v1 < -margin ||
                       v0 > camera.image_height + margin)) {
    return 0;
  }
  // The pixels whose ray meets the face plane (z_p = 0) inside the panel.
  const auto rays = golden::pixel_rays(camera, params.render.apply_distortion);
  const Eigen::Matrix3d to_pattern = pv.rotation.transpose();
  cv::Mat mask(camera.image_height, camera.image_width, CV_8UC1, cv::Scalar(0));
  int covered = 0;
  for (int j = 0; j < camera.image_height; ++j) {
    for (int i = 0; i < camera.image_width; ++i) {
      const golden::PixelRay& ray =
          (*rays)[static_cast<std::size_t>(j) * static_cast<std::size_t>(camera.image_width) +
                  static_cast<std::size_t>(i)];
      if (!ray.valid) continue;
      const Eigen::Vector3d d = to_pattern * Eigen::Vector3d(ray.x, ray.y, 1.0);
      if (!(d.z() < 0.0)) continue;
      const double t = -pv.centre.z() / d.z();
      const double x = pv.centre.x() + t * d.x(), y = pv.centre.y() + t * d.y();
      if (std::abs(x) <= half_w && std::abs(y) <= half_h) {
        mask.at<uint8_t>(j, i) = 1;
        ++covered;
      }
    }
  }
  if (covered == 0) return 0;
  gp::PatternRenderParams rp;
  rp.supersample = params.pattern_supersample;
  rp.blur_sigma_px = 0.0;
  rp.noise_sigma_grey = 0.0;
  rp.apply_distortion = params.render.apply_distortion;
  const cv::Mat grey = gp::render_pattern(camera, g, params.pattern_radiometry, station.id, pv, rp);
  for (int j = 0; j < camera.image_height; ++j) {
    const uint8_t* m = mask.ptr<uint8_t>(j);
    const uint8_t* src = grey.ptr<uint8_t>(j);
    double* out = radiance.ptr<double>(j);
    for (int i = 0; i < camera.image_width; ++i) {
      if (m[i]) out[i] = src[i] - params.render.background_grey;
    }
  }
  return covered;
}

// The strips that can show in `view`: the ceiling footprint of the image is
// the region bounded by the footprints of its border pixels (the map from a
// rising ray to the ceiling is continuous and one to one), so its bounding
// box holds every pixel footprint; a strip whose box misses it is never a
// candidate of any pixel and rendering without it gives the same frame.
// Every strip is kept when a border pixel's footprint does not rise (the
// horizon is in view: the footprint is unbounded).
golden::CeilingScene visible_strips(const host::CameraConfig& camera,
                                    const golden::CeilingScene& strips,
                                    const golden::CameraView& view, bool distorted) {
  const auto rays = golden::pixel_rays(camera, distorted);
  const Eigen::Matrix3d to_world = view.world_to_camera.transpose();
  const double above = camera.ceiling_height_m - view.centre.z();
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  const int w = camera.image_width, h = camera.image_height;
  auto add_pixel = [&](int i, int j) {
    const golden::PixelRay& ray =
        (*rays)[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                static_cast<std::size_t>(i)];
    if (!ray.valid) return false;
    for (int c = 0; c < 4; ++c) {
      const double a = (c & 1) - 0.5, b = (c >> 1) - 0.5;
      const Eigen::Vector3d d = to_world * Eigen::Vector3d(ray.x + ray.j00 * a + ray.j01 * b,
                                                           ray.y + ray.j10 * a + ray.j11 * b, 1.0);
      if (!(d.z() > 0.0)) return false;
      const double x = view.centre.x() + above / d.z() * d.x();
      const double y = view.centre.y() + above / d.z() * d.y();
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
    return true;
  };
  for (int i = 0; i < w; ++i) {
    if (!add_pixel(i, 0) || !add_pixel(i, h - 1)) return strips;
  }
  for (int j = 0; j < h; ++j) {
    if (!add_pixel(0, j) || !add_pixel(w - 1, j)) return strips;
  }
  // A margin for the renderer's own rounding.
  const double margin = 1e-6 * (1.0 + std::max(x1 - x0, y1 - y0));
  golden::CeilingScene out;
  out.reference_y_m = strips.reference_y_m;
  const double cx = view.centre.x(), cy = view.centre.y();
  for (const golden::TapeSegment& t : strips.tapes) {
    // The strip's box on the default plane: its points scaled toward the
    // camera by 1 / k, k = its ceiling above the camera / the default's.
    const double k =
        t.ceiling_height_m != 0.0 ? (t.ceiling_height_m - view.centre.z()) / above : 1.0;
    const double hw = 0.5 * t.width_m;
    const double bx0 = cx + (std::min(t.x0_m, t.x1_m) - hw - cx) / k;
    const double bx1 = cx + (std::max(t.x0_m, t.x1_m) + hw - cx) / k;
    const double by0 = cy + (std::min(t.y0_m, t.y1_m) - hw - cy) / k;
    const double by1 = cy + (std::max(t.y0_m, t.y1_m) + hw - cy) / k;
    if (bx1 < x0 - margin || bx0 > x1 + margin || by1 < y0 - margin || by0 > y1 + margin) continue;
    out.tapes.push_back(t);
  }
  return out;
}

}  // namespace

void PoseTrack::add(double t_s, const nav::Pose2& pose) {
  if (!times_.empty() && !(t_s > times_.back())) {
    throw std::invalid_argument("PoseTrack::add: times must increase");
  }
  times_.push_back(t_s);
  poses_.push_back(pose);
}

nav::Pose2 PoseTrack::at(double t_s) const {
  if (times_.empty()) throw std::logic_error("PoseTrack::at: no poses");
  if (t_s <= times_.front()) return poses_.front();
  if (t_s >= times_.back()) return poses_.back();
  const auto it = std::upper_bound(times_.begin(), times_.end(), t_s);
  const auto k = static_cast<std::size_t>(it - times_.begin());
  const double f = (t_s - times_[k - 1]) / (times_[k] - times_[k - 1]);
  const nav::Pose2 &a = poses_[k - 1], &b = poses_[k];
  return {a.x_m + f * (b.x_m - a.x_m), a.y_m + f * (b.y_m - a.y_m),
          nav::wrap_angle(a.yaw_rad + f * nav::wrap_angle(b.yaw_rad - a.yaw_rad))};
}

golden::CameraView camera_view(const host::CameraConfig& camera, const CameraMount& mount,
                               const nav::Pose2& robot) {
  const CameraWorldPose pose = camera_pose(camera, mount, robot);
  return {pose.centre, pose.world_to_camera};
}

StationFrame station_frame(const Course& course, const PatternStation& station,
                           const golden::pattern::PatternGeometry& geometry) {
  const double c = std::cos(station.yaw_rad), s = std::sin(station.yaw_rad);
  StationFrame f;
  // x = y cross z for y = (c, s, 0), z = (0, 0, -1) (face down).
  f.axes << -s, c, 0.0,  //
      c, s, 0.0,         //
      0.0, 0.0, -1.0;
  f.origin = {station.x_m, station.y_m,
              course.ceiling_height_at(station.x_m, station.y_m) - geometry.thickness_m};
  return f;
}

cv::Mat course_radiance(const host::CameraConfig& camera, const Course& course,
                        const golden::CeilingScene& strips, const golden::CameraView& view,
                        const DriveRenderParams& params, int* pattern_pixels) {
  const bool distorted = params.render.apply_distortion && camera.has_distortion();
  cv::Mat radiance = golden::render_radiance(
      camera, visible_strips(camera, strips, view, distorted), view, params.render);
  int covered = 0;
  for (const PatternStation& station : course.patterns) {
    covered += composite_station(camera, course, station, view, params, radiance);
  }
  if (pattern_pixels != nullptr) *pattern_pixels = covered;
  return radiance;
}

double image_motion_px(const host::CameraConfig& camera, const Course& course,
                       const golden::CameraView& from, const golden::CameraView& mid,
                       const golden::CameraView& to) {
  const Eigen::Matrix3d to_world = from.world_to_camera.transpose();
  const double height = course.ceiling_height_at(from.centre.x(), from.centre.y());
  double worst = 0.0;
  for (int a = 0; a < 5; ++a) {
    for (int b = 0; b < 5; ++b) {
      const double u = (a + 0.5) / 5.0 * camera.image_width - 0.5;
      const double v = (b + 0.5) / 5.0 * camera.image_height - 0.5;
      const Eigen::Vector3d dir = to_world * Eigen::Vector3d((u - camera.cx()) / camera.fx(),
                                                             (v - camera.cy()) / camera.fy(), 1.0);
      if (!(dir.z() > 1e-9)) continue;
      const Eigen::Vector3d point = from.centre + (height - from.centre.z()) / dir.z() * dir;
      const auto p0 = project_pinhole(camera, from, point);
      const auto p1 = project_pinhole(camera, mid, point);
      const auto p2 = project_pinhole(camera, to, point);
      if (!p0 || !p1 || !p2) continue;
      worst = std::max(worst, (*p1 - *p0).norm() + (*p2 - *p1).norm());
    }
  }
  return worst;
}

cv::Mat render_drive_float(const host::CameraConfig& camera, const Course& course,
                           const CameraMount& mount, const PoseAt& robot_pose_at, double t_s,
                           double t_exp_s, const DriveRenderParams& params, DriveFrameInfo* info) {
  if (!(t_exp_s >= 0.0) || !std::isfinite(t_exp_s) || !std::isfinite(t_s)) {
    throw std::invalid_argument("render_drive_frame: t and t_exp must be finite, t_exp >= 0");
  }
  if (!(params.max_step_px > 0.0) || params.max_subexposures < 1) {
    throw std::invalid_argument("render_drive_frame: max_step_px > 0, max_subexposures >= 1");
  }
  const golden::CeilingScene strips = ceiling_scene(course);
  DriveFrameInfo local;
  local.motion_px = image_motion_px(camera, course, camera_view(camera, mount, robot_pose_at(t_s)),
                                    camera_view(camera, mount, robot_pose_at(t_s + 0.5 * t_exp_s)),
                                    camera_view(camera, mount, robot_pose_at(t_s + t_exp_s)));
  const double wanted = std::ceil(local.motion_px / params.max_step_px);
  const int k_count =
      t_exp_s > 0.0 ? static_cast<int>(std::clamp(wanted, 1.0, double(params.max_subexposures)))
                    : 1;
  local.subexposures = k_count;
  cv::Mat sum(camera.image_height, camera.image_width, CV_64FC1, cv::Scalar(0.0));
  for (int k = 0; k < k_count; ++k) {
    const double t = t_s + (k + 0.5) * t_exp_s / k_count;
    int covered = 0;
    sum += course_radiance(camera, course, strips, camera_view(camera, mount, robot_pose_at(t)),
                           params, &covered);
    local.pattern_pixels += covered;
  }
  if (k_count > 1) sum *= 1.0 / k_count;
  if (params.frame_index >= 0) {
    golden::RenderParams quiet = params.render;
    quiet.noise_sigma_grey = 0.0;
    golden::finish_render(sum, quiet);
    add_frame_noise(sum, params.render.noise_sigma_grey, params.render.noise_seed,
                    params.frame_index);
  } else {
    golden::finish_render(sum, params.render);
  }
  if (info != nullptr) *info = local;
  return sum;
}

void add_frame_noise(cv::Mat& image, double sigma_grey, uint64_t seed, int64_t frame) {
  if (image.type() != CV_64FC1) throw std::invalid_argument("add_frame_noise: needs CV_64FC1");
  if (!(sigma_grey >= 0.0) || !std::isfinite(sigma_grey))
    throw std::invalid_argument("add_frame_noise: sigma must be finite and >= 0");
  if (sigma_grey == 0.0) return;
  constexpr uint64_t kPool = uint64_t{1} << 20;
  static const std::vector<double> pool = [] {
    std::vector<double> p(kPool);
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n(0.0, 1.0);
    for (double& v : p) v = n(rng);
    return p;
  }();
  // splitmix64 of (seed, frame): an offset and an odd stride.
  const auto mix = [](uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  const uint64_t h1 = mix(seed ^ mix(static_cast<uint64_t>(frame)));
  const uint64_t h2 = mix(h1);
  uint64_t at = h1 & (kPool - 1);
  const uint64_t stride = (h2 & (kPool - 1)) | 1u;
  for (int j = 0; j < image.rows; ++j) {
    double* row = image.ptr<double>(j);
    for (int i = 0; i < image.cols; ++i) {
      row[i] += sigma_grey * pool[at];
      at = (at + stride) & (kPool - 1);
    }
  }
}

cv::Mat render_drive_frame(const host::CameraConfig& camera, const Course& course,
                           const CameraMount& mount, const PoseAt& robot_pose_at, double t_s,
                           double t_exp_s, const DriveRenderParams& params, DriveFrameInfo* info) {
  cv::Mat grey;
  render_drive_float(camera, course, mount, robot_pose_at, t_s, t_exp_s, params, info)
      .convertTo(grey, CV_8UC1);  // rounds and saturates
  return grey;
}

TapeTruth tape_truth(const host::CameraConfig& camera, const Course& course,
                     const CameraWorldPose& pose) {
  TapeTruth truth;
  const Eigen::Vector3d axis = pose.world_to_camera.row(2).transpose();
  const Eigen::Vector3d& c = pose.centre;
  Point2 look{c.x(), c.y()};
  if (axis.z() > 1e-6) {
    // Where the optical axis meets the ceiling, with the height there (twice:
    // the look point may lie in another zone than the camera).
    double above = course.ceiling_height_at(c.x(), c.y()) - c.z();
    for (int pass = 0; pass < 2; ++pass) {
      look = {c.x() + axis.x() * above / axis.z(), c.y() + axis.y() * above / axis.z()};
      above = course.ceiling_height_at(look.x_m, look.y_m) - c.z();
    }
  }
  truth.look_point = look;
  truth.ceiling_above_camera_m = course.ceiling_height_at(look.x_m, look.y_m) - c.z();
  double best = 1e300;
  Point2 nearest;
  for (std::size_t t = 0; t < course.tapes.size(); ++t) {
    const std::vector<Point2>& pts = course.tapes[t].points;
    for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
      const double dx = pts[k + 1].x_m - pts[k].x_m, dy = pts[k + 1].y_m - pts[k].y_m;
      const double len2 = dx * dx + dy * dy;
      const double f = std::clamp(
          ((look.x_m - pts[k].x_m) * dx + (look.y_m - pts[k].y_m) * dy) / len2, 0.0, 1.0);
      const Point2 q{pts[k].x_m + f * dx, pts[k].y_m + f * dy};
      const double d = std::hypot(look.x_m - q.x_m, look.y_m - q.y_m);
      if (d < best) {
        best = d;
        nearest = q;
        truth.tape = static_cast<int>(t);
        truth.segment = static_cast<int>(k);
      }
    }
  }
  if (truth.tape < 0) return truth;
  const std::vector<Point2>& pts = course.tapes[static_cast<std::size_t>(truth.tape)].points;
  const Point2& a = pts[static_cast<std::size_t>(truth.segment)];
  const Point2& b = pts[static_cast<std::size_t>(truth.segment) + 1];
  const double heading = pose.heading_rad();
  double dir = std::atan2(b.y_m - a.y_m, b.x_m - a.x_m);
  if (std::abs(nav::wrap_angle(heading - dir)) > 0.5 * std::numbers::pi) dir += std::numbers::pi;
  truth.tape_heading_rad = nav::wrap_angle(dir);
  truth.yaw_rad = nav::wrap_angle(heading - dir);
  truth.offset_m = std::cos(dir) * (c.y() - a.y_m) - std::sin(dir) * (c.x() - a.x_m);
  // In view: the nearest point, on its ceiling, projects into the image.
  const Eigen::Vector3d p(nearest.x_m, nearest.y_m,
                          course.ceiling_height_at(nearest.x_m, nearest.y_m));
  const Eigen::Vector3d pc = pose.world_to_camera * (p - c);
  if (pc.z() > 0.0) {
    const Eigen::Vector2d xy =
        golden::distort_normalised(camera, Eigen::Vector2d(pc.x() / pc.z(), pc.y() / pc.z()));
    const double u = camera.fx() * xy.x() + camera.cx(), v = camera.fy() * xy.y() + camera.cy();
    truth.in_view =
        u >= -0.5 && u < camera.image_width - 0.5 && v >= -0.5 && v < camera.image_height - 0.5;
  }
  return truth;
}

}  // namespace ceilnav::sim
