#include "golden/ceiling/ceiling_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>
#include <vector>

#include "common/yaml_reader.hpp"

namespace ceilnav::golden::ceiling {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A number of a map: a length or albedo by its key, an angle as
// <name>_rad or <name>_deg (stored in radians).
struct Field {
  const char* name;
  double* value;
  bool angle = false;
  bool required = false;
};

struct Reader : YamlReader<CeilingError> {
  // Reads `fields` (and `extra` keys the caller reads itself) of the map.
  void fields(const YAML::Node& map, const std::string& key, const std::vector<Field>& fs,
              const std::vector<const char*>& extra = {}) const {
    if (!map.IsMap()) fail(key, "must be a map");
    for (const auto& kv : map) {
      const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
      bool known =
          std::any_of(extra.begin(), extra.end(), [&](const char* e) { return name == e; });
      for (const Field& f : fs) {
        known = known || (f.angle ? name == std::string(f.name) + "_rad" ||
                                        name == std::string(f.name) + "_deg"
                                  : name == f.name);
      }
      if (!known) fail(key.empty() ? name : key + "." + name, "unknown key");
    }
    for (const Field& f : fs) {
      const std::string at = key.empty() ? std::string(f.name) : key + "." + f.name;
      if (!f.angle) {
        if (map[f.name]) {
          *f.value = number(map[f.name], at);
        } else if (f.required) {
          fail(at, "missing");
        }
        continue;
      }
      const YAML::Node rad = map[std::string(f.name) + "_rad"];
      const YAML::Node deg = map[std::string(f.name) + "_deg"];
      if (rad && deg) fail(at, "needs at most one of _rad and _deg");
      if (rad) *f.value = number(rad, at + "_rad");
      if (deg) *f.value = number(deg, at + "_deg") * kDeg;
      if (!rad && !deg && f.required) fail(at + "_deg", "missing");
    }
  }

  bool boolean(const YAML::Node& node, const std::string& key) const {
    if (!node || !node.IsScalar()) fail(key, "must be true or false");
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
      fail(key, "'" + node.Scalar() + "' is not true or false");
    }
  }
};

// A feature's rectangle and its own keys, in one map.
void read_rect(const Reader& r, const YAML::Node& m, const std::string& key, Rect& rect,
               std::vector<Field> more, const std::vector<const char*>& extra = {}) {
  more.insert(more.end(), {{"x_m", &rect.x_m, false, true},
                           {"y_m", &rect.y_m, false, true},
                           {"length_m", &rect.length_m, false, true},
                           {"width_m", &rect.width_m, false, true},
                           {"angle", &rect.angle_rad, true}});
  r.fields(m, key, more, extra);
}

Lighting read_lighting(const Reader& r, const YAML::Node& m, const std::string& key) {
  Lighting l;
  r.fields(m, key,
           {{"gain", &l.gain},
            {"gradient_x_per_m", &l.gradient_x_per_m},
            {"gradient_y_per_m", &l.gradient_y_per_m},
            {"origin_x_m", &l.origin_x_m},
            {"origin_y_m", &l.origin_y_m},
            {"lamp_gain", &l.lamp_gain},
            {"lamp_off_albedo", &l.lamp_off_albedo}},
           {"lamps_on"});
  if (m["lamps_on"]) l.lamps_on = r.boolean(m["lamps_on"], key + ".lamps_on");
  return l;
}

CeilingFile read_file(const Reader& r, const YAML::Node& root) {
  CeilingFile f;
  Ceiling& c = f.ceiling;
  if (root["name"]) c.name = r.text(root["name"], "name");
  if (root["tiles"]) {
    Tiles& t = c.tiles;
    r.fields(root["tiles"], "tiles",
             {{"pitch_x_m", &t.pitch_x_m},
              {"pitch_y_m", &t.pitch_y_m},
              {"origin_x_m", &t.origin_x_m},
              {"origin_y_m", &t.origin_y_m},
              {"angle", &t.angle_rad, true},
              {"gap_m", &t.gap_m},
              {"tile_albedo", &t.tile_albedo},
              {"grid_albedo", &t.grid_albedo}});
  } else {
    c.tiles.pitch_x_m = c.tiles.pitch_y_m = 0.0;  // no tiles: a plain ceiling
  }
  const auto each = [&](const char* name, auto&& read) {
    if (!root[name]) return;
    const YAML::Node seq = r.sequence(root[name], name);
    for (std::size_t i = 0; i < seq.size(); ++i) read(seq[i], yaml_at(name, i));
  };
  each("lamps", [&](const YAML::Node& m, const std::string& key) {
    Lamp l;
    read_rect(
        r, m, key, l.rect,
        {{"radiance", &l.radiance}, {"border_m", &l.border_m}, {"frame_albedo", &l.frame_albedo}});
    c.lamps.push_back(l);
  });
  each("vents", [&](const YAML::Node& m, const std::string& key) {
    Vent v;
    read_rect(r, m, key, v.rect,
              {{"border_m", &v.border_m},
               {"frame_albedo", &v.frame_albedo},
               {"slot_albedo", &v.slot_albedo}},
              {"slats"});
    if (m["slats"]) v.slats = r.integer(m["slats"], key + ".slats");
    c.vents.push_back(v);
  });
  each("beams", [&](const YAML::Node& m, const std::string& key) {
    Beam b;
    r.fields(m, key,
             {{"x0_m", &b.x0_m, false, true},
              {"y0_m", &b.y0_m, false, true},
              {"x1_m", &b.x1_m, false, true},
              {"y1_m", &b.y1_m, false, true},
              {"width_m", &b.width_m},
              {"albedo", &b.albedo}});
    c.beams.push_back(b);
  });
  each("spots", [&](const YAML::Node& m, const std::string& key) {
    Spot s;
    r.fields(m, key,
             {{"x_m", &s.x_m, false, true},
              {"y_m", &s.y_m, false, true},
              {"radius_m", &s.radius_m},
              {"albedo", &s.albedo}});
    c.spots.push_back(s);
  });
  c.height_m = r.number(root["height_m"], "height_m");
  if (root["plain_albedo"]) c.plain_albedo = r.number(root["plain_albedo"], "plain_albedo");
  if (root["lighting"]) f.lighting = read_lighting(r, root["lighting"], "lighting");
  if (root["return_lighting"]) {
    f.return_lighting = read_lighting(r, root["return_lighting"], "return_lighting");
  }
  if (root["camera"]) {
    RobotCamera& k = f.camera;
    r.fields(root["camera"], "camera",
             {{"height_m", &k.height_m, false, true},
              {"forward_m", &k.forward_m},
              {"left_m", &k.left_m},
              {"pitch_error", &k.pitch_error_rad, true},
              {"roll_error", &k.roll_error_rad, true}});
  }
  each("sites", [&](const YAML::Node& m, const std::string& key) {
    SitePose s;
    r.fields(m, key,
             {{"x_m", &s.x_m, false, true},
              {"y_m", &s.y_m, false, true},
              {"yaw", &s.yaw_rad, true, true}},
             {"name"});
    if (!m["name"]) r.fail(key + ".name", "missing");
    s.name = r.text(m["name"], key + ".name");
    f.sites.push_back(s);
  });
  return f;
}

}  // namespace

Pose camera_pose(const RobotCamera& camera, double x_m, double y_m, double yaw_rad) {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  Pose p;
  p.x_m = x_m + c * camera.forward_m - s * camera.left_m;
  p.y_m = y_m + s * camera.forward_m + c * camera.left_m;
  p.height_m = camera.height_m;
  p.yaw_rad = yaw_rad;
  p.pitch_error_rad = camera.pitch_error_rad;
  p.roll_error_rad = camera.roll_error_rad;
  return p;
}

CeilingFile default_homing_world() {
  CeilingFile f;
  f.ceiling = office_ceiling();
  f.camera.height_m = 0.5;
  f.camera.forward_m = 0.1;
  f.camera.pitch_error_rad = 0.3 * kDeg;
  f.camera.roll_error_rad = -0.2 * kDeg;
  // Beside the grille at (1.5, 0.3) and its detector (below right of it);
  // beside the grille at (-3.3, -0.3) and its detector (above right); beside
  // the turned diffuser at (4.2, -0.9) (its patch turned by 180 deg reads
  // alike mirrored through the diffuser's centre: the odometry's heading
  // picks the quadrant). Sides 4.7, 7.1 and 2.5 m.
  f.sites = {{"site 1", 1.6, 0.15, 0.0},
             {"site 2", -3.1, -0.3, 150.0 * kDeg},
             {"site 3", 4.0, -0.6, -100.0 * kDeg}};
  Lighting back;
  back.gain = 0.8;
  back.gradient_x_per_m = 0.03;
  back.gradient_y_per_m = -0.02;
  back.lamp_gain = 0.8;
  f.return_lighting = back;
  return f;
}

void validate(const CeilingFile& f, const std::string& source) {
  validate(f.ceiling, source);
  validate(f.lighting, source + ": lighting");
  if (f.return_lighting) validate(*f.return_lighting, source + ": return_lighting");
  const RobotCamera& k = f.camera;
  const auto fail = [&](const std::string& key, const std::string& what) {
    throw CeilingError(source + ": " + key + ": " + what);
  };
  for (const auto& [v, key] : {std::pair{k.height_m, "camera.height_m"},
                               {k.forward_m, "camera.forward_m"},
                               {k.left_m, "camera.left_m"},
                               {k.pitch_error_rad, "camera.pitch_error"},
                               {k.roll_error_rad, "camera.roll_error"}}) {
    if (!std::isfinite(v)) fail(key, "must be finite");
  }
  if (!(k.height_m > 0.0)) fail("camera.height_m", "must be > 0");
  if (!(k.height_m < f.ceiling.height_m - 0.1)) {
    fail("camera.height_m", "must be at least 0.1 m below the ceiling");
  }
  if (std::abs(k.pitch_error_rad) > 10.0 * kDeg || std::abs(k.roll_error_rad) > 10.0 * kDeg) {
    fail("camera", "mounting errors must be within 10 deg");
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < f.sites.size(); ++i) {
    const SitePose& s = f.sites[i];
    const std::string key = yaml_at("sites", i);
    if (s.name.empty()) fail(key + ".name", "must not be empty");
    if (!names.insert(s.name).second) fail(key + ".name", "'" + s.name + "' is used twice");
    if (!std::isfinite(s.x_m) || !std::isfinite(s.y_m) || !std::isfinite(s.yaw_rad)) {
      fail(key, "must be finite");
    }
  }
}

CeilingFile parse_ceiling(const std::string& text, const std::string& source) {
  const Reader r{{source}};
  const YAML::Node root =
      r.world_root(text, "ceilnav_ceiling",
                   {"format", "version", "name", "height_m", "plain_albedo", "tiles", "lamps",
                    "vents", "beams", "spots", "lighting", "return_lighting", "camera", "sites"},
                   {"format", "version", "height_m"});
  CeilingFile f = read_file(r, root);
  validate(f, source);
  return f;
}

CeilingFile load_ceiling(const std::string& path) {
  return parse_ceiling(read_world_text<CeilingError>(path), path);
}

std::string ceiling_to_yaml(const CeilingFile& f) {
  const Ceiling& c = f.ceiling;
  YAML::Emitter out;
  const auto pair = [&](const char* key, double v) {
    out << YAML::Key << key << YAML::Value << yaml_number_text(v);
  };
  const auto rect = [&](const Rect& r) {
    pair("x_m", r.x_m);
    pair("y_m", r.y_m);
    pair("length_m", r.length_m);
    pair("width_m", r.width_m);
    pair("angle_rad", r.angle_rad);
  };
  const auto lighting = [&](const char* key, const Lighting& l) {
    out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
    pair("gain", l.gain);
    pair("gradient_x_per_m", l.gradient_x_per_m);
    pair("gradient_y_per_m", l.gradient_y_per_m);
    pair("origin_x_m", l.origin_x_m);
    pair("origin_y_m", l.origin_y_m);
    out << YAML::Key << "lamps_on" << YAML::Value << l.lamps_on;
    pair("lamp_gain", l.lamp_gain);
    pair("lamp_off_albedo", l.lamp_off_albedo);
    out << YAML::EndMap;
  };
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << "ceilnav_ceiling";
  out << YAML::Key << "version" << YAML::Value << 1;
  out << YAML::Key << "name" << YAML::Value << YAML::DoubleQuoted << c.name;
  pair("height_m", c.height_m);
  pair("plain_albedo", c.plain_albedo);
  out << YAML::Key << "tiles" << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("pitch_x_m", c.tiles.pitch_x_m);
  pair("pitch_y_m", c.tiles.pitch_y_m);
  pair("origin_x_m", c.tiles.origin_x_m);
  pair("origin_y_m", c.tiles.origin_y_m);
  pair("angle_rad", c.tiles.angle_rad);
  pair("gap_m", c.tiles.gap_m);
  pair("tile_albedo", c.tiles.tile_albedo);
  pair("grid_albedo", c.tiles.grid_albedo);
  out << YAML::EndMap;
  out << YAML::Key << "lamps" << YAML::Value << YAML::BeginSeq;
  for (const Lamp& l : c.lamps) {
    out << YAML::Flow << YAML::BeginMap;
    rect(l.rect);
    pair("radiance", l.radiance);
    pair("border_m", l.border_m);
    pair("frame_albedo", l.frame_albedo);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "vents" << YAML::Value << YAML::BeginSeq;
  for (const Vent& v : c.vents) {
    out << YAML::Flow << YAML::BeginMap;
    rect(v.rect);
    out << YAML::Key << "slats" << YAML::Value << v.slats;
    pair("border_m", v.border_m);
    pair("frame_albedo", v.frame_albedo);
    pair("slot_albedo", v.slot_albedo);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "beams" << YAML::Value << YAML::BeginSeq;
  for (const Beam& b : c.beams) {
    out << YAML::Flow << YAML::BeginMap;
    pair("x0_m", b.x0_m);
    pair("y0_m", b.y0_m);
    pair("x1_m", b.x1_m);
    pair("y1_m", b.y1_m);
    pair("width_m", b.width_m);
    pair("albedo", b.albedo);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "spots" << YAML::Value << YAML::BeginSeq;
  for (const Spot& s : c.spots) {
    out << YAML::Flow << YAML::BeginMap;
    pair("x_m", s.x_m);
    pair("y_m", s.y_m);
    pair("radius_m", s.radius_m);
    pair("albedo", s.albedo);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  lighting("lighting", f.lighting);
  if (f.return_lighting) lighting("return_lighting", *f.return_lighting);
  out << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("height_m", f.camera.height_m);
  pair("forward_m", f.camera.forward_m);
  pair("left_m", f.camera.left_m);
  pair("pitch_error_rad", f.camera.pitch_error_rad);
  pair("roll_error_rad", f.camera.roll_error_rad);
  out << YAML::EndMap;
  out << YAML::Key << "sites" << YAML::Value << YAML::BeginSeq;
  for (const SitePose& s : f.sites) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << YAML::DoubleQuoted << s.name;
    pair("x_m", s.x_m);
    pair("y_m", s.y_m);
    pair("yaw_rad", s.yaw_rad);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::EndMap;
  if (!out.good()) throw CeilingError("ceiling_to_yaml: " + out.GetLastError());
  return std::string(
             "# ceilnav ceiling (docs/navigation_io.md, \"Ceiling files\"; docs/renderer.md)\n") +
         out.c_str() + "\n";
}

void save_ceiling(const CeilingFile& file, const std::string& path) {
  validate(file, path);
  write_world_file<CeilingError>(path, ceiling_to_yaml(file));
}

}  // namespace ceilnav::golden::ceiling
