#include "golden/pattern/pattern.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "golden/scene.hpp"

namespace ceilnav::golden::pattern {
namespace {

constexpr int kBlockUnits = 3 + kDataBars + 7;  // wide bar, 5 gaps, data bars (2 x 2 + 3 x 1)

// The 10 two-of-five position pairs in lexicographic order.
constexpr std::array<std::pair<int, int>, kBlockValues> kPairs{
    {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 2}, {1, 3}, {1, 4}, {2, 3}, {2, 4}, {3, 4}}};

void check_geometry(const PatternGeometry& g) {
  if (!(g.radius_m > 0.0) || !(g.thickness_m >= 0.0) || !(g.bar_unit_m > 0.0) ||
      !(g.rim_m >= 0.0) || !(g.bar_gap_m > g.rim_m) || !(g.bar_gap_m >= 0.0) ||
      !(g.bar_height_m > 0.0) || !(g.plate_margin_m >= 0.0)) {
    throw std::invalid_argument("pattern geometry: sizes must be positive (T, gaps >= 0)");
  }
}

struct Rect {
  double x0, x1, y0, y1;
  bool contains(double x, double y) const { return x >= x0 && x <= x1 && y >= y0 && y <= y1; }
  // Distance from (x, y) to the rectangle's boundary.
  double boundary_distance(double x, double y) const {
    const double dx = std::max({x0 - x, 0.0, x - x1});
    const double dy = std::max({y0 - y, 0.0, y - y1});
    if (dx > 0.0 || dy > 0.0) return std::hypot(dx, dy);
    return std::min({x - x0, x1 - x, y - y0, y1 - y});
  }
};

// Everything the per-sample shading needs, in the pattern frame.
struct Scene {
  PatternGeometry g;
  Radiometry rad;
  std::vector<Rect> bars, plates;
  Eigen::Vector3d c;   // camera centre
  Eigen::Matrix3d rt;  // camera -> pattern rotation (R^T)

  Scene(const PatternGeometry& geometry, const Radiometry& r, int identity, const PatternView& view)
      : g(geometry), rad(r), c(view.centre), rt(view.rotation.transpose()) {
    check_geometry(g);
    const double h = 0.5 * g.bar_height_m;
    for (const BarSpan& b : bar_layout(g, identity)) bars.push_back({b.x0_m, b.x1_m, -h, h});
    const double outer = block_outer_x_m(g), inner = block_inner_x_m(g), m = g.plate_margin_m;
    plates.push_back({outer - m, inner + m, -h - m, h + m});
    plates.push_back({-inner - m, -outer + m, -h - m, h + m});
  }

  double falloff(const Eigen::Vector3d& p) const {
    const double l = rad.lamp_distance_m;
    const double dx = p.x(), dy = p.y(), dz = p.z() - l;
    return l * l / (dx * dx + dy * dy + dz * dz);
  }

  double grey(PixelClass cls, const Eigen::Vector3d& p) const {
    return rad.gain * albedo(cls) * falloff(p);
  }
  double albedo(PixelClass cls) const {
    switch (cls) {
      case PixelClass::pattern:
        return rad.albedo_disc;
      case PixelClass::shadow:
        return rad.albedo_shadow;
      case PixelClass::bar:
        return rad.albedo_bar;
      default:
        return rad.albedo_wall;
    }
  }

  // Shade the ray with direction d (pattern frame): radiance above black level.
  // Also returns the class.
  double shade(const Eigen::Vector3d& d, PixelClass& cls) const {
    cls = PixelClass::background;
    const double surroundings = rad.gain * rad.albedo_wall;
    if (!(d.z() < 0.0)) return surroundings;  // never reaches the wall plane
    // Face plane z = 0: disc, bars, plates (front-most: the camera is at z > 0).
    const double t0 = -c.z() / d.z();
    const Eigen::Vector3d p0 = c + t0 * d;
    const double r0 = std::hypot(p0.x(), p0.y());
    if (r0 <= g.radius_m) {
      cls = PixelClass::pattern;
      return grey(cls, p0);
    }
    if (r0 <= g.radius_m + g.rim_m) return grey(cls, p0);  // the dark rim of the face
    for (const Rect& b : bars) {
      if (b.contains(p0.x(), p0.y())) {
        cls = PixelClass::bar;
        return grey(cls, p0);
      }
    }
    for (const Rect& pl : plates) {
      if (pl.contains(p0.x(), p0.y())) return grey(cls, p0);
    }
    // Side wall of the disc: first entry into the cylinder x^2 + y^2 = R^2 with
    // -T <= z <= 0.
    const double a = d.x() * d.x() + d.y() * d.y();
    if (a > 0.0 && g.thickness_m > 0.0) {
      const double b = c.x() * d.x() + c.y() * d.y();
      const double rc = g.radius_m + g.rim_m;
      const double cc = c.x() * c.x() + c.y() * c.y() - rc * rc;
      const double disc = b * b - a * cc;
      if (disc >= 0.0) {
        const double t = (-b - std::sqrt(disc)) / a;
        const Eigen::Vector3d p = c + t * d;
        if (t > 0.0 && p.z() <= 0.0 && p.z() >= -g.thickness_m) {
          cls = PixelClass::shadow;
          return grey(cls, p);
        }
      }
    }
    // The wall z = -T.
    const double tw = (-g.thickness_m - c.z()) / d.z();
    const Eigen::Vector3d pw = c + tw * d;
    if (std::abs(pw.x()) <= rad.wall_half_width_m && std::abs(pw.y()) <= rad.wall_half_height_m) {
      return grey(cls, pw);
    }
    return surroundings;
  }

  // Lower bound of the face-plane distance from p0 to any edge of the scene as
  // seen along rays near this one (incidence tan_inc = |d_xy| / |d_z|).
  double margin(const Eigen::Vector3d& p0, double tan_inc) const {
    const double r0 = std::hypot(p0.x(), p0.y());
    // The side wall projects onto the face plane within R .. R + T tan_inc.
    const double rc = g.radius_m + g.rim_m;
    double m = std::abs(r0 - g.radius_m);
    if (r0 <= rc) m = std::min(m, rc - r0);
    if (r0 > rc) m = std::min(m, std::max(0.0, r0 - rc - g.thickness_m * tan_inc));
    for (const Rect& b : bars) m = std::min(m, b.boundary_distance(p0.x(), p0.y()));
    for (const Rect& pl : plates) m = std::min(m, pl.boundary_distance(p0.x(), p0.y()));
    return m;
  }
};

bool valid_identity(int identity) {
  return identity >= 0 && identity < kIdentityCount;
}

}  // namespace

std::array<int, kDataBars> block_widths(int value) {
  if (value < 0 || value >= kBlockValues) throw std::invalid_argument("block value out of range");
  std::array<int, kDataBars> w{1, 1, 1, 1, 1};
  w[static_cast<std::size_t>(kPairs[static_cast<std::size_t>(value)].first)] = 2;
  w[static_cast<std::size_t>(kPairs[static_cast<std::size_t>(value)].second)] = 2;
  return w;
}

std::optional<int> block_value(const std::array<int, kDataBars>& widths) {
  for (int v = 0; v < kBlockValues; ++v) {
    if (block_widths(v) == widths) return v;
  }
  return std::nullopt;
}

std::pair<int, int> block_values(int identity) {
  if (!valid_identity(identity)) {
    throw std::invalid_argument("pattern identity must be in [0, " +
                                std::to_string(kIdentityCount) + ")");
  }
  const int left = identity / 5, low = identity % 5;
  return {left, 2 * low + ((left + low) % 2)};
}

std::optional<int> identity_from_blocks(int left_value, int right_value) {
  if (left_value < 0 || left_value >= kBlockValues || right_value < 0 ||
      right_value >= kBlockValues) {
    return std::nullopt;
  }
  const int low = right_value / 2;
  if (right_value % 2 != (left_value + low) % 2) return std::nullopt;
  return left_value * 5 + low;
}

std::optional<int> mirrored_identity(int identity) {
  const auto [left, right] = block_values(identity);
  return identity_from_blocks(right, left);
}

double block_inner_x_m(const PatternGeometry& g) {
  return -(g.radius_m + g.bar_gap_m);
}
double block_outer_x_m(const PatternGeometry& g) {
  return block_inner_x_m(g) - kBlockUnits * g.bar_unit_m;
}

std::vector<BarSpan> bar_layout(const PatternGeometry& g, int identity) {
  check_geometry(g);
  const auto [left, right] = block_values(identity);
  const double u = g.bar_unit_m;
  // One block from its outer end inward, as offsets in units from the outer end.
  auto block = [&](int value) {
    std::vector<std::pair<double, double>> spans{{0.0, 3.0}};
    double x = 3.0;
    for (int w : block_widths(value)) {
      x += 1.0;
      spans.emplace_back(x, x + w);
      x += w;
    }
    return spans;
  };
  std::vector<BarSpan> bars;
  const double outer = block_outer_x_m(g);
  for (const auto& [a, b] : block(left)) bars.push_back({outer + a * u, outer + b * u});
  const auto right_spans = block(right);
  for (auto it = right_spans.rbegin(); it != right_spans.rend(); ++it) {
    bars.push_back({-outer - it->second * u, -outer - it->first * u});
  }
  return bars;
}

double Radiometry::level(PixelClass c) const {
  double a = albedo_wall;
  if (c == PixelClass::pattern) a = albedo_disc;
  if (c == PixelClass::shadow) a = albedo_shadow;
  if (c == PixelClass::bar) a = albedo_bar;
  return black_level + gain * a;
}

double Radiometry::observed_level(PixelClass c) const {
  return std::clamp(level(c), 0.0, 255.0);
}

double vignetting_factor(const CameraPhotometry& p, int width, int height, double x, double y) {
  const double cx = 0.5 * (width - 1), cy = 0.5 * (height - 1);
  const double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (cx * cx + cy * cy);
  return 1.0 - p.vignetting * r2;
}

ClassThresholds class_thresholds(const Radiometry& r) {
  const double bar = r.level(PixelClass::bar), wall = r.level(PixelClass::background);
  const double shadow = r.level(PixelClass::shadow), disc = r.level(PixelClass::pattern);
  // The bar may lie below 0 and the disc above 255 (a frame's calibrated
  // levels: the camera clips them); the wall, the run background, may not.
  if (!(bar < wall && wall < shadow && shadow < disc) || !(wall >= 0.0 && wall < 255.0)) {
    throw std::invalid_argument(
        "radiometry: levels must increase bar < wall < shadow < disc, the wall within 0..255");
  }
  ClassThresholds t{};
  // A third of the way from bar to wall: the wall far from the lamp is darker
  // (the bar reader fits the resulting edge bias, docs/pattern.md). At least
  // 1, so that a bar the camera clips to 0 is still the bar class.
  t.bar_below = std::max(1, static_cast<int>(std::lround(bar + (wall - bar) / 3.0)));
  t.shadow_from = static_cast<int>(std::lround(0.5 * (wall + shadow)));
  // The disc borders only the dark rim (wall albedo): the midpoint of the
  // true levels is unbiased, even where the camera clips the disc's interior.
  t.pattern_from = static_cast<int>(std::lround(0.5 * (disc + wall)));
  if (!(t.bar_below < t.shadow_from && t.shadow_from < t.pattern_from && t.pattern_from <= 255)) {
    throw std::invalid_argument("radiometry: class levels too close to separate");
  }
  return t;
}

std::array<uint8_t, 256> class_lut(const Radiometry& r) {
  const ClassThresholds t = class_thresholds(r);
  std::array<uint8_t, 256> lut{};
  for (int g = 0; g < 256; ++g) {
    PixelClass c = PixelClass::background;
    if (g < t.bar_below)
      c = PixelClass::bar;
    else if (g >= t.pattern_from)
      c = PixelClass::pattern;
    else if (g >= t.shadow_from)
      c = PixelClass::shadow;
    lut[static_cast<std::size_t>(g)] = static_cast<uint8_t>(c);
  }
  return lut;
}

std::array<stream::LutEntry, 256> bar_mask_lut(const Radiometry& r) {
  const std::array<uint8_t, 256> cls = class_lut(r);
  // Darker than the wall: remap = 255 - grey (w = the bar's ink). Lighter
  // than the wall: remap = background + the disc's coverage of the pixel
  // (grey - wall) / (disc - wall) in units of 1 / disc_coverage_weight, so a
  // disc run's weight is its sub-pixel chord (docs/pattern.md). Below wall +
  // kCoverageDeadZone (3 sigma of the wall's noise at sigma 3) 0, so a bar
  // run's margins on the plate stay weightless; from disc - kCoverageDeadZone
  // full, so the disc's noise does not bias the chord.
  const double wall = r.level(PixelClass::background), disc = r.level(PixelClass::pattern);
  const uint8_t bg = bar_run_background(r);
  const double k = static_cast<double>(255 - bg);
  const double full_from = disc_full_grey(r);
  std::array<stream::LutEntry, 256> lut{};
  for (unsigned g = 0; g < 256; ++g) {
    const bool mask = cls[g] == static_cast<uint8_t>(PixelClass::bar) ||
                      cls[g] == static_cast<uint8_t>(PixelClass::pattern);
    const double grey = static_cast<double>(g);
    auto remap = static_cast<uint8_t>(255 - g);
    if (grey >= wall + kCoverageDeadZone) {
      const double c = grey >= full_from ? 1.0 : std::min(1.0, (grey - wall) / (disc - wall));
      remap = static_cast<uint8_t>(bg + static_cast<int>(std::lround(k * c)));
    }
    lut[g] = stream::lut_entry(remap, mask, cls[g]);
  }
  return lut;
}

double disc_full_grey(const Radiometry& r) {
  return r.observed_level(PixelClass::pattern) - kCoverageDeadZone;
}

uint32_t disc_coverage_weight(const Radiometry& r) {
  return static_cast<uint32_t>(255 - bar_run_background(r));
}

host::pattern::DiscCoverageModel disc_coverage_model(const Radiometry& r, double noise_grey,
                                                     double blur_sigma_px, bool blur_on_pixels) {
  host::pattern::DiscCoverageModel m;
  m.k = disc_coverage_weight(r);
  m.contrast = r.level(PixelClass::pattern) - r.level(PixelClass::background);
  m.dead_lo = kCoverageDeadZone / m.contrast;
  // 1 - dead_lo unless the camera clips the disc (then from the clip level).
  m.dead_hi = (disc_full_grey(r) - r.level(PixelClass::background)) / m.contrast;
  m.noise_grey = noise_grey;
  (blur_on_pixels ? m.kernel_sigma_px : m.psf_sigma_px) = blur_sigma_px;
  return m;
}

uint8_t bar_run_background(const Radiometry& r) {
  const double wall = r.level(PixelClass::background);
  return static_cast<uint8_t>(std::lround(std::clamp(255.0 - wall, 0.0, 255.0)));
}

cv::Mat classify(const cv::Mat& grey, const std::array<uint8_t, 256>& lut) {
  if (grey.type() != CV_8UC1) throw std::invalid_argument("classify: needs an 8-bit grey frame");
  cv::Mat table(1, 256, CV_8UC1, const_cast<uint8_t*>(lut.data()));
  cv::Mat out;
  cv::LUT(grey, table, out);
  return out;
}

stream::PipelineConfig device_config(int width, int height, const Radiometry& r) {
  if (width < 1 || width > static_cast<int>(stream::kMaxWidth) || height < 1 ||
      height > static_cast<int>(stream::kMaxHeight)) {
    throw std::invalid_argument("device_config: frame size out of the device's range");
  }
  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(width);
  cfg.height = static_cast<uint16_t>(height);
  cfg.lut = bar_mask_lut(r);
  cfg.background_level = bar_run_background(r);
  // The disc's full pixels weigh disc_coverage_weight, more than a bar
  // pixel's ink could make it look like the wall: the host tells the runs
  // apart by position (inside the disc's moment ellipse), not by weight.
  if (disc_coverage_weight(r) < 20) {
    throw std::invalid_argument(
        "device_config: wall level leaves no room for the disc's coverage weight");
  }
  cfg.min_run_length = 1;
  cfg.max_runs_per_row = 32;
  cfg.class_window = {0, static_cast<uint16_t>(width), 0, static_cast<uint16_t>(height)};
  return cfg;
}

uint32_t bar_run_min_weight(const Radiometry& r) {
  const ClassThresholds t = class_thresholds(r);
  return static_cast<uint32_t>(255 - (t.bar_below - 1) - bar_run_background(r));
}

PatternView look_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& target,
                    double swing_rad) {
  const Eigen::Vector3d f = (target - centre).normalized();
  const Eigen::Vector3d up(0.0, 1.0, 0.0);
  Eigen::Vector3d right = f.cross(up);
  if (!(right.norm() > 1e-9) || !f.allFinite()) {
    throw std::invalid_argument("look_at: optical axis vertical or undefined");
  }
  right.normalize();
  Eigen::Vector3d down = f.cross(right);
  // Swing: rotate the image axes about f, clockwise in the image for swing > 0.
  const double cs = std::cos(swing_rad), sn = std::sin(swing_rad);
  const Eigen::Vector3d r2 = cs * right + sn * down;
  const Eigen::Vector3d d2 = -sn * right + cs * down;
  PatternView v;
  v.centre = centre;
  v.rotation.row(0) = r2.transpose();
  v.rotation.row(1) = d2.transpose();
  v.rotation.row(2) = f.transpose();
  return v;
}

Eigen::Vector3d spherical_position(double d_m, double theta_rad, double beta_rad) {
  return d_m * Eigen::Vector3d(std::sin(theta_rad) * std::sin(beta_rad),
                               std::sin(theta_rad) * std::cos(beta_rad), std::cos(theta_rad));
}

PatternView spherical_view(double d_m, double theta_rad, double beta_rad, double swing_rad) {
  if (!(d_m > 0.0) || !(theta_rad >= 0.0) || !(theta_rad < 0.5 * std::numbers::pi)) {
    throw std::invalid_argument("spherical_view: need D > 0 and 0 <= theta < 90 deg");
  }
  return look_at(spherical_position(d_m, theta_rad, beta_rad), Eigen::Vector3d::Zero(), swing_rad);
}

Eigen::Matrix3d pattern_axes(const PatternPlacement& p) {
  const Eigen::Vector3d z(std::cos(p.facing_rad), std::sin(p.facing_rad), 0.0);
  const Eigen::Vector3d y(0.0, 0.0, 1.0);
  Eigen::Matrix3d m;
  m.col(0) = y.cross(z);
  m.col(1) = y;
  m.col(2) = z;
  return m;
}

Eigen::Vector3d world_to_pattern(const PatternPlacement& p, const Eigen::Vector3d& world) {
  return pattern_axes(p).transpose() * (world - Eigen::Vector3d(p.x_m, p.y_m, p.z_m));
}

Eigen::Vector3d pattern_to_world(const PatternPlacement& p, const Eigen::Vector3d& local) {
  return Eigen::Vector3d(p.x_m, p.y_m, p.z_m) + pattern_axes(p) * local;
}

PatternView robot_view(const PatternPlacement& p, const RobotCamera& cam) {
  // World -> camera: forward f, right r (horizontal, before swing), down.
  const double cy = std::cos(cam.camera_yaw_rad), sy = std::sin(cam.camera_yaw_rad);
  const double ct = std::cos(cam.tilt_rad), st = std::sin(cam.tilt_rad);
  const Eigen::Vector3d f(ct * cy, ct * sy, st);
  const Eigen::Vector3d right(sy, -cy, 0.0);
  const Eigen::Vector3d down = f.cross(right);
  const double cs = std::cos(cam.swing_rad), sn = std::sin(cam.swing_rad);
  Eigen::Matrix3d r_world;
  r_world.row(0) = (cs * right + sn * down).transpose();
  r_world.row(1) = (-sn * right + cs * down).transpose();
  r_world.row(2) = f.transpose();
  PatternView v;
  v.centre = world_to_pattern(p, Eigen::Vector3d(cam.x_m, cam.y_m, cam.height_m));
  v.rotation = r_world * pattern_axes(p);  // X_cam = R_w A (X_pat - C_pat)
  return v;
}

const PatternPlacement* PatternDatabase::find(int identity) const {
  for (const PatternPlacement& p : patterns) {
    if (p.identity == identity) return &p;
  }
  return nullptr;
}

PatternDatabase load_pattern_database(const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception&) {
    throw std::runtime_error("pattern database " + path + ": not a readable YAML/JSON file");
  }
  if (!fs.isOpened()) throw std::runtime_error("pattern database " + path + ": cannot open");
  auto real = [&](const cv::FileNode& node, const std::string& key, double fallback,
                  bool required) {
    const cv::FileNode n = node[key];
    if (n.empty()) {
      if (required) throw std::runtime_error("pattern database " + path + ": missing key " + key);
      return fallback;
    }
    if (!n.isReal() && !n.isInt()) {
      throw std::runtime_error("pattern database " + path + ": key " + key + " is not a number");
    }
    const double v = static_cast<double>(n);
    if (!std::isfinite(v)) {
      throw std::runtime_error("pattern database " + path + ": key " + key + " is not finite");
    }
    return v;
  };
  PatternDatabase db;
  const cv::FileNode geo = fs["geometry"];
  if (!geo.empty()) {
    if (!geo.isMap()) throw std::runtime_error("pattern database " + path + ": geometry not a map");
    PatternGeometry& g = db.geometry;
    g.radius_m = real(geo, "radius_m", g.radius_m, false);
    g.thickness_m = real(geo, "thickness_m", g.thickness_m, false);
    g.rim_m = real(geo, "rim_m", g.rim_m, false);
    g.bar_unit_m = real(geo, "bar_unit_m", g.bar_unit_m, false);
    g.bar_gap_m = real(geo, "bar_gap_m", g.bar_gap_m, false);
    g.bar_height_m = real(geo, "bar_height_m", g.bar_height_m, false);
    g.plate_margin_m = real(geo, "plate_margin_m", g.plate_margin_m, false);
    try {
      check_geometry(g);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error("pattern database " + path + ": " + e.what());
    }
  }
  const cv::FileNode list = fs["patterns"];
  if (list.isNone()) {
    throw std::runtime_error("pattern database " + path +
                             ": missing key patterns (a sequence of {identity, x_m, y_m, z_m, "
                             "facing_deg})");
  }
  if (!list.isSeq()) {
    throw std::runtime_error("pattern database " + path +
                             ": key patterns is not a sequence of {identity, x_m, y_m, z_m, "
                             "facing_deg}");
  }
  if (list.size() == 0) {
    throw std::runtime_error("pattern database " + path +
                             ": has no patterns (key patterns is an empty sequence); list at "
                             "least one {identity, x_m, y_m, z_m, facing_deg}");
  }
  for (const cv::FileNode& n : list) {
    if (!n.isMap()) throw std::runtime_error("pattern database " + path + ": entry not a map");
    PatternPlacement p;
    const double id = real(n, "identity", 0.0, true);
    if (id != std::floor(id) || id < 0 || id >= kIdentityCount) {
      throw std::runtime_error("pattern database " + path +
                               ": identity must be an integer in [0, " +
                               std::to_string(kIdentityCount) + ")");
    }
    p.identity = static_cast<int>(id);
    p.x_m = real(n, "x_m", 0.0, true);
    p.y_m = real(n, "y_m", 0.0, true);
    p.z_m = real(n, "z_m", 0.0, true);
    p.facing_rad = real(n, "facing_deg", 0.0, true) * std::numbers::pi / 180.0;
    if (db.find(p.identity) != nullptr) {
      throw std::runtime_error("pattern database " + path + ": identity " +
                               std::to_string(p.identity) + " listed twice");
    }
    db.patterns.push_back(p);
  }
  return db;
}

void save_pattern_database(const std::string& path, const PatternDatabase& db) {
  const std::string tmp = path + ".tmp.yaml";
  {
    cv::FileStorage fs(tmp, cv::FileStorage::WRITE);
    if (!fs.isOpened()) throw std::runtime_error("cannot write " + path);
    fs << "geometry"
       << "{";
    fs << "radius_m" << db.geometry.radius_m << "thickness_m" << db.geometry.thickness_m;
    fs << "rim_m" << db.geometry.rim_m;
    fs << "bar_unit_m" << db.geometry.bar_unit_m << "bar_gap_m" << db.geometry.bar_gap_m;
    fs << "bar_height_m" << db.geometry.bar_height_m << "plate_margin_m"
       << db.geometry.plate_margin_m;
    fs << "}";
    fs << "patterns"
       << "[";
    for (const PatternPlacement& p : db.patterns) {
      fs << "{"
         << "identity" << p.identity << "x_m" << p.x_m << "y_m" << p.y_m << "z_m" << p.z_m
         << "facing_deg" << p.facing_rad * 180.0 / std::numbers::pi << "}";
    }
    fs << "]";
    fs.release();
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path);
  }
}

namespace {

std::optional<Eigen::Vector2d> project(const host::CameraConfig& camera, const PatternView& view,
                                       const Eigen::Vector3d& p, bool distort) {
  const Eigen::Vector3d x = view.rotation * (p - view.centre);
  if (!(x.z() > 1e-9)) return std::nullopt;
  Eigen::Vector2d xy(x.x() / x.z(), x.y() / x.z());
  if (distort) xy = distort_normalised(camera, xy);
  return Eigen::Vector2d(camera.fx() * xy.x() + camera.cx(), camera.fy() * xy.y() + camera.cy());
}

bool inside(const host::CameraConfig& camera, const std::optional<Eigen::Vector2d>& px,
            double margin) {
  return px && px->x() >= margin - 0.5 && px->y() >= margin - 0.5 &&
         px->x() <= camera.image_width - 0.5 - margin &&
         px->y() <= camera.image_height - 0.5 - margin;
}

}  // namespace

PatternTruth pattern_truth(const host::CameraConfig& camera, const PatternGeometry& g, int identity,
                           const PatternView& view) {
  check_geometry(g);
  PatternTruth t{};
  const Eigen::Vector3d& c = view.centre;
  t.d_m = c.norm();
  t.theta_rad = std::acos(std::clamp(c.z() / t.d_m, -1.0, 1.0));
  t.beta_rad = std::atan2(c.x(), c.y());
  // Swing: angle of the image of the pattern's +y direction at the centre from
  // image "up", positive clockwise... measured as the rotation that look_at applied.
  const Eigen::Vector3d f = view.rotation.row(2).transpose();
  Eigen::Vector3d right = f.cross(Eigen::Vector3d(0.0, 1.0, 0.0));
  t.swing_rad = 0.0;
  if (right.norm() > 1e-12) {
    right.normalize();
    const Eigen::Vector3d down = f.cross(right);
    const Eigen::Vector3d r2 = view.rotation.row(0).transpose();
    t.swing_rad = std::atan2(r2.dot(down), r2.dot(right));
  }
  t.identity = identity;
  const bool distort = camera.has_distortion();
  const auto centre = project(camera, view, Eigen::Vector3d::Zero(), distort);
  t.centre_px = centre ? *centre
                       : Eigen::Vector2d(std::numeric_limits<double>::quiet_NaN(),
                                         std::numeric_limits<double>::quiet_NaN());
  t.disc_in_view = true;
  for (int k = 0; k < 72; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 72.0;
    const Eigen::Vector3d rim(g.radius_m * std::cos(a), g.radius_m * std::sin(a), 0.0);
    if (!inside(camera, project(camera, view, rim, distort), 0.0)) t.disc_in_view = false;
  }
  t.code_in_view = true;
  t.min_bar_width_px = std::numeric_limits<double>::infinity();
  const double h = 0.5 * g.bar_height_m;
  for (const BarSpan& b : bar_layout(g, identity)) {
    for (double y : {-h, 0.0, h}) {
      const auto p0 = project(camera, view, {b.x0_m, y, 0.0}, distort);
      const auto p1 = project(camera, view, {b.x1_m, y, 0.0}, distort);
      if (y != 0.0 && (!inside(camera, p0, 1.0) || !inside(camera, p1, 1.0))) {
        t.code_in_view = false;
      }
      if (p0 && p1) t.min_bar_width_px = std::min(t.min_bar_width_px, std::abs(p1->x() - p0->x()));
    }
  }
  if (!std::isfinite(t.min_bar_width_px)) t.min_bar_width_px = 0.0;
  return t;
}

PixelClass class_along_ray(const PatternGeometry& g, int identity, const PatternView& view,
                           double x, double y) {
  const Scene scene(g, Radiometry{}, identity, view);
  PixelClass cls = PixelClass::background;
  scene.shade(scene.rt * Eigen::Vector3d(x, y, 1.0), cls);
  return cls;
}

cv::Mat render_pattern(const host::CameraConfig& camera, const PatternGeometry& g,
                       const Radiometry& radiometry, int identity, const PatternView& view,
                       const PatternRenderParams& params) {
  if (params.supersample < 1 || params.supersample > 16) {
    throw std::invalid_argument("render_pattern: supersample must be in [1, 16]");
  }
  if (!(view.centre.z() > 0.0)) {
    throw std::invalid_argument("render_pattern: the camera must be in front of the pattern");
  }
  class_thresholds(radiometry);  // validates the levels
  const Scene scene(g, radiometry, identity, view);
  const auto rays = pixel_rays(camera, params.apply_distortion);
  const int w = camera.image_width, h = camera.image_height, n = params.supersample;
  std::vector<double> ja(static_cast<std::size_t>(n * n)), jb(ja.size());
  cv::Mat radiance(h, w, CV_64FC1, cv::Scalar(0.0));
  const double surroundings = radiometry.gain * radiometry.albedo_wall;
  const CameraPhotometry& cp = params.photometry;
  if (!(cp.gain > 0.0) || !std::isfinite(cp.gain) || !std::isfinite(cp.offset_grey) ||
      !(cp.vignetting >= 0.0 && cp.vignetting < 1.0)) {
    throw std::invalid_argument(
        "render_pattern: camera gain must be > 0, offset finite, vignetting in [0, 1)");
  }
  for (int j = 0; j < h; ++j) {
    double* out = radiance.ptr<double>(j);
    for (int i = 0; i < w; ++i) {
      const std::size_t k =
          static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
      const PixelRay& ray = (*rays)[k];
      if (!ray.valid) {
        out[i] = surroundings;
        continue;
      }
      auto dir = [&](double a, double b) {
        return Eigen::Vector3d(scene.rt * Eigen::Vector3d(ray.x + ray.j00 * a + ray.j01 * b,
                                                          ray.y + ray.j10 * a + ray.j11 * b, 1.0));
      };
      // Footprint on the face plane: the four corner rays.
      const Eigen::Vector3d d0 = dir(0.0, 0.0);
      bool uniform = false;
      if (d0.z() < 0.0) {
        const Eigen::Vector3d p0 = scene.c - (scene.c.z() / d0.z()) * d0;
        double footprint = 0.0, tan_inc = 0.0;
        bool all_hit = true;
        for (int q = 0; q < 4; ++q) {
          const Eigen::Vector3d d = dir((q & 1) - 0.5, (q >> 1) - 0.5);
          if (!(d.z() < 0.0)) {
            all_hit = false;
            break;
          }
          const Eigen::Vector3d p = scene.c - (scene.c.z() / d.z()) * d;
          footprint = std::max(footprint, (p - p0).norm());
          tan_inc = std::max(tan_inc, std::hypot(d.x(), d.y()) / -d.z());
        }
        uniform = all_hit && scene.margin(p0, tan_inc) > 1.05 * footprint + 1e-9;
      }
      double sum = 0.0;
      PixelClass cls = PixelClass::background;
      if (uniform) {  // smooth falloff only: 2 x 2 midpoint rule
        for (int q = 0; q < 4; ++q) {
          sum += scene.shade(dir(0.5 * ((q & 1) - 0.5), 0.5 * ((q >> 1) - 0.5)), cls);
        }
        out[i] = 0.25 * sum;
        continue;
      }
      jittered_offsets(k, n, ja.data(), jb.data());
      for (std::size_t s = 0; s < ja.size(); ++s) sum += scene.shade(dir(ja[s], jb[s]), cls);
      out[i] = sum / static_cast<double>(ja.size());
    }
  }
  if (cp.gain != 1.0 || cp.vignetting != 0.0) {
    for (int j = 0; j < h; ++j) {
      double* out = radiance.ptr<double>(j);
      for (int i = 0; i < w; ++i) out[i] *= cp.gain * vignetting_factor(cp, w, h, i, j);
    }
  }
  RenderParams finish;
  finish.background_grey = radiometry.black_level + cp.offset_grey;
  finish.blur_sigma_px = params.blur_sigma_px;
  finish.noise_sigma_grey = params.noise_sigma_grey;
  finish.noise_seed = params.noise_seed;
  finish_render(radiance, finish);
  cv::Mat grey;
  radiance.convertTo(grey, CV_8UC1);
  return grey;
}

}  // namespace ceilnav::golden::pattern
