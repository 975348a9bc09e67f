#include "golden/ceiling/ceiling.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ceilnav::golden::ceiling {
namespace {

// Paint ids (ceiling.hpp, Paint::id): disjoint ranges per feature kind.
constexpr int kGrid = 1, kTile = 2, kPlain = 3;
constexpr int kLampBase = 1000, kVentBase = 100000, kSpotBase = 200000, kBeamBase = 300000;

void check(bool ok, const std::string& source, const std::string& key, const char* what) {
  if (!ok) throw CeilingError(fmt::format("{}: {}: {}", source, key, what));
}
bool finite(double v) {
  return std::isfinite(v);
}
bool nonneg(double v) {
  return std::isfinite(v) && v >= 0.0;
}
bool positive(double v) {
  return std::isfinite(v) && v > 0.0;
}

void check_rect(const Rect& r, double border, const std::string& source, const std::string& key) {
  check(finite(r.x_m) && finite(r.y_m) && finite(r.angle_rad), source, key,
        "position and angle must be finite");
  check(positive(r.length_m) && positive(r.width_m), source, key, "length and width must be > 0");
  check(nonneg(border) && 2.0 * border < r.width_m && 2.0 * border < r.length_m, source, key,
        "the border must be >= 0 and leave an inside");
}

// (along, across) of (x, y) in the rectangle's own axes.
Eigen::Vector2d local(const Rect& r, double x, double y) {
  const double dx = x - r.x_m, dy = y - r.y_m;
  const double c = std::cos(r.angle_rad), s = std::sin(r.angle_rad);
  return {dx * c + dy * s, -dx * s + dy * c};
}

// Distance of v to the nearest multiple of pitch.
double to_grid(double v, double pitch) {
  const double m = v - pitch * std::round(v / pitch);
  return std::abs(m);
}

}  // namespace

void validate(const Ceiling& c, const std::string& source) {
  check(positive(c.height_m), source, "height_m", "must be finite and > 0");
  check(nonneg(c.plain_albedo), source, "plain_albedo", "must be finite and >= 0");
  const Tiles& t = c.tiles;
  check(nonneg(t.pitch_x_m) && nonneg(t.pitch_y_m), source, "tiles.pitch", "must be >= 0");
  check(finite(t.origin_x_m) && finite(t.origin_y_m) && finite(t.angle_rad), source, "tiles.origin",
        "must be finite");
  check(nonneg(t.gap_m), source, "tiles.gap_m", "must be >= 0");
  for (double p : {t.pitch_x_m, t.pitch_y_m}) {
    check(p == 0.0 || t.gap_m < p, source, "tiles.gap_m", "must be narrower than the pitch");
  }
  check(nonneg(t.tile_albedo) && nonneg(t.grid_albedo), source, "tiles.albedo", "must be >= 0");
  for (std::size_t i = 0; i < c.lamps.size(); ++i) {
    const Lamp& l = c.lamps[i];
    const std::string key = fmt::format("lamps[{}]", i);
    check_rect(l.rect, l.border_m, source, key);
    check(nonneg(l.radiance) && nonneg(l.frame_albedo), source, key,
          "radiance and albedo must be >= 0");
  }
  for (std::size_t i = 0; i < c.vents.size(); ++i) {
    const Vent& v = c.vents[i];
    const std::string key = fmt::format("vents[{}]", i);
    check_rect(v.rect, v.border_m, source, key);
    check(v.slats >= 1 && v.slats <= 1000, source, key, "slats must be 1 .. 1000");
    check(nonneg(v.frame_albedo) && nonneg(v.slot_albedo), source, key, "albedos must be >= 0");
  }
  for (std::size_t i = 0; i < c.beams.size(); ++i) {
    const Beam& b = c.beams[i];
    const std::string key = fmt::format("beams[{}]", i);
    check(finite(b.x0_m) && finite(b.y0_m) && finite(b.x1_m) && finite(b.y1_m), source, key,
          "ends must be finite");
    check(std::hypot(b.x1_m - b.x0_m, b.y1_m - b.y0_m) > 0.0, source, key, "ends must differ");
    check(positive(b.width_m) && nonneg(b.albedo), source, key, "width must be > 0, albedo >= 0");
  }
  for (std::size_t i = 0; i < c.spots.size(); ++i) {
    const Spot& s = c.spots[i];
    const std::string key = fmt::format("spots[{}]", i);
    check(finite(s.x_m) && finite(s.y_m) && positive(s.radius_m) && nonneg(s.albedo), source, key,
          "position finite, radius > 0, albedo >= 0");
  }
}

void validate(const Lighting& l, const std::string& source) {
  check(nonneg(l.gain) && nonneg(l.lamp_gain) && nonneg(l.lamp_off_albedo), source, "gain",
        "gains and the lamp-off albedo must be finite and >= 0");
  check(finite(l.gradient_x_per_m) && finite(l.gradient_y_per_m) && finite(l.origin_x_m) &&
            finite(l.origin_y_m),
        source, "gradient", "must be finite");
}

double light_at(const Lighting& l, double x, double y) {
  const double v = l.gain * (1.0 + l.gradient_x_per_m * (x - l.origin_x_m) +
                             l.gradient_y_per_m * (y - l.origin_y_m));
  return v > 0.0 ? v : 0.0;
}

namespace {

double half_diagonal(const Rect& r) {
  return 0.5 * std::sqrt(r.length_m * r.length_m + r.width_m * r.width_m);
}

// (x, y) outside the rectangle's circumscribed circle (no trigonometry).
bool outside_circumcircle(const Rect& r, double x, double y) {
  const double dx = x - r.x_m, dy = y - r.y_m;
  const double reach = 0.25 * (r.length_m * r.length_m + r.width_m * r.width_m);
  return dx * dx + dy * dy > reach;
}

}  // namespace

Paint paint_at(const Ceiling& c, const Lighting& lighting, double x, double y) {
  for (std::size_t i = 0; i < c.lamps.size(); ++i) {
    const Lamp& l = c.lamps[i];
    if (outside_circumcircle(l.rect, x, y)) continue;
    const Eigen::Vector2d p = local(l.rect, x, y);
    if (std::abs(p.x()) > 0.5 * l.rect.length_m || std::abs(p.y()) > 0.5 * l.rect.width_m) continue;
    const int id = kLampBase + 2 * static_cast<int>(i);
    if (std::abs(p.x()) > 0.5 * l.rect.length_m - l.border_m ||
        std::abs(p.y()) > 0.5 * l.rect.width_m - l.border_m) {
      return {id + 1, false, l.frame_albedo};
    }
    if (lighting.lamps_on) return {id, true, l.radiance};
    return {id, false, lighting.lamp_off_albedo};
  }
  for (std::size_t i = 0; i < c.vents.size(); ++i) {
    const Vent& v = c.vents[i];
    if (outside_circumcircle(v.rect, x, y)) continue;
    const Eigen::Vector2d p = local(v.rect, x, y);
    if (std::abs(p.x()) > 0.5 * v.rect.length_m || std::abs(p.y()) > 0.5 * v.rect.width_m) continue;
    const int id = kVentBase + 3 * static_cast<int>(i);
    const double half_in = 0.5 * v.rect.length_m - v.border_m;
    if (std::abs(p.x()) > half_in || std::abs(p.y()) > 0.5 * v.rect.width_m - v.border_m) {
      return {id, false, v.frame_albedo};
    }
    // 2 slats + 1 bands across the inside, slots at the odd ones.
    const int bands = 2 * v.slats + 1;
    const int band =
        std::min(bands - 1, static_cast<int>((p.x() + half_in) / (2.0 * half_in) * bands));
    if (band % 2 == 1) return {id + 2, false, v.slot_albedo};
    return {id + 1, false, v.frame_albedo};
  }
  for (std::size_t i = 0; i < c.spots.size(); ++i) {
    const Spot& s = c.spots[i];
    const double dx = x - s.x_m, dy = y - s.y_m;
    if (dx * dx + dy * dy > 2.0 * s.radius_m * s.radius_m) continue;  // cheap cull
    if (std::hypot(dx, dy) <= s.radius_m) {
      return {kSpotBase + static_cast<int>(i), false, s.albedo};
    }
  }
  for (std::size_t i = 0; i < c.beams.size(); ++i) {
    const Beam& b = c.beams[i];
    const Eigen::Vector2d a(b.x0_m, b.y0_m), d(b.x1_m - b.x0_m, b.y1_m - b.y0_m);
    const Eigen::Vector2d q(x, y);
    const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    if ((q - (a + t * d)).norm() <= 0.5 * b.width_m) {
      return {kBeamBase + static_cast<int>(i), false, b.albedo};
    }
  }
  const Tiles& t = c.tiles;
  if (t.pitch_x_m == 0.0 && t.pitch_y_m == 0.0) return {kPlain, false, c.plain_albedo};
  const double dx = x - t.origin_x_m, dy = y - t.origin_y_m;
  const double ca = std::cos(t.angle_rad), sa = std::sin(t.angle_rad);
  const double u = dx * ca + dy * sa, v = -dx * sa + dy * ca;
  const bool gap = (t.pitch_x_m > 0.0 && to_grid(u, t.pitch_x_m) <= 0.5 * t.gap_m) ||
                   (t.pitch_y_m > 0.0 && to_grid(v, t.pitch_y_m) <= 0.5 * t.gap_m);
  return gap ? Paint{kGrid, false, t.grid_albedo} : Paint{kTile, false, t.tile_albedo};
}

namespace {

// |signed distance| to the boundary of the centred rectangle length x width.
double rect_boundary(const Eigen::Vector2d& p, double length, double width) {
  const double ex = std::abs(p.x()) - 0.5 * length, ey = std::abs(p.y()) - 0.5 * width;
  if (ex <= 0.0 && ey <= 0.0) return std::min(-ex, -ey);
  const double ox = std::max(ex, 0.0), oy = std::max(ey, 0.0);
  return std::sqrt(ox * ox + oy * oy);
}

}  // namespace

double border_distance(const Ceiling& c, double x, double y) {
  // The tile grid first (within half a pitch of any point), then the
  // features that could be nearer: a feature whose circumscribed circle is
  // at least the distance so far away is skipped (the result is the same
  // minimum; the features' trigonometry is the renderer's cost).
  double d = std::numeric_limits<double>::infinity();
  const Tiles& t = c.tiles;
  if (t.pitch_x_m > 0.0 || t.pitch_y_m > 0.0) {
    const double dx = x - t.origin_x_m, dy = y - t.origin_y_m;
    const double ca = std::cos(t.angle_rad), sa = std::sin(t.angle_rad);
    const double u = dx * ca + dy * sa, v = -dx * sa + dy * ca;
    if (t.pitch_x_m > 0.0) d = std::min(d, std::abs(to_grid(u, t.pitch_x_m) - 0.5 * t.gap_m));
    if (t.pitch_y_m > 0.0) d = std::min(d, std::abs(to_grid(v, t.pitch_y_m) - 0.5 * t.gap_m));
  }
  const auto beyond = [&](double cx, double cy, double reach) {
    const double dx = x - cx, dy = y - cy, far = d + reach;
    return std::isfinite(d) && dx * dx + dy * dy > far * far;
  };
  for (const Lamp& l : c.lamps) {
    if (beyond(l.rect.x_m, l.rect.y_m, half_diagonal(l.rect))) continue;
    const Eigen::Vector2d p = local(l.rect, x, y);
    d = std::min(d, rect_boundary(p, l.rect.length_m, l.rect.width_m));
    if (l.border_m > 0.0) {
      d = std::min(d, rect_boundary(p, l.rect.length_m - 2.0 * l.border_m,
                                    l.rect.width_m - 2.0 * l.border_m));
    }
  }
  for (const Vent& v : c.vents) {
    if (beyond(v.rect.x_m, v.rect.y_m, half_diagonal(v.rect))) continue;
    const Eigen::Vector2d p = local(v.rect, x, y);
    d = std::min(d, rect_boundary(p, v.rect.length_m, v.rect.width_m));
    const double half_in = 0.5 * v.rect.length_m - v.border_m;
    d = std::min(d, rect_boundary(p, 2.0 * half_in, v.rect.width_m - 2.0 * v.border_m));
    const int bands = 2 * v.slats + 1;
    const double step = 2.0 * half_in / bands;
    for (int k = 1; k < bands; ++k) d = std::min(d, std::abs(p.x() - (-half_in + k * step)));
  }
  for (const Spot& s : c.spots) {
    if (beyond(s.x_m, s.y_m, s.radius_m)) continue;
    d = std::min(d, std::abs(std::hypot(x - s.x_m, y - s.y_m) - s.radius_m));
  }
  for (const Beam& b : c.beams) {
    const Eigen::Vector2d a(b.x0_m, b.y0_m), e(b.x1_m - b.x0_m, b.y1_m - b.y0_m), q(x, y);
    const double along = std::clamp((q - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    d = std::min(d, std::abs((q - (a + along * e)).norm() - 0.5 * b.width_m));
  }
  return d;
}

double radiance_at(const Ceiling& c, const Lighting& l, double x, double y) {
  const Paint p = paint_at(c, l, x, y);
  return p.emissive ? p.value * l.lamp_gain : p.value * light_at(l, x, y);
}

Ceiling office_ceiling() {
  Ceiling c;
  c.name = "office";
  c.height_m = 3.5;
  c.tiles = Tiles{};  // 0.6 m tiles, 24 mm grid, aligned with X
  // Lamps of 1.2 x 0.3 m in two rows, every 2.4 m along X, filling a tile
  // row each (centred in a 0.6 x 1.2 pair of tiles' cell).
  for (int i = -4; i <= 4; ++i) {
    for (double y : {-1.5, 1.5}) {
      Lamp l;
      l.rect = {2.4 * i + 0.3, y, 1.2, 0.3, 0.0};
      c.lamps.push_back(l);
    }
  }
  // Square grilles in some tiles, and one turned diffuser.
  for (const auto& [x, y] : {std::pair{1.5, 0.3}, {-3.3, -0.3}, {6.3, 0.9}, {-7.5, 0.3}}) {
    Vent v;
    v.rect = {x, y, 0.55, 0.55, 0.0};
    c.vents.push_back(v);
  }
  Vent round;
  round.rect = {4.2, -0.9, 0.5, 0.3, std::numbers::pi / 2.0};
  round.slats = 5;
  c.vents.push_back(round);
  for (int i = -5; i <= 5; ++i) c.spots.push_back({1.8 * i + 0.9, 0.0, 0.035, 0.25});
  // Smoke detectors off the tile centres, one beside each square grille:
  // what makes a patch around a grille read the same at no other turn.
  for (const auto& [x, y] : {std::pair{1.83, 0.11}, {-2.95, -0.1}, {6.0, 1.24}, {-7.2, -0.04}}) {
    c.spots.push_back({x, y, 0.07, 0.3});
  }
  return c;
}

Ceiling hall_ceiling() {
  Ceiling c;
  c.name = "hall";
  c.height_m = 3.0;
  c.tiles.pitch_x_m = 1.2;
  c.tiles.pitch_y_m = 0.6;
  c.tiles.gap_m = 0.015;
  c.tiles.grid_albedo = 0.4;
  Beam b;
  b.x0_m = -20.0;
  b.x1_m = 20.0;
  b.y0_m = b.y1_m = 1.2;
  b.width_m = 0.3;
  b.albedo = 0.5;
  c.beams.push_back(b);
  for (int i = -6; i <= 6; ++i) {
    Lamp l;
    l.rect = {3.0 * i, -0.6, 0.6, 0.6, 0.0};
    l.radiance = 2.5;
    c.lamps.push_back(l);
  }
  Vent v;
  v.rect = {1.2, -1.5, 0.9, 0.25, 0.0};
  v.slats = 10;
  c.vents.push_back(v);
  c.spots.push_back({-2.0, 0.6, 0.05, 0.2});
  c.spots.push_back({5.0, 0.3, 0.05, 0.2});
  return c;
}

}  // namespace ceilnav::golden::ceiling
