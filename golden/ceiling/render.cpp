#include "golden/ceiling/render.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "golden/scene.hpp"

namespace ceilnav::golden::ceiling {
namespace {

void check_params(const RenderParams& p) {
  if (p.supersample < 1 || p.supersample > 16) {
    throw std::invalid_argument("ceiling render: supersample must be 1 .. 16");
  }
  if (!(std::isfinite(p.gain_grey) && p.gain_grey >= 0.0) || !(std::isfinite(p.background_grey)) ||
      !(std::isfinite(p.blur_sigma_px) && p.blur_sigma_px >= 0.0) ||
      !(std::isfinite(p.noise_sigma_grey) && p.noise_sigma_grey >= 0.0)) {
    throw std::invalid_argument("ceiling render: gain, blur and noise must be finite and >= 0");
  }
}

// The features of `c` that can reach into the box [x0, x1] x [y0, y1]
// (their circumscribed circles meet it); the tiles and the plain ceiling
// kept. The frame's pixels see only that box, so they render the same from
// the cut ceiling, which is cheaper to query.
Ceiling features_within(const Ceiling& c, double x0, double y0, double x1, double y1) {
  const auto meets = [&](double x, double y, double reach) {
    const double dx = std::max({x0 - x, 0.0, x - x1}), dy = std::max({y0 - y, 0.0, y - y1});
    return dx * dx + dy * dy <= reach * reach;
  };
  const auto half_diagonal = [](const Rect& r) {
    return 0.5 * std::sqrt(r.length_m * r.length_m + r.width_m * r.width_m);
  };
  Ceiling out = c;
  out.lamps.clear();
  out.vents.clear();
  out.spots.clear();
  out.beams.clear();
  for (const Lamp& l : c.lamps) {
    if (meets(l.rect.x_m, l.rect.y_m, half_diagonal(l.rect))) out.lamps.push_back(l);
  }
  for (const Vent& v : c.vents) {
    if (meets(v.rect.x_m, v.rect.y_m, half_diagonal(v.rect))) out.vents.push_back(v);
  }
  for (const Spot& s : c.spots) {
    if (meets(s.x_m, s.y_m, s.radius_m)) out.spots.push_back(s);
  }
  for (const Beam& b : c.beams) {
    // The beam's box, widened by half its width.
    const double w = 0.5 * b.width_m;
    if (std::min(b.x0_m, b.x1_m) - w <= x1 && std::max(b.x0_m, b.x1_m) + w >= x0 &&
        std::min(b.y0_m, b.y1_m) - w <= y1 && std::max(b.y0_m, b.y1_m) + w >= y0) {
      out.beams.push_back(b);
    }
  }
  return out;
}

}  // namespace

CameraView view_of(const Pose& pose) {
  const Eigen::Matrix3d r0 = golden::world_to_camera_rotation(pose.yaw_rad, 0.5 * std::numbers::pi);
  const double cp = std::cos(pose.pitch_error_rad), sp = std::sin(pose.pitch_error_rad);
  const double cr = std::cos(pose.roll_error_rad), sr = std::sin(pose.roll_error_rad);
  Eigen::Matrix3d rx, ry;
  rx << 1.0, 0.0, 0.0, 0.0, cp, -sp, 0.0, sp, cp;
  ry << cr, 0.0, sr, 0.0, 1.0, 0.0, -sr, 0.0, cr;
  return {Eigen::Vector3d(pose.x_m, pose.y_m, pose.height_m), rx * ry * r0};
}

std::optional<Eigen::Vector2d> project(const host::CameraConfig& camera, const Ceiling& ceiling,
                                       const Pose& pose, double x_m, double y_m, bool distorted) {
  const CameraView v = view_of(pose);
  const Eigen::Vector3d pc =
      v.world_to_camera * (Eigen::Vector3d(x_m, y_m, ceiling.height_m) - v.centre);
  if (!(pc.z() > 0.0)) return std::nullopt;
  Eigen::Vector2d xy(pc.x() / pc.z(), pc.y() / pc.z());
  if (distorted && camera.has_distortion()) xy = golden::distort_normalised(camera, xy);
  return Eigen::Vector2d(camera.fx() * xy.x() + camera.cx(), camera.fy() * xy.y() + camera.cy());
}

cv::Mat render_radiance(const host::CameraConfig& camera, const Ceiling& ceiling,
                        const Lighting& lighting, const Pose& pose, const RenderParams& params) {
  check_params(params);
  validate(ceiling);
  validate(lighting);
  if (!(std::isfinite(pose.x_m) && std::isfinite(pose.y_m) && std::isfinite(pose.height_m) &&
        std::isfinite(pose.yaw_rad) && std::abs(pose.pitch_error_rad) < 0.5 &&
        std::abs(pose.roll_error_rad) < 0.5 && pose.height_m < ceiling.height_m)) {
    throw std::invalid_argument(
        "ceiling render: the camera must be finite, below the ceiling and within 0.5 rad of "
        "vertical");
  }
  const CameraView view = view_of(pose);
  const Eigen::Matrix3d to_world = view.world_to_camera.transpose();
  const double rise = ceiling.height_m - pose.height_m;
  const bool distorted = params.apply_distortion && camera.has_distortion();
  const auto rays = golden::lens_pixel_rays(camera, distorted);
  const int w = camera.image_width, h = camera.image_height, n = params.supersample;
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::vector<double> ja(cells), jb(cells);
  cv::Mat out(h, w, CV_64FC1, cv::Scalar(0.0));

  // The ceiling point of the normalised ray (x, y); false when the ray does
  // not rise to the ceiling.
  const auto hit = [&](double x, double y, Eigen::Vector2d& p) {
    const Eigen::Vector3d d = to_world * Eigen::Vector3d(x, y, 1.0);
    if (!(d.z() > 1e-9)) return false;
    const double t = rise / d.z();
    p = view.centre.head<2>() + t * d.head<2>();
    return true;
  };
  // The ceiling box the frame can see: the footprints of the border pixels
  // (their rays' corners) bound it; 5 cm of margin.
  double bx0 = 1e300, by0 = 1e300, bx1 = -1e300, by1 = -1e300;
  bool bounded = true;
  for (int j = 0; j < h && bounded; ++j) {
    for (int i = 0; i < w && bounded; i += (j == 0 || j == h - 1) ? 1 : w - 1) {
      const golden::PixelRay& ray =
          (*rays)[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                  static_cast<std::size_t>(i)];
      if (!ray.valid) {
        bounded = false;  // a ray outside the lens model: no box
        break;
      }
      for (int q = 0; q < 4; ++q) {
        const double a = (q & 1) - 0.5, b = (q >> 1) - 0.5;
        Eigen::Vector2d p = Eigen::Vector2d::Zero();
        if (!hit(ray.x + ray.j00 * a + ray.j01 * b, ray.y + ray.j10 * a + ray.j11 * b, p)) {
          bounded = false;
          break;
        }
        bx0 = std::min(bx0, p.x());
        bx1 = std::max(bx1, p.x());
        by0 = std::min(by0, p.y());
        by1 = std::max(by1, p.y());
      }
    }
  }
  const Ceiling seen =
      bounded ? features_within(ceiling, bx0 - 0.05, by0 - 0.05, bx1 + 0.05, by1 + 0.05) : ceiling;
  for (int j = 0; j < h; ++j) {
    auto* row = out.ptr<double>(j);
    for (int i = 0; i < w; ++i) {
      const std::size_t k =
          static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
      const golden::PixelRay& ray = (*rays)[k];
      if (!ray.valid) continue;
      if (params.adaptive_sampling) {
        // The footprint (to the affine approximation a parallelogram, its
        // farthest points from the centre its corners) inside a disc on one
        // paint: no border crosses it, and the light's mean over it is its
        // value at the centre (linear light).
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        if (!hit(ray.x, ray.y, c)) continue;
        double reach = 0.0;
        bool all_hit = true;
        for (int q = 0; q < 4 && all_hit; ++q) {
          const double a = (q & 1) - 0.5, b = (q >> 1) - 0.5;
          Eigen::Vector2d p = c;
          all_hit = hit(ray.x + ray.j00 * a + ray.j01 * b, ray.y + ray.j10 * a + ray.j11 * b, p);
          if (all_hit) reach = std::max(reach, (p - c).norm());
        }
        if (all_hit && border_distance(seen, c.x(), c.y()) > reach) {
          const Paint centre = paint_at(seen, lighting, c.x(), c.y());
          row[i] = centre.emissive ? centre.value * lighting.lamp_gain
                                   : centre.value * light_at(lighting, c.x(), c.y());
          continue;
        }
      }
      golden::jittered_offsets(k, n, ja.data(), jb.data());
      double sum = 0.0;
      for (std::size_t m = 0; m < cells; ++m) {
        Eigen::Vector2d p = Eigen::Vector2d::Zero();
        if (hit(ray.x + ray.j00 * ja[m] + ray.j01 * jb[m],
                ray.y + ray.j10 * ja[m] + ray.j11 * jb[m], p)) {
          sum += radiance_at(seen, lighting, p.x(), p.y());
        }
      }
      row[i] = sum / static_cast<double>(cells);
    }
  }
  return out;
}

cv::Mat render_frame(const host::CameraConfig& camera, const Ceiling& ceiling,
                     const Lighting& lighting, const Pose& pose, const RenderParams& params) {
  cv::Mat img = render_radiance(camera, ceiling, lighting, pose, params);
  img *= params.gain_grey;
  golden::RenderParams finish;
  finish.background_grey = params.background_grey;
  finish.blur_sigma_px = params.blur_sigma_px;
  finish.noise_sigma_grey = params.noise_sigma_grey;
  finish.noise_seed = params.noise_seed;
  golden::finish_render(img, finish);
  cv::Mat grey;
  img.convertTo(grey, CV_8UC1);  // rounds to nearest and saturates
  return grey;
}

}  // namespace ceilnav::golden::ceiling
