#include "sim/course.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <system_error>

#include "common/yaml_reader.hpp"
#include "golden/pattern/pattern.hpp"

namespace ceilnav::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// ---------------------------------------------------------------------------
// Geometry helpers.

double cross(double ax, double ay, double bx, double by) {
  return ax * by - ay * bx;
}

double segment_length(const Point2& a, const Point2& b) {
  return std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
}

double heading(const Point2& from, const Point2& to) {
  return nav::wrap_angle(std::atan2(to.y_m - from.y_m, to.x_m - from.x_m));
}

// ---------------------------------------------------------------------------
// Reading.

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  yaml_fail<CourseError>(source, key, what);
}

// The shared typed reader (common/yaml_reader.hpp) and the course's own
// shapes: a point [x, y] and a yaw in radians or degrees.
struct Reader : YamlReader<CourseError> {
  Point2 point(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence() || node.size() != 2) fail(key, "must be [x, y]");
    return {number(node[0], key + "[0]"), number(node[1], key + "[1]")};
  }

  double yaw(const YAML::Node& map, const std::string& key) const {
    const bool rad = static_cast<bool>(map["yaw_rad"]), deg = static_cast<bool>(map["yaw_deg"]);
    if (rad == deg) fail(key, "needs exactly one of yaw_rad and yaw_deg");
    return rad ? number(map["yaw_rad"], key + ".yaw_rad")
               : number(map["yaw_deg"], key + ".yaw_deg") * kDeg;
  }
};

std::string num(double v) {
  return yaml_number_text(v);
}

std::string at(const std::string& key, std::size_t i) {
  return yaml_at(key, i);
}

Course read_course(const YAML::Node& root, const std::string& source) {
  const Reader r{{source}};
  r.keys(root, "", {"format", "version", "name", "ceiling", "tapes", "patterns", "start", "route"},
         {"format", "version", "ceiling", "tapes", "start"});
  if (r.text(root["format"], "format") != "ceilnav_course") {
    fail(source, "format", "must be 'ceilnav_course'");
  }
  if (r.integer(root["version"], "version") != 1) fail(source, "version", "must be 1");
  Course c;
  if (root["name"]) c.name = r.text(root["name"], "name");

  const YAML::Node ceiling = root["ceiling"];
  r.keys(ceiling, "ceiling", {"height_m", "zones"}, {"height_m"});
  c.ceiling_height_m = r.number(ceiling["height_m"], "ceiling.height_m");
  if (ceiling["zones"]) {
    const YAML::Node zones = r.sequence(ceiling["zones"], "ceiling.zones");
    for (std::size_t i = 0; i < zones.size(); ++i) {
      const std::string key = at("ceiling.zones", i);
      const YAML::Node z = zones[i];
      r.keys(z, key, {"height_m", "rectangle", "polygon"}, {"height_m"});
      HeightZone zone;
      zone.height_m = r.number(z["height_m"], key + ".height_m");
      if (static_cast<bool>(z["rectangle"]) == static_cast<bool>(z["polygon"])) {
        fail(source, key, "needs exactly one of rectangle and polygon");
      }
      if (z["rectangle"]) {
        const YAML::Node rect = z["rectangle"];
        if (!rect.IsSequence() || rect.size() != 4) {
          fail(source, key + ".rectangle", "must be [x_min, y_min, x_max, y_max]");
        }
        std::array<double, 4> v{};
        for (std::size_t k = 0; k < 4; ++k) v[k] = r.number(rect[k], at(key + ".rectangle", k));
        if (!(v[2] > v[0]) || !(v[3] > v[1])) {
          fail(source, key + ".rectangle", "needs x_max > x_min and y_max > y_min");
        }
        zone.polygon = {{v[0], v[1]}, {v[2], v[1]}, {v[2], v[3]}, {v[0], v[3]}};
      } else {
        const YAML::Node poly = r.sequence(z["polygon"], key + ".polygon");
        for (std::size_t k = 0; k < poly.size(); ++k) {
          zone.polygon.push_back(r.point(poly[k], at(key + ".polygon", k)));
        }
      }
      c.zones.push_back(zone);
    }
  }

  const YAML::Node tapes = r.sequence(root["tapes"], "tapes");
  for (std::size_t i = 0; i < tapes.size(); ++i) {
    const std::string key = at("tapes", i);
    const YAML::Node t = tapes[i];
    r.keys(t, key, {"name", "width_m", "reflectance", "points", "gaps"}, {"width_m", "points"});
    TapePolyline tape;
    if (t["name"]) tape.name = r.text(t["name"], key + ".name");
    tape.width_m = r.number(t["width_m"], key + ".width_m");
    if (t["reflectance"]) tape.reflectance = r.number(t["reflectance"], key + ".reflectance");
    const YAML::Node points = r.sequence(t["points"], key + ".points");
    for (std::size_t k = 0; k < points.size(); ++k) {
      tape.points.push_back(r.point(points[k], at(key + ".points", k)));
    }
    if (t["gaps"]) {
      const YAML::Node gaps = r.sequence(t["gaps"], key + ".gaps");
      for (std::size_t k = 0; k < gaps.size(); ++k) {
        const Point2 g = r.point(gaps[k], at(key + ".gaps", k));
        tape.gaps_m.emplace_back(g.x_m, g.y_m);
      }
    }
    c.tapes.push_back(tape);
  }

  if (root["patterns"]) {
    const YAML::Node patterns = r.sequence(root["patterns"], "patterns");
    for (std::size_t i = 0; i < patterns.size(); ++i) {
      const std::string key = at("patterns", i);
      const YAML::Node p = patterns[i];
      r.keys(p, key, {"id", "x_m", "y_m", "yaw_rad", "yaw_deg"}, {"id", "x_m", "y_m"});
      c.patterns.push_back({r.integer(p["id"], key + ".id"), r.number(p["x_m"], key + ".x_m"),
                            r.number(p["y_m"], key + ".y_m"), r.yaw(p, key)});
    }
  }

  const YAML::Node start = root["start"];
  r.keys(start, "start", {"x_m", "y_m", "yaw_rad", "yaw_deg"}, {"x_m", "y_m"});
  c.start = {r.number(start["x_m"], "start.x_m"), r.number(start["y_m"], "start.y_m"),
             r.yaw(start, "start")};

  if (root["route"]) {
    const YAML::Node route = r.sequence(root["route"], "route");
    for (std::size_t i = 0; i < route.size(); ++i) {
      const std::string word = r.text(route[i], at("route", i));
      if (word == "left") {
        c.route.push_back(Turn::left);
      } else if (word == "right") {
        c.route.push_back(Turn::right);
      } else if (word == "straight") {
        c.route.push_back(Turn::straight);
      } else {
        fail(source, at("route", i), "'" + word + "' is not left, right or straight");
      }
    }
  }
  validate(c, source);
  return c;
}

void write_file(const std::string& path, const std::string& text) {
  write_world_file<CourseError>(path, text);
}

// ---------------------------------------------------------------------------
// Junction helpers.

// Closest point of tape `t` to p: distance, arc length and segment index.
struct Nearest {
  double distance = 1e300, arc = 0.0;
  std::size_t segment = 0;
  Point2 point;
};

Nearest nearest_on(const TapePolyline& t, const Point2& p) {
  Nearest best;
  double arc = 0.0;
  for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
    const Point2 &a = t.points[k], &b = t.points[k + 1];
    const double len = segment_length(a, b);
    const double ux = (b.x_m - a.x_m) / len, uy = (b.y_m - a.y_m) / len;
    const double s = std::clamp((p.x_m - a.x_m) * ux + (p.y_m - a.y_m) * uy, 0.0, len);
    const Point2 q{a.x_m + s * ux, a.y_m + s * uy};
    const double d = segment_length(p, q);
    if (d < best.distance) best = {d, arc + s, k, q};
    arc += len;
  }
  return best;
}

// Headings leaving arc position `arc` of tape t both ways (at a vertex, along
// the two segments that meet there).
void headings_at(const TapePolyline& t, double arc, double tol, std::vector<double>& out) {
  double s0 = 0.0;
  for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
    const double s1 = s0 + segment_length(t.points[k], t.points[k + 1]);
    const double forward = heading(t.points[k], t.points[k + 1]);
    if (arc >= s0 - tol && arc < s1 - tol) out.push_back(forward);  // tape ahead
    if (arc > s0 + tol && arc <= s1 + tol) out.push_back(nav::wrap_angle(forward + kPi));
    s0 = s1;
  }
}

void add_heading_unique(std::vector<double>& hs, double h) {
  for (double e : hs) {
    if (std::abs(nav::wrap_angle(e - h)) < 1e-6) return;
  }
  hs.push_back(h);
}

// ---------------------------------------------------------------------------
// Generator helpers.

Point2 rotated(const Point2& p, double angle, const Point2& shift) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {shift.x_m + c * p.x_m - s * p.y_m, shift.y_m + s * p.x_m + c * p.y_m};
}

// Adds up to `count` gaps of 0.2..1 m to a tape, each at least `clearance`
// from the tape's ends and from the arc positions in `keep_clear`.
void add_gaps(TapePolyline& tape, std::mt19937_64& rng, int count,
              const std::vector<double>& keep_clear, double clearance) {
  std::uniform_real_distribution<double> length(0.2, 1.0);
  std::uniform_real_distribution<double> where(clearance, tape.length_m() - clearance - 1.0);
  for (int tries = 0; tries < 50 && static_cast<int>(tape.gaps_m.size()) < count; ++tries) {
    const double a = where(rng), b = a + length(rng);
    bool ok = true;
    for (double k : keep_clear) ok = ok && (b < k - clearance || a > k + clearance);
    for (const auto& [g0, g1] : tape.gaps_m) ok = ok && (b < g0 - 2.0 || a > g1 + 2.0);
    if (ok) tape.gaps_m.emplace_back(a, b);
  }
  std::sort(tape.gaps_m.begin(), tape.gaps_m.end());
}

// The default course's layout: loop W x H, cross branch at x = xb.
Course loop_course(double w, double h, double xb) {
  Course c;
  c.tapes.push_back({"A", {{-2.0, 0.0}, {w, 0.0}, {w, h + 2.0}}, 0.05, 1.0, {}});
  c.tapes.push_back({"B", {{w, h}, {0.0, h}, {0.0, 2.0}}, 0.05, 1.0, {}});
  c.tapes.push_back({"C", {{xb, 0.0}, {xb, h}}, 0.05, 1.0, {}});
  c.ceiling_height_m = 2.5;
  c.start = {0.0, 0.0, 0.0};
  // Along A to the branch: straight; up A, left onto B at its T; left onto
  // C at its T; left onto A; and once more round the loop.
  c.route = {Turn::straight, Turn::left, Turn::left, Turn::left, Turn::left, Turn::left};
  return c;
}

}  // namespace

// ---------------------------------------------------------------------------

double TapePolyline::length_m() const {
  double s = 0.0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) s += segment_length(points[k], points[k + 1]);
  return s;
}

bool HeightZone::contains(double x, double y) const {
  // Crossing number: a horizontal ray to +x crosses the boundary an odd
  // number of times from inside.
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Point2 &a = polygon[i], &b = polygon[j];
    if ((a.y_m > y) != (b.y_m > y)) {
      const double x_cross = a.x_m + (y - a.y_m) * (b.x_m - a.x_m) / (b.y_m - a.y_m);
      if (x < x_cross) inside = !inside;
    }
  }
  return inside;
}

const char* turn_name(Turn turn) {
  switch (turn) {
    case Turn::left:
      return "left";
    case Turn::right:
      return "right";
    case Turn::straight:
      return "straight";
  }
  return "?";
}

double Course::ceiling_height_at(double x, double y) const {
  const int z = zone_at(x, y);
  return z < 0 ? ceiling_height_m : zones[static_cast<std::size_t>(z)].height_m;
}

int Course::zone_at(double x, double y) const {
  int found = -1;
  for (std::size_t i = 0; i < zones.size(); ++i) {
    if (zones[i].contains(x, y)) found = static_cast<int>(i);
  }
  return found;
}

bool Course::operator==(const Course& o) const {
  return name == o.name && tapes == o.tapes && ceiling_height_m == o.ceiling_height_m &&
         zones == o.zones && patterns == o.patterns && start.x_m == o.start.x_m &&
         start.y_m == o.start.y_m && start.yaw_rad == o.start.yaw_rad && route == o.route;
}

double Course::tape_length_m() const {
  double s = 0.0;
  for (const TapePolyline& t : tapes) s += t.length_m();
  return s;
}

void validate(const Course& c, const std::string& source) {
  if (!(c.ceiling_height_m > 0.0) || !std::isfinite(c.ceiling_height_m)) {
    fail(source, "ceiling.height_m", "must be > 0");
  }
  for (std::size_t i = 0; i < c.zones.size(); ++i) {
    const HeightZone& z = c.zones[i];
    const std::string key = at("ceiling.zones", i);
    if (!(z.height_m > 0.0) || !std::isfinite(z.height_m))
      fail(source, key + ".height_m", "must be > 0");
    if (z.polygon.size() < 3) fail(source, key + ".polygon", "needs at least 3 points");
    double area2 = 0.0;
    for (std::size_t k = 0; k < z.polygon.size(); ++k) {
      const Point2 &a = z.polygon[k], &b = z.polygon[(k + 1) % z.polygon.size()];
      if (!std::isfinite(a.x_m) || !std::isfinite(a.y_m))
        fail(source, key + ".polygon", "not finite");
      area2 += cross(a.x_m, a.y_m, b.x_m, b.y_m);
    }
    if (!(std::abs(area2) > 1e-9)) fail(source, key + ".polygon", "has no area");
  }
  if (c.tapes.empty()) fail(source, "tapes", "needs at least one tape");
  for (std::size_t i = 0; i < c.tapes.size(); ++i) {
    const TapePolyline& t = c.tapes[i];
    const std::string key = at("tapes", i);
    if (!(t.width_m > 0.0) || !std::isfinite(t.width_m))
      fail(source, key + ".width_m", "must be > 0");
    if (!(t.reflectance >= 0.0) || !std::isfinite(t.reflectance)) {
      fail(source, key + ".reflectance", "must be >= 0");
    }
    if (t.points.size() < 2) fail(source, key + ".points", "needs at least 2 points");
    for (std::size_t k = 0; k < t.points.size(); ++k) {
      if (!std::isfinite(t.points[k].x_m) || !std::isfinite(t.points[k].y_m)) {
        fail(source, at(key + ".points", k), "not finite");
      }
      if (k > 0 && !(segment_length(t.points[k - 1], t.points[k]) > 0.0)) {
        fail(source, at(key + ".points", k), "repeats the previous point");
      }
    }
    const double length = t.length_m();
    double previous_end = 0.0;
    for (std::size_t k = 0; k < t.gaps_m.size(); ++k) {
      const auto& [g0, g1] = t.gaps_m[k];
      const std::string gk = at(key + ".gaps", k);
      if (!(g1 > g0)) fail(source, gk, "needs end > start");
      if (!(g0 >= previous_end) || (k > 0 && !(g0 > previous_end))) {
        fail(source, gk, "gaps must be sorted and disjoint");
      }
      if (!(g0 >= 0.0) || !(g1 <= length)) {
        fail(source, gk, "must lie inside [0, " + std::to_string(length) + "] m of arc length");
      }
      previous_end = g1;
    }
  }
  for (std::size_t i = 0; i < c.patterns.size(); ++i) {
    const PatternStation& p = c.patterns[i];
    const std::string key = at("patterns", i);
    if (p.id < 0 || p.id >= golden::pattern::kIdentityCount) {
      fail(source, key + ".id",
           "must be in [0, " + std::to_string(golden::pattern::kIdentityCount) + ")");
    }
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.yaw_rad)) {
      fail(source, key, "position and yaw must be finite");
    }
  }
  if (!std::isfinite(c.start.x_m) || !std::isfinite(c.start.y_m) ||
      !std::isfinite(c.start.yaw_rad)) {
    fail(source, "start", "position and yaw must be finite");
  }
}

Course parse_course(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    fail(source, "", std::string("not YAML or JSON: ") + e.what());
  }
  if (!root.IsMap()) fail(source, "", "top level is not a map of keys");
  return read_course(root, source);
}

Course load_course(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw CourseError(path + ": cannot open: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_course(text.str(), path);
}

std::string course_to_yaml(const Course& c) {
  YAML::Emitter out;
  auto point = [&](double x, double y) {
    out << YAML::Flow << YAML::BeginSeq << num(x) << num(y) << YAML::EndSeq;
  };
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << "ceilnav_course";
  out << YAML::Key << "version" << YAML::Value << 1;
  out << YAML::Key << "name" << YAML::Value << YAML::DoubleQuoted << c.name;
  out << YAML::Key << "ceiling" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "height_m" << YAML::Value << num(c.ceiling_height_m);
  out << YAML::Key << "zones" << YAML::Value << YAML::BeginSeq;
  for (const HeightZone& z : c.zones) {
    out << YAML::BeginMap << YAML::Key << "height_m" << YAML::Value << num(z.height_m);
    out << YAML::Key << "polygon" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const Point2& p : z.polygon) point(p.x_m, p.y_m);
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  out << YAML::Key << "tapes" << YAML::Value << YAML::BeginSeq;
  for (const TapePolyline& t : c.tapes) {
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << YAML::DoubleQuoted << t.name;
    out << YAML::Key << "width_m" << YAML::Value << num(t.width_m);
    out << YAML::Key << "reflectance" << YAML::Value << num(t.reflectance);
    out << YAML::Key << "points" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const Point2& p : t.points) point(p.x_m, p.y_m);
    out << YAML::EndSeq;
    out << YAML::Key << "gaps" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const auto& [g0, g1] : t.gaps_m) point(g0, g1);
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "patterns" << YAML::Value << YAML::BeginSeq;
  for (const PatternStation& p : c.patterns) {
    out << YAML::Flow << YAML::BeginMap << YAML::Key << "id" << YAML::Value << p.id << YAML::Key
        << "x_m" << YAML::Value << num(p.x_m) << YAML::Key << "y_m" << YAML::Value << num(p.y_m)
        << YAML::Key << "yaw_rad" << YAML::Value << num(p.yaw_rad) << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "start" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "x_m"
      << YAML::Value << num(c.start.x_m) << YAML::Key << "y_m" << YAML::Value << num(c.start.y_m)
      << YAML::Key << "yaw_rad" << YAML::Value << num(c.start.yaw_rad) << YAML::EndMap;
  out << YAML::Key << "route" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (Turn t : c.route) out << turn_name(t);
  out << YAML::EndSeq << YAML::EndMap;
  if (!out.good()) throw CourseError("course_to_yaml: " + out.GetLastError());
  return std::string("# ceilnav course (docs/navigation.md, \"Course files\")\n") + out.c_str() +
         "\n";
}

std::string course_to_json(const Course& c) {
  using nlohmann::json;
  auto pt = [](double x, double y) { return json::array({x, y}); };
  json zones = json::array();
  for (const HeightZone& z : c.zones) {
    json poly = json::array();
    for (const Point2& p : z.polygon) poly.push_back(pt(p.x_m, p.y_m));
    zones.push_back({{"height_m", z.height_m}, {"polygon", poly}});
  }
  json tapes = json::array();
  for (const TapePolyline& t : c.tapes) {
    json points = json::array(), gaps = json::array();
    for (const Point2& p : t.points) points.push_back(pt(p.x_m, p.y_m));
    for (const auto& [g0, g1] : t.gaps_m) gaps.push_back(pt(g0, g1));
    tapes.push_back({{"name", t.name},
                     {"width_m", t.width_m},
                     {"reflectance", t.reflectance},
                     {"points", points},
                     {"gaps", gaps}});
  }
  json patterns = json::array();
  for (const PatternStation& p : c.patterns) {
    patterns.push_back({{"id", p.id}, {"x_m", p.x_m}, {"y_m", p.y_m}, {"yaw_rad", p.yaw_rad}});
  }
  json route = json::array();
  for (Turn t : c.route) route.push_back(turn_name(t));
  const json doc = {
      {"format", "ceilnav_course"},
      {"version", 1},
      {"name", c.name},
      {"ceiling", {{"height_m", c.ceiling_height_m}, {"zones", zones}}},
      {"tapes", tapes},
      {"patterns", patterns},
      {"start", {{"x_m", c.start.x_m}, {"y_m", c.start.y_m}, {"yaw_rad", c.start.yaw_rad}}},
      {"route", route}};
  return doc.dump(2) + "\n";
}

void save_course(const Course& course, const std::string& path) {
  validate(course, path);
  const bool json = path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
  write_file(path, json ? course_to_json(course) : course_to_yaml(course));
}

std::vector<Junction> junctions(const Course& c) {
  std::vector<Junction> out;
  const std::size_t n = c.tapes.size();
  // Tees: an end of tape i on the interior of tape j.
  for (std::size_t i = 0; i < n; ++i) {
    const TapePolyline& ti = c.tapes[i];
    for (int end = 0; end < 2; ++end) {
      const Point2& e = end == 0 ? ti.points.front() : ti.points.back();
      const Point2& inner = end == 0 ? ti.points[1] : ti.points[ti.points.size() - 2];
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const TapePolyline& tj = c.tapes[j];
        const double tol = 0.5 * std::max(ti.width_m, tj.width_m);
        const Nearest near = nearest_on(tj, e);
        if (near.distance > tol || near.arc <= tol || near.arc >= tj.length_m() - tol) continue;
        Junction jn{Junction::Kind::tee,
                    near.point,
                    {heading(e, inner)},
                    {static_cast<int>(i), static_cast<int>(j)}};
        std::vector<double> host;
        headings_at(tj, near.arc, tol, host);
        for (double h : host) add_heading_unique(jn.headings_rad, h);
        std::sort(jn.headings_rad.begin(), jn.headings_rad.end());
        out.push_back(jn);
      }
    }
  }
  // Crossings: segment interiors of two tapes meeting away from any tee.
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const TapePolyline &ti = c.tapes[i], &tj = c.tapes[j];
      const double tol = 0.5 * std::max(ti.width_m, tj.width_m);
      for (std::size_t a = 0; a + 1 < ti.points.size(); ++a) {
        for (std::size_t b = 0; b + 1 < tj.points.size(); ++b) {
          const Point2 &p0 = ti.points[a], &p1 = ti.points[a + 1];
          const Point2 &q0 = tj.points[b], &q1 = tj.points[b + 1];
          const double rx = p1.x_m - p0.x_m, ry = p1.y_m - p0.y_m;
          const double sx = q1.x_m - q0.x_m, sy = q1.y_m - q0.y_m;
          const double den = cross(rx, ry, sx, sy);
          if (std::abs(den) < 1e-12) continue;
          const double qpx = q0.x_m - p0.x_m, qpy = q0.y_m - p0.y_m;
          const double u = cross(qpx, qpy, sx, sy) / den, v = cross(qpx, qpy, rx, ry) / den;
          if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) continue;
          const Point2 x{p0.x_m + u * rx, p0.y_m + u * ry};
          // At or near a tape's end it is a tee (or no junction), not a crossing.
          const double arc_i = nearest_on(ti, x).arc, arc_j = nearest_on(tj, x).arc;
          if (arc_i <= tol || arc_i >= ti.length_m() - tol || arc_j <= tol ||
              arc_j >= tj.length_m() - tol) {
            continue;
          }
          // Through a vertex: found from both segments there once.
          if (std::any_of(out.begin(), out.end(), [&](const Junction& o) {
                return o.kind == Junction::Kind::crossing && o.tapes[0] == static_cast<int>(i) &&
                       o.tapes[1] == static_cast<int>(j) && segment_length(o.position, x) <= tol;
              })) {
            continue;
          }
          Junction jn{Junction::Kind::crossing, x, {}, {static_cast<int>(i), static_cast<int>(j)}};
          std::vector<double> hs;
          headings_at(ti, arc_i, tol, hs);
          headings_at(tj, arc_j, tol, hs);
          for (double h : hs) add_heading_unique(jn.headings_rad, h);
          std::sort(jn.headings_rad.begin(), jn.headings_rad.end());
          out.push_back(jn);
        }
      }
    }
  }
  // L-turns: interior vertices turning by 60..120 deg.
  for (std::size_t i = 0; i < n; ++i) {
    const TapePolyline& t = c.tapes[i];
    for (std::size_t k = 1; k + 1 < t.points.size(); ++k) {
      const double in = heading(t.points[k - 1], t.points[k]);
      const double outh = heading(t.points[k], t.points[k + 1]);
      const double turn = std::abs(nav::wrap_angle(outh - in));
      if (turn < 60.0 * kDeg || turn > 120.0 * kDeg) continue;
      Junction jn{Junction::Kind::l_turn,
                  t.points[k],
                  {nav::wrap_angle(in + kPi), outh},
                  {static_cast<int>(i)}};
      std::sort(jn.headings_rad.begin(), jn.headings_rad.end());
      out.push_back(jn);
    }
  }
  return out;
}

golden::CeilingScene ceiling_scene(const Course& course) {
  validate(course);
  golden::CeilingScene scene;
  for (const TapePolyline& t : course.tapes) {
    // Pieces of arc length between the gaps.
    std::vector<std::pair<double, double>> pieces;
    double from = 0.0;
    for (const auto& [g0, g1] : t.gaps_m) {
      if (g0 > from) pieces.emplace_back(from, g0);
      from = g1;
    }
    const double length = t.length_m();
    if (length > from) pieces.emplace_back(from, length);
    const double hw = 0.5 * t.width_m;
    double s0 = 0.0;
    for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
      const Point2 &a = t.points[k], &b = t.points[k + 1];
      const double len = segment_length(a, b), s1 = s0 + len;
      const double ux = (b.x_m - a.x_m) / len, uy = (b.y_m - a.y_m) / len;
      auto miter = [&](std::size_t vertex) {
        const double turn =
            std::abs(nav::wrap_angle(heading(t.points[vertex], t.points[vertex + 1]) -
                                     heading(t.points[vertex - 1], t.points[vertex])));
        return std::min(hw * std::tan(0.5 * std::min(turn, 0.99 * kPi)), t.width_m);
      };
      for (const auto& [p0, p1] : pieces) {
        const double lo = std::max(p0, s0), hi = std::min(p1, s1);
        if (!(hi > lo)) continue;
        double e0 = lo - s0, e1 = hi - s0;  // along the segment
        if (lo == s0 && k > 0) e0 -= miter(k);
        if (hi == s1 && k + 2 < t.points.size()) e1 += miter(k + 1);
        // Split where the strip crosses a zone border.
        std::vector<double> cuts{e0, e1};
        for (const HeightZone& z : course.zones) {
          for (std::size_t m = 0; m < z.polygon.size(); ++m) {
            const Point2 &q0 = z.polygon[m], &q1 = z.polygon[(m + 1) % z.polygon.size()];
            const double sx = q1.x_m - q0.x_m, sy = q1.y_m - q0.y_m;
            const double den = cross(ux, uy, sx, sy);
            if (std::abs(den) < 1e-12) continue;
            const double qpx = q0.x_m - a.x_m, qpy = q0.y_m - a.y_m;
            const double u = cross(qpx, qpy, sx, sy) / den, v = cross(qpx, qpy, ux, uy) / den;
            if (u > e0 && u < e1 && v >= 0.0 && v <= 1.0) cuts.push_back(u);
          }
        }
        std::sort(cuts.begin(), cuts.end());
        for (std::size_t m = 0; m + 1 < cuts.size(); ++m) {
          if (!(cuts[m + 1] > cuts[m])) continue;
          const double mid = 0.5 * (cuts[m] + cuts[m + 1]);
          golden::TapeSegment seg{a.x_m + cuts[m] * ux,
                                  a.y_m + cuts[m] * uy,
                                  a.x_m + cuts[m + 1] * ux,
                                  a.y_m + cuts[m + 1] * uy,
                                  t.width_m,
                                  t.reflectance};
          seg.ceiling_height_m = course.ceiling_height_at(a.x_m + mid * ux, a.y_m + mid * uy);
          scene.tapes.push_back(seg);
        }
      }
      s0 = s1;
    }
  }
  return scene;
}

Course default_course() {
  Course c = loop_course(40.0, 20.0, 20.0);
  c.name = "default";
  c.tapes[0].gaps_m = {{8.0, 8.8}, {47.0, 48.0}, {57.0, 57.5}};
  c.tapes[1].gaps_m = {{10.0, 10.6}, {30.0, 31.0}, {50.0, 50.7}};
  c.tapes[2].gaps_m = {{9.5, 10.3}};
  c.zones.push_back({{{25.0, -5.0}, {45.0, -5.0}, {45.0, 10.0}, {25.0, 10.0}}, 2.8});
  c.patterns.push_back({7, 12.0, 1.2, 0.0});
  return c;
}

Course random_course(uint64_t seed, double length_m) {
  if (!(length_m >= 60.0) || !std::isfinite(length_m)) {
    throw std::invalid_argument("random_course: length must be >= 60 m");
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double aspect = 0.4 + 0.3 * u01(rng);
  const double w = (length_m - 2.0) / (2.0 + 3.0 * aspect), h = aspect * w;
  const double xb = w * (0.35 + 0.3 * u01(rng));
  Course c = loop_course(w, h, xb);
  c.name = "random " + std::to_string(seed);
  // Gaps away from the ends and the junctions (arc positions on each tape).
  add_gaps(c.tapes[0], rng, 3, {2.0 + xb, 2.0 + w, 2.0 + w + h}, 2.0);
  add_gaps(c.tapes[1], rng, 3, {w - xb, w}, 2.0);
  add_gaps(c.tapes[2], rng, 1, {}, 2.0);
  // A zone over part of the loop with a step of 0.1..0.5 m up or down.
  const double step = (u01(rng) < 0.5 ? -1.0 : 1.0) * (0.1 + 0.4 * u01(rng));
  const double zx = xb + (w - xb) * (0.2 + 0.5 * u01(rng)), zy = h * (0.3 + 0.4 * u01(rng));
  c.zones.push_back({{{zx, -5.0}, {w + 5.0, -5.0}, {w + 5.0, zy}, {zx, zy}}, 2.5 + step});
  // A pattern station beside the first leg, 1.2 m off the tape.
  c.patterns.push_back({static_cast<int>(rng() % golden::pattern::kIdentityCount),
                        2.0 + (xb - 4.0) * u01(rng), u01(rng) < 0.5 ? 1.2 : -1.2, 0.0});
  // Rotate and shift the whole course.
  const double angle = 2.0 * kPi * u01(rng) - kPi;
  const Point2 shift{40.0 * u01(rng) - 20.0, 40.0 * u01(rng) - 20.0};
  for (TapePolyline& t : c.tapes) {
    for (Point2& p : t.points) p = rotated(p, angle, shift);
  }
  for (HeightZone& z : c.zones) {
    for (Point2& p : z.polygon) p = rotated(p, angle, shift);
  }
  for (PatternStation& p : c.patterns) {
    const Point2 q = rotated({p.x_m, p.y_m}, angle, shift);
    p = {p.id, q.x_m, q.y_m, nav::wrap_angle(p.yaw_rad + angle)};
  }
  const Point2 s = rotated({0.0, 0.0}, angle, shift);
  c.start = {s.x_m, s.y_m, nav::wrap_angle(angle)};
  validate(c, c.name);
  return c;
}

}  // namespace ceilnav::sim
