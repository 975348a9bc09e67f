#include "golden/corridor/render.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

namespace ceilnav::golden::corridor {
namespace {

// The six faces of the box; face coordinates (a, b): ceiling and floor
// (x, y), side walls (x, z), end walls (y, z).
enum Face : int { kCeiling, kFloor, kLeft, kRight, kFar, kNear, kFaces };

// What a surface point shows: a lamp's own radiance, or an albedo lit by the
// face's light.
struct Paint {
  bool emissive = false;
  double value = 0.0;
};

// A periodic set of axis-aligned rectangles on a face: [a_lo + i pa, a_hi +
// i pa] x [b_lo + j pb, b_hi + j pb] for i in [i0, i1], j in [j0, j1]; a single
// rectangle has one index and a period longer than itself.
struct Family {
  double a_lo, a_hi, pa;
  long i0, i1;
  double b_lo, b_hi, pb;
  long j0, j1;
  Paint paint;
};

// floor(v) for |v| < 2^62 without a library call.
long floor_long(double v) {
  const auto k = static_cast<long>(v);
  return static_cast<double>(k) > v ? k - 1 : k;
}

// The index of the rectangle whose interval holds c, or nothing.
bool interval_index(double c, double lo, double hi, double p, long k0, long k1, long& k) {
  k = floor_long((c - lo) / p);
  if (k < k0 || k > k1) return false;
  const double shift = static_cast<double>(k) * p;
  return c >= lo + shift && c <= hi + shift;
}

// Whether some rectangle's interval meets [c0, c1].
bool interval_overlaps(double c0, double c1, double lo, double hi, double p, long k0, long k1) {
  const long first = std::max(k0, -floor_long((hi - c0) / p));  // ceil((c0 - hi) / p)
  const long last = std::min(k1, floor_long((c1 - lo) / p));
  return first <= last;
}

Family single(double a0, double a1, double b0, double b1, Paint paint) {
  return {a0, a1, a1 - a0 + 1.0, 0, 0, b0, b1, b1 - b0 + 1.0, 0, 0, paint};
}

struct Hit {
  int face;
  double a, b;
};

struct Scene {
  double half_width, height, x_start, x_end;
  bool far_open;
  std::array<Paint, kFaces> base;
  std::array<std::vector<Family>, kFaces> families;  // bottom to top (later paints over)
  Lighting light;
  Eigen::Vector3d centre;
  Eigen::Matrix3d to_world;  // camera -> world (R^T)

  // The face the ray (x, y, 1) (camera axes) meets: the camera is inside the
  // box, so exactly one (the nearest plane it rises, falls or runs towards).
  Hit hit(double x, double y) const {
    const Eigen::Vector3d d = to_world.col(0) * x + to_world.col(1) * y + to_world.col(2);
    double t = std::numeric_limits<double>::infinity();
    int face = kCeiling;
    auto consider = [&](double tt, int f) {
      if (tt < t) {
        t = tt;
        face = f;
      }
    };
    if (d.z() > 0.0) consider((height - centre.z()) / d.z(), kCeiling);
    if (d.z() < 0.0) consider(-centre.z() / d.z(), kFloor);
    if (d.y() > 0.0) consider((half_width - centre.y()) / d.y(), kLeft);
    if (d.y() < 0.0) consider((-half_width - centre.y()) / d.y(), kRight);
    if (d.x() > 0.0) consider((x_end - centre.x()) / d.x(), kFar);
    if (d.x() < 0.0) consider((x_start - centre.x()) / d.x(), kNear);
    const Eigen::Vector3d p = centre + t * d;
    switch (face) {
      case kCeiling:
      case kFloor:
        return {face, p.x(), p.y()};
      case kLeft:
      case kRight:
        return {face, p.x(), p.z()};
      default:
        return {face, p.y(), p.z()};
    }
  }

  const Paint& paint_at(const Hit& h) const {
    const std::vector<Family>& fams = families[static_cast<std::size_t>(h.face)];
    for (auto f = fams.rbegin(); f != fams.rend(); ++f) {
      long i = 0, j = 0;
      if (interval_index(h.a, f->a_lo, f->a_hi, f->pa, f->i0, f->i1, i) &&
          interval_index(h.b, f->b_lo, f->b_hi, f->pb, f->j0, f->j1, j)) {
        return f->paint;
      }
    }
    return base[static_cast<std::size_t>(h.face)];
  }

  double light_at(const Hit& h) const {
    switch (h.face) {
      case kCeiling:
        return light.ceiling_light;
      case kFloor:
        return light.floor_light;
      default:
        return light.wall_light_floor + (light.wall_light_ceiling - light.wall_light_floor) *
                                            std::clamp(h.b / height, 0.0, 1.0);
    }
  }

  double radiance(const Hit& h) const {
    const Paint& p = paint_at(h);
    return p.emissive ? p.value : p.value * light_at(h);
  }

  // The paint of a footprint whose four corner hits lie on one face (then
  // the whole footprint does: the face and the ray footprint are convex),
  // when one paint covers all of it; nullptr when a feature's border may
  // cross it. Top-down, the first family whose rectangles can meet the
  // corners' box decides: all four corners in one of its rectangles (convex)
  // is that paint, anything else may be mixed.
  const Paint* uniform_paint(const std::array<Hit, 4>& c) const {
    const double a0 = std::min({c[0].a, c[1].a, c[2].a, c[3].a});
    const double a1 = std::max({c[0].a, c[1].a, c[2].a, c[3].a});
    const double b0 = std::min({c[0].b, c[1].b, c[2].b, c[3].b});
    const double b1 = std::max({c[0].b, c[1].b, c[2].b, c[3].b});
    const std::vector<Family>& fams = families[static_cast<std::size_t>(c[0].face)];
    for (auto f = fams.rbegin(); f != fams.rend(); ++f) {
      if (!interval_overlaps(a0, a1, f->a_lo, f->a_hi, f->pa, f->i0, f->i1) ||
          !interval_overlaps(b0, b1, f->b_lo, f->b_hi, f->pb, f->j0, f->j1)) {
        continue;
      }
      long i = 0, j = 0;
      if (!interval_index(c[0].a, f->a_lo, f->a_hi, f->pa, f->i0, f->i1, i) ||
          !interval_index(c[0].b, f->b_lo, f->b_hi, f->pb, f->j0, f->j1, j)) {
        return nullptr;
      }
      const double sa = static_cast<double>(i) * f->pa, sb = static_cast<double>(j) * f->pb;
      for (const Hit& h : c) {
        if (!(h.a >= f->a_lo + sa && h.a <= f->a_hi + sa && h.b >= f->b_lo + sb &&
              h.b <= f->b_hi + sb)) {
          return nullptr;
        }
      }
      return &f->paint;
    }
    return &base[static_cast<std::size_t>(c[0].face)];
  }
};

Scene build_scene(const Corridor& c, const CameraView& view) {
  Scene s;
  s.half_width = 0.5 * c.width_m;
  s.height = c.ceiling_height_m;
  s.x_start = c.x_start_m;
  s.x_end = c.x_end_m();
  s.far_open = c.far_end_open;
  s.light = c.lighting;
  s.centre = view.centre;
  s.to_world = view.world_to_camera.transpose();
  s.base[kCeiling] = {false, c.ceiling_albedo};
  s.base[kFloor] = {false, c.floor_albedo};
  s.base[kLeft] = s.base[kRight] = {false, c.wall_albedo};
  s.base[kFar] =
      c.far_end_open ? Paint{true, c.lighting.open_radiance} : Paint{false, c.end_wall_albedo};
  s.base[kNear] = {false, c.end_wall_albedo};
  const double hw = s.half_width, h = s.height, x0 = s.x_start, x1 = s.x_end;
  auto& ceiling = s.families[kCeiling];
  const Seams& seams = c.seams;
  const double sw = 0.5 * seams.width_m;
  if (seams.along_pitch_m > 0.0) {
    const double p = seams.along_pitch_m;
    const auto j0 = static_cast<long>(std::ceil((-hw + sw - seams.along_origin_m) / p));
    const auto j1 = static_cast<long>(std::floor((hw - sw - seams.along_origin_m) / p));
    if (j0 <= j1) {
      ceiling.push_back({x0,
                         x1,
                         x1 - x0 + 1.0,
                         0,
                         0,
                         seams.along_origin_m - sw,
                         seams.along_origin_m + sw,
                         p,
                         j0,
                         j1,
                         {false, seams.albedo}});
    }
  }
  if (seams.across_pitch_m > 0.0) {
    const double p = seams.across_pitch_m;
    const auto i0 = static_cast<long>(std::ceil((x0 + sw - seams.across_origin_m) / p));
    const auto i1 = static_cast<long>(std::floor((x1 - sw - seams.across_origin_m) / p));
    if (i0 <= i1) {
      ceiling.push_back({seams.across_origin_m - sw,
                         seams.across_origin_m + sw,
                         p,
                         i0,
                         i1,
                         -hw,
                         hw,
                         2.0 * hw + 1.0,
                         0,
                         0,
                         {false, seams.albedo}});
    }
  }
  const Lamps& l = c.lamps;
  if (!l.rows_y_m.empty()) {
    const auto n =
        static_cast<long>(std::floor((x1 - 0.5 * l.length_m - l.first_x_m) / l.spacing_m + 1e-9));
    for (double y : l.rows_y_m) {
      ceiling.push_back({l.first_x_m - 0.5 * l.length_m,
                         l.first_x_m + 0.5 * l.length_m,
                         l.spacing_m,
                         0,
                         n,
                         y - 0.5 * l.width_m,
                         y + 0.5 * l.width_m,
                         l.width_m + 1.0,
                         0,
                         0,
                         {true, l.radiance}});
    }
  }
  for (int face : {kLeft, kRight}) {
    auto& wall = s.families[static_cast<std::size_t>(face)];
    if (c.skirting.height_m > 0.0) {
      wall.push_back(single(x0, x1, 0.0, c.skirting.height_m, {false, c.skirting.albedo}));
    }
    if (c.cornice.height_m > 0.0) {
      wall.push_back(single(x0, x1, h - c.cornice.height_m, h, {false, c.cornice.albedo}));
    }
    for (const Door& d : c.doors) {
      if ((d.wall == Wall::left) != (face == kLeft)) continue;
      const double fw = d.frame_width_m;
      if (fw > 0.0) {
        wall.push_back(single(d.x_m - fw, d.x_m + d.width_m + fw, 0.0, d.height_m + fw,
                              {false, d.frame_albedo}));
      }
      wall.push_back(single(d.x_m, d.x_m + d.width_m, 0.0, d.height_m, {false, d.albedo}));
    }
  }
  return s;
}

void check_params(const RenderParams& p) {
  if (p.supersample < 1 || p.supersample > 64) {
    throw std::invalid_argument("corridor render: supersample must be in [1, 64]");
  }
  if (!std::isfinite(p.gain_grey) || !std::isfinite(p.background_grey) ||
      !(p.blur_sigma_px >= 0.0) || !(p.noise_sigma_grey >= 0.0)) {
    throw std::invalid_argument(
        "corridor render: gain and background finite, blur and noise sigmas >= 0");
  }
}

}  // namespace

cv::Mat render_radiance(const host::CameraConfig& camera, const Corridor& corridor,
                        const CameraView& view, const RenderParams& params, RenderStats* stats) {
  check_params(params);
  validate(corridor);
  if (!view.centre.allFinite() || !view.world_to_camera.allFinite()) {
    throw std::invalid_argument("corridor render: the camera view must be finite");
  }
  const Eigen::Vector3d& c = view.centre;
  if (!(c.x() > corridor.x_start_m && c.x() < corridor.x_end_m() &&
        std::abs(c.y()) < 0.5 * corridor.width_m && c.z() > 0.0 &&
        c.z() < corridor.ceiling_height_m)) {
    throw CorridorError("corridor render: the camera must be inside the corridor");
  }
  const Scene scene = build_scene(corridor, view);
  const bool distorted = params.apply_distortion && camera.has_distortion();
  const auto rays = lens_pixel_rays(camera, distorted);
  const int w = camera.image_width, h = camera.image_height, n = params.supersample;
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::vector<double> ja(cells), jb(cells);
  RenderStats local;
  cv::Mat radiance(h, w, CV_64FC1, cv::Scalar(0.0));

  // The value of a pixel whose footprint lies on one face in one paint. The
  // ceiling's and floor's light is constant; on the walls it varies smoothly
  // and (2 centre + mean of the corners) / 3 integrates a quadratic over the
  // footprint exactly (a 2-D Simpson rule from the corner hits).
  auto uniform_value = [&](const Paint& paint, int face, const PixelRay& ray,
                           const std::array<Hit, 4>* corners) {
    if (paint.emissive) return paint.value;
    if (face == kCeiling || face == kFloor) return paint.value * scene.light_at({face, 0.0, 0.0});
    std::array<Hit, 4> own{};
    if (corners == nullptr) {
      for (std::size_t q = 0; q < 4; ++q) {
        const double a = static_cast<double>(q & 1U) - 0.5, b = static_cast<double>(q >> 1U) - 0.5;
        own[q] = scene.hit(ray.x + ray.j00 * a + ray.j01 * b, ray.y + ray.j10 * a + ray.j11 * b);
      }
      corners = &own;
    }
    const std::array<Hit, 4>& c4 = *corners;
    const double corners_light = 0.25 * (scene.light_at(c4[0]) + scene.light_at(c4[1]) +
                                         scene.light_at(c4[2]) + scene.light_at(c4[3]));
    return paint.value * (2.0 * scene.light_at(scene.hit(ray.x, ray.y)) + corners_light) / 3.0;
  };

  auto render_pixel = [&](int i, int j, double* out) {
    const std::size_t k =
        static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
    const PixelRay& ray = (*rays)[k];
    if (!ray.valid) return;  // where the lens model folds over: 0, as the tape renderer
    if (params.adaptive_sampling) {
      std::array<Hit, 4> corners{};
      bool one_face = true;
      for (std::size_t q = 0; q < 4; ++q) {
        const double a = static_cast<double>(q & 1U) - 0.5, b = static_cast<double>(q >> 1U) - 0.5;
        corners[q] =
            scene.hit(ray.x + ray.j00 * a + ray.j01 * b, ray.y + ray.j10 * a + ray.j11 * b);
        one_face = one_face && corners[q].face == corners[0].face;
      }
      const Paint* paint = one_face ? scene.uniform_paint(corners) : nullptr;
      if (paint != nullptr) {
        out[i] = uniform_value(*paint, corners[0].face, ray, &corners);
        ++local.uniform_pixels;
        ++local.samples;
        return;
      }
    }
    jittered_offsets(k, n, ja.data(), jb.data());
    double sum = 0.0;
    for (std::size_t m = 0; m < cells; ++m) {
      sum += scene.radiance(scene.hit(ray.x + ray.j00 * ja[m] + ray.j01 * jb[m],
                                      ray.y + ray.j10 * ja[m] + ray.j11 * jb[m]));
    }
    out[i] = sum / static_cast<double>(cells);
    ++local.edge_pixels;
    local.samples += static_cast<int64_t>(cells);
  };

  // Tiles of kTile x kTile pixels: the box (in normalised coordinates) of
  // every footprint corner ray of the tile's pixels is convex, so when its
  // four corner rays meet one face all its rays do, and their hits lie in the
  // convex quadrilateral of the corners' hits; when one paint covers that
  // (uniform_paint), every pixel of the tile is a uniform pixel of that paint
  // (its own classification would find the same), valued as render_pixel
  // values it, without the per-pixel classification.
  constexpr int kTile = 8;
  for (int j0 = 0; j0 < h; j0 += kTile) {
    const int j1 = std::min(h, j0 + kTile);
    for (int i0 = 0; i0 < w; i0 += kTile) {
      const int i1 = std::min(w, i0 + kTile);
      const Paint* tile_paint = nullptr;
      int tile_face = 0;
      if (params.adaptive_sampling) {
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        bool valid = true;
        for (int j = j0; j < j1 && valid; ++j) {
          for (int i = i0; i < i1; ++i) {
            const PixelRay& ray =
                (*rays)[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                        static_cast<std::size_t>(i)];
            if (!ray.valid) {
              valid = false;
              break;
            }
            // The footprint corners x + J (+-1/2, +-1/2) lie in this box,
            // widened by far more than the rounding of either computation.
            const double rx = 0.5 * (std::abs(ray.j00) + std::abs(ray.j01)) * (1.0 + 1e-9);
            const double ry = 0.5 * (std::abs(ray.j10) + std::abs(ray.j11)) * (1.0 + 1e-9);
            x0 = std::min(x0, ray.x - rx);
            x1 = std::max(x1, ray.x + rx);
            y0 = std::min(y0, ray.y - ry);
            y1 = std::max(y1, ray.y + ry);
          }
        }
        if (valid) {
          const std::array<Hit, 4> corners{scene.hit(x0, y0), scene.hit(x1, y0), scene.hit(x0, y1),
                                           scene.hit(x1, y1)};
          if (corners[0].face == corners[1].face && corners[0].face == corners[2].face &&
              corners[0].face == corners[3].face) {
            tile_paint = scene.uniform_paint(corners);
            tile_face = corners[0].face;
          }
        }
      }
      for (int j = j0; j < j1; ++j) {
        double* out = radiance.ptr<double>(j);
        for (int i = i0; i < i1; ++i) {
          if (tile_paint == nullptr) {
            render_pixel(i, j, out);
            continue;
          }
          const PixelRay& ray = (*rays)[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                        static_cast<std::size_t>(i)];
          out[i] = uniform_value(*tile_paint, tile_face, ray, nullptr);
          ++local.uniform_pixels;
          ++local.samples;
        }
      }
    }
  }
  if (stats != nullptr) *stats = local;
  return radiance;
}

Pose interpolate(const Pose& a, const Pose& b, double f) {
  auto mix = [f](double p, double q) { return p + f * (q - p); };
  return {mix(a.x_m, b.x_m),         mix(a.y_m, b.y_m),           mix(a.height_m, b.height_m),
          mix(a.pan_rad, b.pan_rad), mix(a.tilt_rad, b.tilt_rad), mix(a.swing_rad, b.swing_rad)};
}

Pose mid_exposure(const Exposure& e) {
  return interpolate(e.start, e.end, 0.5);
}

cv::Mat render_float(const host::CameraConfig& camera, const Corridor& corridor,
                     const Exposure& exposure, const RenderParams& params, RenderStats* stats) {
  if (exposure.subexposures < 1 || exposure.subexposures > 256) {
    throw std::invalid_argument("corridor render: subexposures must be in [1, 256]");
  }
  const int k_count = exposure.subexposures;
  cv::Mat sum;
  RenderStats total;
  for (int k = 0; k < k_count; ++k) {
    const Pose pose = k_count == 1 ? exposure.start
                                   : interpolate(exposure.start, exposure.end, (k + 0.5) / k_count);
    RenderStats one;
    cv::Mat r = render_radiance(camera, corridor, view_of(pose), params, &one);
    total.uniform_pixels += one.uniform_pixels;
    total.edge_pixels += one.edge_pixels;
    total.samples += one.samples;
    if (k == 0) {
      sum = r;
    } else {
      sum += r;
    }
  }
  sum *= params.gain_grey / k_count;
  golden::RenderParams finish;
  finish.background_grey = params.background_grey;
  finish.blur_sigma_px = params.blur_sigma_px;
  finish.noise_sigma_grey = params.noise_sigma_grey;
  finish.noise_seed = params.noise_seed;
  finish_render(sum, finish);
  if (stats != nullptr) *stats = total;
  return sum;
}

cv::Mat render_float(const host::CameraConfig& camera, const Corridor& corridor, const Pose& pose,
                     const RenderParams& params, RenderStats* stats) {
  return render_float(camera, corridor, Exposure{pose, pose, 1}, params, stats);
}

cv::Mat render_frame(const host::CameraConfig& camera, const Corridor& corridor,
                     const Exposure& exposure, const RenderParams& params) {
  cv::Mat grey;
  render_float(camera, corridor, exposure, params).convertTo(grey, CV_8UC1);
  return grey;
}

cv::Mat render_frame(const host::CameraConfig& camera, const Corridor& corridor, const Pose& pose,
                     const RenderParams& params) {
  return render_frame(camera, corridor, Exposure{pose, pose, 1}, params);
}

}  // namespace ceilnav::golden::corridor
