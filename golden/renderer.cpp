#include "golden/renderer.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace ceilnav::golden {
namespace {

// ---------------------------------------------------------------------------
// Inverse distortion.

// OpenCV's distortion D(x, y) and its Jacobian dD/d(x, y).
void distort_with_jacobian(const host::CameraConfig& camera, double x, double y, double& xd,
                           double& yd, Eigen::Matrix2d& jac) {
  const auto& k = camera.distortion_coefficients;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
  const double dradial = k[0] + r2 * (2.0 * k[1] + 3.0 * r2 * k[4]);  // d radial / d r2
  xd = x * radial + 2.0 * k[2] * x * y + k[3] * (r2 + 2.0 * x * x);
  yd = y * radial + k[2] * (r2 + 2.0 * y * y) + 2.0 * k[3] * x * y;
  jac(0, 0) = radial + 2.0 * x * x * dradial + 2.0 * k[2] * y + 6.0 * k[3] * x;
  jac(0, 1) = 2.0 * x * y * dradial + 2.0 * k[2] * x + 2.0 * k[3] * y;
  jac(1, 0) = 2.0 * x * y * dradial + 2.0 * k[2] * x + 2.0 * k[3] * y;
  jac(1, 1) = radial + 2.0 * y * y * dradial + 6.0 * k[2] * y + 2.0 * k[3] * x;
}

// Solves D(x, y) = (xd, yd) by Newton from (x, y). On success (x, y) is the
// undistorted point and jac = dD/d(x, y) there (det > 0: no fold-over).
bool undistort_newton(const host::CameraConfig& camera, double xd, double yd, double& x, double& y,
                      Eigen::Matrix2d& jac) {
  const double scale = std::max(1.0, std::abs(xd) + std::abs(yd));
  for (int iteration = 0; iteration < 60; ++iteration) {
    double ex = 0.0, ey = 0.0;
    distort_with_jacobian(camera, x, y, ex, ey, jac);
    ex -= xd;
    ey -= yd;
    const double det = jac.determinant();
    if (!(det > 0.0) || !std::isfinite(det)) return false;
    if (std::abs(ex) + std::abs(ey) <= 4e-16 * scale) return true;
    x -= (jac(1, 1) * ex - jac(0, 1) * ey) / det;
    y -= (-jac(1, 0) * ex + jac(0, 0) * ey) / det;
  }
  double ex = 0.0, ey = 0.0;
  distort_with_jacobian(camera, x, y, ex, ey, jac);
  return std::abs(ex - xd) + std::abs(ey - yd) <= 1e-13 * scale && jac.determinant() > 0.0;
}

// ---------------------------------------------------------------------------
// Per-camera table of pixel-centre rays: normalised (x, y) and the Jacobian
// d(x, y)/d(u, v), so that a sub-sample at offset (a, b) px from the centre has
// the ray (x, y) + J (a, b) (the local affine approximation).

// The rays of a kTile x kTile block of pixels: the box (in normalised
// coordinates) of the corner rays x + J (+-1/2, +-1/2) of its valid pixels,
// each computed exactly as radiance_of computes it, so every footprint corner
// radiance_of evaluates for the block lies in the box.
constexpr int kTile = 8;
struct RayTile {
  double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
  bool any_valid = false;
};

struct RayTable {
  std::vector<PixelRay> rays;  // row-major
  double affine_error_px = 0.0;
  int tiles_x = 0, tiles_y = 0;
  std::vector<RayTile> tiles;  // row-major, tiles_x x tiles_y
};

// A footprint corner ray of a pixel: offset (a, b) = (+-1/2, +-1/2) px from
// its centre (c = 0..3: a from bit 0, b from bit 1).
double corner_offset_a(std::size_t c) {
  return static_cast<double>(c & 1U) - 0.5;
}
double corner_offset_b(std::size_t c) {
  return static_cast<double>(c >> 1U) - 0.5;
}

void build_tiles(RayTable& table, int w, int h) {
  table.tiles_x = (w + kTile - 1) / kTile;
  table.tiles_y = (h + kTile - 1) / kTile;
  table.tiles.assign(
      static_cast<std::size_t>(table.tiles_x) * static_cast<std::size_t>(table.tiles_y), {});
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const PixelRay& ray = table.rays[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                       static_cast<std::size_t>(i)];
      if (!ray.valid) continue;
      RayTile& tile =
          table
              .tiles[static_cast<std::size_t>(j / kTile) * static_cast<std::size_t>(table.tiles_x) +
                     static_cast<std::size_t>(i / kTile)];
      for (std::size_t c = 0; c < 4; ++c) {
        const double a = corner_offset_a(c), b = corner_offset_b(c);
        const double x = ray.x + ray.j00 * a + ray.j01 * b;
        const double y = ray.y + ray.j10 * a + ray.j11 * b;
        if (!tile.any_valid) {
          tile = {x, x, y, y, true};
          continue;
        }
        tile.x0 = std::min(tile.x0, x);
        tile.x1 = std::max(tile.x1, x);
        tile.y0 = std::min(tile.y0, y);
        tile.y1 = std::max(tile.y1, y);
      }
    }
  }
}

struct CameraKey {
  int width, height;
  std::array<double, 9> matrix;
  std::array<double, 5> distortion;
  bool operator==(const CameraKey&) const = default;
};

std::shared_ptr<const RayTable> build_ray_table(const host::CameraConfig& camera, bool distorted) {
  auto table = std::make_shared<RayTable>();
  const int w = camera.image_width, h = camera.image_height;
  const double fx = camera.fx(), fy = camera.fy(), cx = camera.cx(), cy = camera.cy();
  table->rays.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      PixelRay& ray = table->rays[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                  static_cast<std::size_t>(i)];
      const double xd = (i - cx) / fx, yd = (j - cy) / fy;
      if (!distorted) {
        ray = {xd, yd, 1.0 / fx, 0.0, 0.0, 1.0 / fy, true};
        continue;
      }
      double x = xd, y = yd;
      Eigen::Matrix2d jac;
      ray.valid = undistort_newton(camera, xd, yd, x, y, jac);
      // d(x,y)/d(u,v) = (dD/d(x,y))^-1 diag(1/fx, 1/fy)
      const Eigen::Matrix2d inv = jac.inverse();
      ray.x = x;
      ray.y = y;
      ray.j00 = inv(0, 0) / fx;
      ray.j01 = inv(0, 1) / fy;
      ray.j10 = inv(1, 0) / fx;
      ray.j11 = inv(1, 1) / fy;
    }
  }
  build_tiles(*table, w, h);
  if (!distorted) return table;
  // Exact rays through the pixel corners, to measure the affine error where the
  // quadratic remainder is largest.
  const std::size_t cw = static_cast<std::size_t>(w) + 1;
  std::vector<Eigen::Vector2d> corners(cw * (static_cast<std::size_t>(h) + 1));
  std::vector<char> corner_valid(corners.size());
  for (int j = 0; j <= h; ++j) {
    for (int i = 0; i <= w; ++i) {
      const double xd = (i - 0.5 - cx) / fx, yd = (j - 0.5 - cy) / fy;
      double x = xd, y = yd;
      Eigen::Matrix2d jac;
      const std::size_t index = static_cast<std::size_t>(j) * cw + static_cast<std::size_t>(i);
      corner_valid[index] = undistort_newton(camera, xd, yd, x, y, jac) ? 1 : 0;
      corners[index] = {x, y};
    }
  }
  double worst = 0.0;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const PixelRay& ray = table->rays[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                        static_cast<std::size_t>(i)];
      if (!ray.valid) continue;
      for (int corner = 0; corner < 4; ++corner) {
        const int di = corner & 1, dj = corner >> 1;
        const std::size_t index =
            static_cast<std::size_t>(j + dj) * cw + static_cast<std::size_t>(i + di);
        if (!corner_valid[index]) continue;
        const double a = di - 0.5, b = dj - 0.5;
        const double ex = ray.x + ray.j00 * a + ray.j01 * b - corners[index].x();
        const double ey = ray.y + ray.j10 * a + ray.j11 * b - corners[index].y();
        worst = std::max(worst, std::hypot(fx * ex, fy * ey));
      }
    }
  }
  table->affine_error_px = worst;
  return table;
}

// A small cache keyed by the camera: building a distorted table costs two
// Newton solves per pixel, rendering a frame costs much less.
std::shared_ptr<const RayTable> ray_table(const host::CameraConfig& camera, bool distorted) {
  static std::mutex mutex;
  static std::vector<std::pair<CameraKey, std::shared_ptr<const RayTable>>> cache;
  CameraKey key{camera.image_width, camera.image_height, camera.camera_matrix,
                distorted ? camera.distortion_coefficients : std::array<double, 5>{}};
  const std::lock_guard<std::mutex> lock(mutex);
  for (const auto& [cached_key, table] : cache) {
    if (cached_key == key) return table;
  }
  auto table = build_ray_table(camera, distorted);
  constexpr std::size_t kCacheEntries = 4;
  if (cache.size() >= kCacheEntries) cache.erase(cache.begin());
  cache.emplace_back(key, table);
  return table;
}

void check_camera(const host::CameraConfig& camera) {
  if (camera.image_width <= 0 || camera.image_height <= 0) {
    throw std::invalid_argument("renderer: image size must be positive");
  }
  if (!(camera.fx() > 0.0) || !(camera.fy() > 0.0)) {
    throw std::invalid_argument("renderer: fx and fy must be positive");
  }
  if (!(camera.ceiling_above_camera_m() > 0.0)) {
    throw std::invalid_argument("renderer: the ceiling must be above the camera");
  }
}

// ---------------------------------------------------------------------------
// Sampling.

// splitmix64's finaliser: a counter-based generator, so every pixel's jitter
// and noise depend only on (seed, pixel index), not on traversal order.
uint64_t mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double unit_interval(uint64_t bits) {  // [0, 1)
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

constexpr uint64_t kJitterSeed = 0x6a09e667f3bcc909ULL;  // fixed: frames are reproducible

// The jittered-stratified offsets of L pixels (jittered_offsets' definition):
// a[l n^2 + m], b[l n^2 + m] for pixel l and cell m = sy n + sx. Each pixel's
// offsets come from a serial chain of splitmix64 steps; stepping L chains
// side by side lets the processor overlap them.
template <std::size_t L>
void jitter_lanes(const std::size_t* pixel_index, int n, double* a, double* b) {
  const double inv_n = 1.0 / n;
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::array<uint64_t, L> state{};
  for (std::size_t l = 0; l < L; ++l) {
    state[l] = mix64(kJitterSeed ^ (static_cast<uint64_t>(pixel_index[l]) * 0xd1b54a32d192ed03ULL));
  }
  std::size_t m = 0;
  for (int sy = 0; sy < n; ++sy) {
    for (int sx = 0; sx < n; ++sx, ++m) {
      for (std::size_t l = 0; l < L; ++l) {
        state[l] = mix64(state[l]);
        a[l * cells + m] = (sx + unit_interval(state[l])) * inv_n - 0.5;
        state[l] = mix64(state[l]);
        b[l * cells + m] = (sy + unit_interval(state[l])) * inv_n - 0.5;
      }
    }
  }
}

// A tape in its own frame: s along the centre line from (x0, y0), t across it.
struct TapeFrame {
  double ax, ay, ex, ey;
  double length, half_width, reflectance;
  double min_x, max_x, min_y, max_y;  // bounding box
  // k = this strip's ceiling above the camera / the default ceiling's: a ray
  // meets the strip's plane at C + k (p - C), p its point on the default
  // plane, at range k r (radiance / k^2). scaled = (k != 1).
  double scale = 1.0, inv_scale2 = 1.0;
  bool scaled = false;
  // Whether a box [x0, x1] x [y0, y1] on the default plane, taken onto this
  // strip's plane (C + k (q - C)), misses the strip's bounding box. Monotone
  // in the box: a box that holds another misses whatever the other misses.
  bool box_misses(double x0, double x1, double y0, double y1, double cam_x, double cam_y) const {
    if (scaled) {
      x0 = cam_x + scale * (x0 - cam_x);
      x1 = cam_x + scale * (x1 - cam_x);
      y0 = cam_y + scale * (y0 - cam_y);
      y1 = cam_y + scale * (y1 - cam_y);
    }
    return x1 < min_x || x0 > max_x || y1 < min_y || y0 > max_y;
  }
  bool contains(double px, double py) const {
    const double dx = px - ax, dy = py - ay;
    const double s = dx * ex + dy * ey;
    const double t = dy * ex - dx * ey;
    return s >= 0.0 && s <= length && std::abs(t) <= half_width;
  }
};

std::vector<TapeFrame> tape_frames(const CeilingScene& scene, const host::CameraConfig& camera,
                                   double camera_z_m) {
  std::vector<TapeFrame> frames;
  const double default_above = camera.ceiling_height_m - camera_z_m;
  for (const TapeSegment& tape : scene.tapes) {
    const double dx = tape.x1_m - tape.x0_m, dy = tape.y1_m - tape.y0_m;
    const double length = std::hypot(dx, dy);
    if (!(length > 0.0) || !(tape.width_m > 0.0) || !(tape.reflectance >= 0.0)) {
      throw std::invalid_argument("renderer: a tape needs length > 0, width > 0, reflectance >= 0");
    }
    const double hw = 0.5 * tape.width_m;
    // The bounding box grows by the half width in both axes (a safe cover).
    frames.push_back({tape.x0_m, tape.y0_m, dx / length, dy / length, length, hw, tape.reflectance,
                      std::min(tape.x0_m, tape.x1_m) - hw, std::max(tape.x0_m, tape.x1_m) + hw,
                      std::min(tape.y0_m, tape.y1_m) - hw, std::max(tape.y0_m, tape.y1_m) + hw});
    if (tape.ceiling_height_m != 0.0) {
      const double above = tape.ceiling_height_m - camera_z_m;
      if (!(above > 0.0) || !std::isfinite(above)) {
        throw std::invalid_argument("renderer: a tape's ceiling must be above the camera");
      }
      TapeFrame& f = frames.back();
      f.scale = above / default_above;
      f.inv_scale2 = 1.0 / (f.scale * f.scale);
      f.scaled = f.scale != 1.0;
    }
  }
  return frames;
}

// Ray (x, y, 1) in camera coordinates -> point on the ceiling and 1/range^2.
struct CeilingGeometry {
  double cx_m, cy_m, height_m;                // camera X, Y; ceiling above the camera
  double rx, ry, rz, dx, dy, dz, fx, fy, fz;  // rows of R (world vectors)

  // The ceiling point of the ray and its distance parameter t (the point is
  // C + t (x, y, 1) in camera axes); false when the ray does not rise (never
  // meets the ceiling in front).
  bool point(double x, double y, double& px, double& py, double& t) const {
    const double up = x * rz + y * dz + fz;
    if (!(up > 0.0)) return false;
    t = height_m / up;
    px = cx_m + t * (x * rx + y * dx + fx);
    py = cy_m + t * (x * ry + y * dy + fy);
    return true;
  }
  static double inv_range2(double t, double x, double y) {
    return 1.0 / (t * t * (1.0 + x * x + y * y));
  }
  bool hit(double x, double y, double& px, double& py, double& inv_r2) const {
    double t = 0.0;
    if (!point(x, y, px, py, t)) return false;
    inv_r2 = inv_range2(t, x, y);
    return true;
  }
};

// The box on the default ceiling plane that holds the point of every
// footprint corner radiance_of computes for a tile's pixels (their rays lie in
// the tile's box of rays, whose image on the ceiling is the convex
// quadrilateral of its corners' images when every corner rises), widened by a
// margin far above the rounding of either computation. false when the tile's
// rays come near the horizon: the tile is then rendered without culling.
bool tile_footprint(const CeilingGeometry& geo, const RayTile& tile, double& x0, double& x1,
                    double& y0, double& y1) {
  const double mx = std::max(std::abs(tile.x0), std::abs(tile.x1));
  const double my = std::max(std::abs(tile.y0), std::abs(tile.y1));
  const double rise_scale = std::abs(geo.rz) * mx + std::abs(geo.dz) * my + std::abs(geo.fz);
  x0 = y0 = std::numeric_limits<double>::infinity();
  x1 = y1 = -std::numeric_limits<double>::infinity();
  double min_up = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 4; ++c) {
    const double x = (c & 1) ? tile.x1 : tile.x0, y = (c & 2) ? tile.y1 : tile.y0;
    const double up = x * geo.rz + y * geo.dz + geo.fz;
    // The rise is linear in the ray: its smallest value over the box is at a
    // corner, and a well-rising box keeps the division well conditioned.
    double px = 0.0, py = 0.0, t = 0.0;
    if (!(up >= 1e-3 * rise_scale) || !geo.point(x, y, px, py, t)) return false;
    min_up = std::min(min_up, up);
    x0 = std::min(x0, px);
    x1 = std::max(x1, px);
    y0 = std::min(y0, py);
    y1 = std::max(y1, py);
  }
  const double reach = geo.height_m / min_up * (1.0 + mx + my) *
                       (std::abs(geo.rx) + std::abs(geo.dx) + std::abs(geo.fx) + std::abs(geo.ry) +
                        std::abs(geo.dy) + std::abs(geo.fy));
  const double margin = 1e-9 * (std::abs(geo.cx_m) + std::abs(geo.cy_m) + reach);
  x0 -= margin;
  x1 += margin;
  y0 -= margin;
  y1 += margin;
  return std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1);
}

cv::Mat radiance_of(const host::CameraConfig& camera, const CeilingScene& scene,
                    const CameraView& view, const RenderParams& params, RenderStats& stats) {
  const int w = camera.image_width, h = camera.image_height;
  const bool distorted = params.apply_distortion && camera.has_distortion();
  const std::shared_ptr<const RayTable> table = ray_table(camera, distorted);
  const double cam_x = view.centre.x(), cam_y = view.centre.y();
  const double above = camera.ceiling_height_m - view.centre.z();
  if (!(above > 0.0)) throw std::invalid_argument("renderer: the ceiling must be above the camera");
  const std::vector<TapeFrame> tapes = tape_frames(scene, camera, view.centre.z());
  const Eigen::Matrix3d& r = view.world_to_camera;
  const CeilingGeometry geo{cam_x,   cam_y,   above,   r(0, 0), r(0, 1), r(0, 2),
                            r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)};
  const int n = params.supersample;
  const double inv_n = 1.0 / n;

  cv::Mat radiance(h, w, CV_64FC1, cv::Scalar(0.0));
  std::vector<int> candidates;
  candidates.reserve(tapes.size());
  std::vector<int> all_tapes(tapes.size());
  for (std::size_t t = 0; t < tapes.size(); ++t) all_tapes[t] = static_cast<int>(t);

  // Edge pixels found by render_pixel, sampled after the classification:
  // the pixel, its value's place, the brightest tape covering its whole
  // footprint (reflectance 0: none) and the tapes that may cover a sample
  // (edge_tapes[first, first + count), or all of them).
  struct EdgePixel {
    std::size_t k;
    double* out;
    double inside_reflectance, inside_weight;
    std::size_t first, count;
    bool all;
  };
  std::vector<EdgePixel> edges;
  std::vector<int> edge_tapes;

  // One pixel. `near`: the tapes (ascending) whose bounding box the pixel's
  // footprint box can meet; the footprint classification skips every other
  // tape, as its box test would.
  auto render_pixel = [&](int i, int j, double* out, const std::vector<int>& near) {
    const std::size_t k =
        static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
    const PixelRay& ray = table->rays[k];
    if (!ray.valid || tapes.empty()) {
      ++stats.background_pixels;
      return;
    }
    // Classify the footprint: the pixel square maps to a parallelogram of
    // rays (affine approximation) and, when every corner ray rises, to a
    // convex quadrilateral on the ceiling (a projective image of a convex set
    // that does not cross the horizon), so its corners decide inside/outside
    // of each (convex) tape exactly.
    double inside_reflectance = 0.0, inside_weight = 1.0;  // weight: 1 / k^2
    const std::vector<int>* mixed = &candidates;
    candidates.clear();
    if (params.adaptive_sampling) {
      std::array<double, 4> qx{}, qy{}, q_t{};
      int rising = 0;
      for (std::size_t c = 0; c < 4; ++c) {
        const double a = corner_offset_a(c), b = corner_offset_b(c);
        if (geo.point(ray.x + ray.j00 * a + ray.j01 * b, ray.y + ray.j10 * a + ray.j11 * b, qx[c],
                      qy[c], q_t[c])) {
          ++rising;
        }
      }
      if (rising == 0) {  // the rise is linear in the ray: no point of the footprint rises
        ++stats.background_pixels;
        return;
      }
      if (rising < 4) {
        mixed = &all_tapes;  // the footprint straddles the horizon: sample it all
      } else {
        const double min_x = std::min({qx[0], qx[1], qx[2], qx[3]});
        const double max_x = std::max({qx[0], qx[1], qx[2], qx[3]});
        const double min_y = std::min({qy[0], qy[1], qy[2], qy[3]});
        const double max_y = std::max({qy[0], qy[1], qy[2], qy[3]});
        for (const int ti : near) {
          const auto t = static_cast<std::size_t>(ti);
          const TapeFrame& tape = tapes[t];
          // The footprint on this strip's plane: C + k (q - C).
          std::array<double, 4> scaled_x{}, scaled_y{};
          const double* sx = qx.data();
          const double* sy = qy.data();
          if (tape.scaled) {
            for (std::size_t c = 0; c < 4; ++c) {
              scaled_x[c] = cam_x + tape.scale * (qx[c] - cam_x);
              scaled_y[c] = cam_y + tape.scale * (qy[c] - cam_y);
            }
            sx = scaled_x.data();
            sy = scaled_y.data();
          }
          if (tape.box_misses(min_x, max_x, min_y, max_y, cam_x, cam_y)) continue;
          int s_below = 0, s_above = 0, t_below = 0, t_above = 0;
          for (std::size_t c = 0; c < 4; ++c) {
            const double dx = sx[c] - tape.ax, dy = sy[c] - tape.ay;
            const double s = dx * tape.ex + dy * tape.ey;
            const double tt = dy * tape.ex - dx * tape.ey;
            s_below += s < 0.0;
            s_above += s > tape.length;
            t_below += tt < -tape.half_width;
            t_above += tt > tape.half_width;
          }
          if (s_below == 4 || s_above == 4 || t_below == 4 || t_above == 4) continue;
          if (s_below + s_above + t_below + t_above == 0) {
            if (tape.reflectance > inside_reflectance) {
              inside_reflectance = tape.reflectance;
              inside_weight = tape.inv_scale2;
            }
          } else {
            candidates.push_back(ti);
          }
        }
        // A partly covering tape that is not brighter than one covering the
        // whole footprint changes nothing.
        std::erase_if(candidates, [&](int t) {
          return tapes[static_cast<std::size_t>(t)].reflectance <= inside_reflectance;
        });
        if (candidates.empty()) {
          if (inside_reflectance <= 0.0) {
            ++stats.background_pixels;
            return;
          }
          // Smooth 1/r^2 over the footprint: 2 x 2 midpoint rule, relative
          // error ~ (footprint / range)^2 / 96, far below 1e-4.
          double sum = 0.0;
          for (int c = 0; c < 4; ++c) {
            const double a = 0.5 * ((c & 1) - 0.5), b = 0.5 * ((c >> 1) - 0.5);
            double px = 0.0, py = 0.0, inv_r2 = 0.0;
            geo.hit(ray.x + ray.j00 * a + ray.j01 * b, ray.y + ray.j10 * a + ray.j11 * b, px, py,
                    inv_r2);
            sum += inv_r2;
          }
          out[i] = params.tape_gain * inside_reflectance * 0.25 * (sum * inside_weight);
          ++stats.interior_pixels;
          stats.samples += 4;
          return;
        }
      }
    } else {
      mixed = &all_tapes;
    }
    // Edge pixel: sampled below, in batches.
    if (mixed == &all_tapes) {
      edges.push_back({k, out + i, inside_reflectance, inside_weight, 0, 0, true});
    } else {
      edges.push_back(
          {k, out + i, inside_reflectance, inside_weight, edge_tapes.size(), mixed->size(), false});
      edge_tapes.insert(edge_tapes.end(), mixed->begin(), mixed->end());
    }
    ++stats.edge_pixels;
    stats.samples += static_cast<int64_t>(n) * n;
  };

  // Tile by tile: the tapes whose box the tile's footprint box misses are
  // skipped by the box test of every one of its pixels (the footprint
  // corners lie in the tile's box, and the box test is monotone in them), so
  // they are dropped for the whole tile; a tile that no tape can touch is
  // background. Near the horizon, and without adaptive sampling, every tape
  // is kept.
  std::vector<int> near;
  near.reserve(tapes.size());
  for (int ty = 0; ty < table->tiles_y; ++ty) {
    for (int tx = 0; tx < table->tiles_x; ++tx) {
      const RayTile& tile =
          table->tiles[static_cast<std::size_t>(ty) * static_cast<std::size_t>(table->tiles_x) +
                       static_cast<std::size_t>(tx)];
      const int i0 = tx * kTile, i1 = std::min(w, i0 + kTile);
      const int j0 = ty * kTile, j1 = std::min(h, j0 + kTile);
      const std::vector<int>* tile_tapes = &all_tapes;
      double x0 = 0.0, x1 = 0.0, y0 = 0.0, y1 = 0.0;
      if (params.adaptive_sampling && !tapes.empty() && tile.any_valid &&
          tile_footprint(geo, tile, x0, x1, y0, y1)) {
        near.clear();
        for (std::size_t t = 0; t < tapes.size(); ++t) {
          if (!tapes[t].box_misses(x0, x1, y0, y1, cam_x, cam_y))
            near.push_back(static_cast<int>(t));
        }
        if (near.empty()) {
          stats.background_pixels += static_cast<int64_t>(i1 - i0) * (j1 - j0);
          continue;
        }
        tile_tapes = &near;
      }
      for (int j = j0; j < j1; ++j) {
        double* out = radiance.ptr<double>(j);
        for (int i = i0; i < i1; ++i) render_pixel(i, j, out, *tile_tapes);
      }
    }
  }

  // Edge pixels: jittered stratified samples, one per cell of an N x N grid,
  // the jitter a fixed function of the pixel index (jittered_offsets), made
  // for kLanes pixels at a time.
  constexpr std::size_t kLanes = 4;
  const std::size_t cells = static_cast<std::size_t>(n) * static_cast<std::size_t>(n);
  std::vector<double> jitter_a(kLanes * cells), jitter_b(kLanes * cells);
  for (std::size_t e0 = 0; e0 < edges.size(); e0 += kLanes) {
    std::array<std::size_t, kLanes> pixels{};
    for (std::size_t l = 0; l < kLanes; ++l)
      pixels[l] = edges[std::min(e0 + l, edges.size() - 1)].k;
    jitter_lanes<kLanes>(pixels.data(), n, jitter_a.data(), jitter_b.data());
    for (std::size_t l = 0; l < kLanes && e0 + l < edges.size(); ++l) {
      const EdgePixel& e = edges[e0 + l];
      const PixelRay& ray = table->rays[e.k];
      const double* ja = jitter_a.data() + l * cells;
      const double* jb = jitter_b.data() + l * cells;
      const int* mixed = e.all ? all_tapes.data() : edge_tapes.data() + e.first;
      const std::size_t count = e.all ? all_tapes.size() : e.count;
      double sum = 0.0;
      for (std::size_t m = 0; m < cells; ++m) {
        const double a = ja[m], b = jb[m];
        const double x = ray.x + ray.j00 * a + ray.j01 * b;
        const double y = ray.y + ray.j10 * a + ray.j11 * b;
        double px = 0.0, py = 0.0, t_ray = 0.0;
        if (!geo.point(x, y, px, py, t_ray)) continue;
        double reflectance = e.inside_reflectance, weight = e.inside_weight;
        for (std::size_t c = 0; c < count; ++c) {
          const TapeFrame& tape = tapes[static_cast<std::size_t>(mixed[c])];
          if (tape.reflectance > reflectance &&
              (tape.scaled ? tape.contains(cam_x + tape.scale * (px - cam_x),
                                           cam_y + tape.scale * (py - cam_y))
                           : tape.contains(px, py))) {
            reflectance = tape.reflectance;
            weight = tape.inv_scale2;
          }
        }
        // A sample on no tape adds reflectance 0 x (a finite 1/r^2) x 1 = +0:
        // skipping it (and its division) leaves the sum as it was.
        if (reflectance > 0.0)
          sum += reflectance * CeilingGeometry::inv_range2(t_ray, x, y) * weight;
      }
      *e.out = params.tape_gain * sum * inv_n * inv_n;
    }
  }
  return radiance;
}

// The noise finish_render adds, row-major: sigma * sqrt(-2 ln u1) *
// cos(2 pi u2) (Box-Muller on two counter-based uniforms, u1 in (0, 1]), a
// fixed function of (seed, sigma, pixel index). Its log and cos are most of a
// small frame's rendering time and a drive renders every frame with the same
// seed, so the last few fields are kept; a kept field holds exactly the
// values that computing it again would give.
struct NoiseKey {
  uint64_t seed;
  double sigma;
  int rows, cols;
  bool operator==(const NoiseKey&) const = default;
};

std::shared_ptr<const std::vector<double>> noise_field(uint64_t noise_seed, double sigma, int rows,
                                                       int cols) {
  static std::mutex mutex;
  static std::vector<std::pair<NoiseKey, std::shared_ptr<const std::vector<double>>>> cache;
  const NoiseKey key{noise_seed, sigma, rows, cols};
  {
    const std::lock_guard<std::mutex> lock(mutex);
    for (const auto& [cached_key, field] : cache) {
      if (cached_key == key) return field;
    }
  }
  auto field = std::make_shared<std::vector<double>>(static_cast<std::size_t>(rows) *
                                                     static_cast<std::size_t>(cols));
  const uint64_t seed = mix64(noise_seed ^ 0xa54ff53a5f1d36f1ULL);
  for (std::size_t k = 0; k < field->size(); ++k) {
    const uint64_t index = static_cast<uint64_t>(k);
    const double u1 = 1.0 - unit_interval(mix64(seed ^ (2 * index)));
    const double u2 = unit_interval(mix64(seed ^ (2 * index + 1)));
    (*field)[k] = sigma * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  // At most 4 fields and 64 MiB of them (four 2048 x 1024 frames); a larger
  // field is not kept.
  constexpr std::size_t kCacheEntries = 4;
  constexpr std::size_t kCacheValues = std::size_t{8} << 20;
  if (field->size() > kCacheValues) return field;
  const std::lock_guard<std::mutex> lock(mutex);
  std::size_t values = field->size();
  for (const auto& entry : cache) values += entry.second->size();
  while (!cache.empty() && (cache.size() >= kCacheEntries || values > kCacheValues)) {
    values -= cache.front().second->size();
    cache.erase(cache.begin());
  }
  cache.emplace_back(key, field);
  return field;
}

}  // namespace

std::optional<Eigen::Vector2d> undistort_pixel(const host::CameraConfig& camera,
                                               const Eigen::Vector2d& pixel) {
  const double xd = (pixel.x() - camera.cx()) / camera.fx();
  const double yd = (pixel.y() - camera.cy()) / camera.fy();
  double x = xd, y = yd;
  Eigen::Matrix2d jac;
  if (!undistort_newton(camera, xd, yd, x, y, jac)) return std::nullopt;
  return Eigen::Vector2d(x, y);
}

double affine_undistortion_error_px(const host::CameraConfig& camera) {
  check_camera(camera);
  return ray_table(camera, camera.has_distortion())->affine_error_px;
}

cv::Mat render_float(const host::CameraConfig& camera, const CeilingScene& scene,
                     const CameraPose& pose, const RenderParams& params, RenderStats* stats) {
  check_camera(camera);
  if (params.supersample < 1 || params.supersample > 64) {
    throw std::invalid_argument("render: supersample must be in [1, 64]");
  }
  if (!(params.blur_sigma_px >= 0.0) || !(params.noise_sigma_grey >= 0.0) ||
      !std::isfinite(params.background_grey) || !std::isfinite(params.tape_gain)) {
    throw std::invalid_argument("render: blur and noise sigmas must be >= 0, grey levels finite");
  }
  RenderStats local_stats;
  cv::Mat image = radiance_of(camera, scene, camera_view(camera, pose), params, local_stats);
  if (stats != nullptr) *stats = local_stats;
  finish_render(image, params);
  return image;
}

CameraView camera_view(const host::CameraConfig& camera, const CameraPose& pose) {
  return {camera_centre(camera, pose), world_to_camera_rotation(pose.yaw_rad, pitch_rad(camera))};
}

cv::Mat render_radiance(const host::CameraConfig& camera, const CeilingScene& scene,
                        const CameraView& view, const RenderParams& params, RenderStats* stats) {
  check_camera(camera);
  if (params.supersample < 1 || params.supersample > 64) {
    throw std::invalid_argument("render: supersample must be in [1, 64]");
  }
  if (!view.centre.allFinite() || !view.world_to_camera.allFinite()) {
    throw std::invalid_argument("render: the camera view must be finite");
  }
  RenderStats local_stats;
  cv::Mat image = radiance_of(camera, scene, view, params, local_stats);
  if (stats != nullptr) *stats = local_stats;
  return image;
}

std::shared_ptr<const std::vector<PixelRay>> lens_pixel_rays(const host::CameraConfig& camera,
                                                             bool distorted) {
  host::CameraConfig lens = camera;
  lens.camera_height_m = 0.0;
  lens.ceiling_height_m = 1.0;
  return pixel_rays(lens, distorted);
}

std::shared_ptr<const std::vector<PixelRay>> pixel_rays(const host::CameraConfig& camera,
                                                        bool distorted) {
  check_camera(camera);
  auto table = ray_table(camera, distorted && camera.has_distortion());
  return {table, &table->rays};
}

void jittered_offsets(std::size_t pixel_index, int n, double* a, double* b) {
  jitter_lanes<1>(&pixel_index, n, a, b);
}

void finish_render(cv::Mat& image, const RenderParams& params) {
  if (image.type() != CV_64FC1) throw std::invalid_argument("finish_render: needs CV_64FC1");
  if (!(params.blur_sigma_px >= 0.0) || !(params.noise_sigma_grey >= 0.0) ||
      !std::isfinite(params.background_grey)) {
    throw std::invalid_argument("render: blur and noise sigmas must be >= 0, grey levels finite");
  }
  image += cv::Scalar(params.background_grey);
  if (params.blur_sigma_px > 0.0) {
    // Kernel to +-5 sigma: the truncated tail weighs < 1e-6.
    const int half = static_cast<int>(std::ceil(5.0 * params.blur_sigma_px));
    cv::GaussianBlur(image, image, cv::Size(2 * half + 1, 2 * half + 1), params.blur_sigma_px,
                     params.blur_sigma_px, cv::BORDER_REFLECT_101);
  }
  if (params.noise_sigma_grey > 0.0) {
    const std::shared_ptr<const std::vector<double>> noise =
        noise_field(params.noise_seed, params.noise_sigma_grey, image.rows, image.cols);
    const double* n = noise->data();
    for (int j = 0; j < image.rows; ++j) {
      double* row = image.ptr<double>(j);
      for (int i = 0; i < image.cols; ++i) row[i] += *n++;
    }
  }
}

cv::Mat render_frame(const host::CameraConfig& camera, const CeilingScene& scene,
                     const CameraPose& pose, const RenderParams& params) {
  cv::Mat grey;
  render_float(camera, scene, pose, params).convertTo(grey, CV_8UC1);  // rounds and saturates
  return grey;
}

}  // namespace ceilnav::golden
