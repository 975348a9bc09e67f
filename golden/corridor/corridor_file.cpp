#include "golden/corridor/corridor_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <numbers>
#include <sstream>

#include "common/yaml_reader.hpp"

namespace ceilnav::golden::corridor {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Reader : YamlReader<CorridorError> {
  // An optional number: `value` keeps its default when the key is absent.
  void optional(const YAML::Node& map, const char* name, const std::string& key,
                double& value) const {
    if (map[name]) value = number(map[name], key + "." + name);
  }

  // An angle given as <name>_rad or <name>_deg (exactly one; absent: 0).
  double angle(const YAML::Node& map, const std::string& key, const std::string& name) const {
    const YAML::Node rad = map[name + "_rad"], deg = map[name + "_deg"];
    if (rad && deg) fail(key, "needs at most one of " + name + "_rad and " + name + "_deg");
    if (rad) return number(rad, key + "." + name + "_rad");
    if (deg) return number(deg, key + "." + name + "_deg") * kDeg;
    return 0.0;
  }
};

Corridor read_corridor(const Reader& r, const YAML::Node& root) {
  Corridor c;
  if (root["name"]) c.name = r.text(root["name"], "name");
  const YAML::Node g = root["geometry"];
  r.keys(g, "geometry", {"width_m", "ceiling_height_m", "x_start_m", "length_m", "far_end"},
         {"width_m", "ceiling_height_m", "length_m"});
  c.width_m = r.number(g["width_m"], "geometry.width_m");
  c.ceiling_height_m = r.number(g["ceiling_height_m"], "geometry.ceiling_height_m");
  c.length_m = r.number(g["length_m"], "geometry.length_m");
  r.optional(g, "x_start_m", "geometry", c.x_start_m);
  if (g["far_end"]) {
    const std::string end = r.text(g["far_end"], "geometry.far_end");
    if (end != "wall" && end != "open") r.fail("geometry.far_end", "must be 'wall' or 'open'");
    c.far_end_open = end == "open";
  }
  if (const YAML::Node s = root["surfaces"]) {
    r.keys(s, "surfaces", {"ceiling_albedo", "wall_albedo", "floor_albedo", "end_wall_albedo"}, {});
    r.optional(s, "ceiling_albedo", "surfaces", c.ceiling_albedo);
    r.optional(s, "wall_albedo", "surfaces", c.wall_albedo);
    r.optional(s, "floor_albedo", "surfaces", c.floor_albedo);
    r.optional(s, "end_wall_albedo", "surfaces", c.end_wall_albedo);
  }
  if (const YAML::Node li = root["lighting"]) {
    r.keys(
        li, "lighting",
        {"ceiling_light", "wall_light_floor", "wall_light_ceiling", "floor_light", "open_radiance"},
        {});
    r.optional(li, "ceiling_light", "lighting", c.lighting.ceiling_light);
    r.optional(li, "wall_light_floor", "lighting", c.lighting.wall_light_floor);
    r.optional(li, "wall_light_ceiling", "lighting", c.lighting.wall_light_ceiling);
    r.optional(li, "floor_light", "lighting", c.lighting.floor_light);
    r.optional(li, "open_radiance", "lighting", c.lighting.open_radiance);
  }
  if (const YAML::Node l = root["lamps"]) {
    r.keys(l, "lamps", {"rows_y_m", "length_m", "width_m", "spacing_m", "first_x_m", "radiance"},
           {"rows_y_m"});
    const YAML::Node rows = r.sequence(l["rows_y_m"], "lamps.rows_y_m");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      c.lamps.rows_y_m.push_back(r.number(rows[i], yaml_at("lamps.rows_y_m", i)));
    }
    r.optional(l, "length_m", "lamps", c.lamps.length_m);
    r.optional(l, "width_m", "lamps", c.lamps.width_m);
    r.optional(l, "spacing_m", "lamps", c.lamps.spacing_m);
    r.optional(l, "first_x_m", "lamps", c.lamps.first_x_m);
    r.optional(l, "radiance", "lamps", c.lamps.radiance);
  }
  if (const YAML::Node s = root["seams"]) {
    r.keys(s, "seams",
           {"along_pitch_m", "along_origin_m", "across_pitch_m", "across_origin_m", "width_m",
            "albedo"},
           {});
    r.optional(s, "along_pitch_m", "seams", c.seams.along_pitch_m);
    r.optional(s, "along_origin_m", "seams", c.seams.along_origin_m);
    r.optional(s, "across_pitch_m", "seams", c.seams.across_pitch_m);
    r.optional(s, "across_origin_m", "seams", c.seams.across_origin_m);
    r.optional(s, "width_m", "seams", c.seams.width_m);
    r.optional(s, "albedo", "seams", c.seams.albedo);
  }
  for (const auto& [name, band] : {std::pair{"cornice", &c.cornice}, {"skirting", &c.skirting}}) {
    if (const YAML::Node b = root[name]) {
      r.keys(b, name, {"height_m", "albedo"}, {"height_m"});
      band->height_m = r.number(b["height_m"], std::string(name) + ".height_m");
      r.optional(b, "albedo", name, band->albedo);
    }
  }
  if (root["doors"]) {
    const YAML::Node doors = r.sequence(root["doors"], "doors");
    for (std::size_t i = 0; i < doors.size(); ++i) {
      const std::string key = yaml_at("doors", i);
      const YAML::Node d = doors[i];
      r.keys(d, key,
             {"wall", "x_m", "width_m", "height_m", "frame_width_m", "albedo", "frame_albedo"},
             {"wall", "x_m", "width_m", "height_m"});
      Door door;
      const std::string wall = r.text(d["wall"], key + ".wall");
      if (wall != "left" && wall != "right") r.fail(key + ".wall", "must be 'left' or 'right'");
      door.wall = wall == "left" ? Wall::left : Wall::right;
      door.x_m = r.number(d["x_m"], key + ".x_m");
      door.width_m = r.number(d["width_m"], key + ".width_m");
      door.height_m = r.number(d["height_m"], key + ".height_m");
      r.optional(d, "frame_width_m", key, door.frame_width_m);
      r.optional(d, "albedo", key, door.albedo);
      r.optional(d, "frame_albedo", key, door.frame_albedo);
      c.doors.push_back(door);
    }
  }
  return c;
}

Pose read_pose(const Reader& r, const YAML::Node& m) {
  r.keys(m, "camera",
         {"x_m", "y_m", "height_m", "pan_rad", "pan_deg", "tilt_rad", "tilt_deg", "swing_rad",
          "swing_deg"},
         {"x_m", "y_m", "height_m"});
  return {r.number(m["x_m"], "camera.x_m"),
          r.number(m["y_m"], "camera.y_m"),
          r.number(m["height_m"], "camera.height_m"),
          r.angle(m, "camera", "pan"),
          r.angle(m, "camera", "tilt"),
          r.angle(m, "camera", "swing")};
}

}  // namespace

CorridorFile parse_corridor(const std::string& text, const std::string& source) {
  const Reader r{{source}};
  const YAML::Node root =
      r.world_root(text, "ceilnav_corridor",
                   {"format", "version", "name", "geometry", "surfaces", "lighting", "lamps",
                    "seams", "cornice", "skirting", "doors", "camera"},
                   {"format", "version", "geometry"});
  CorridorFile file;
  file.corridor = read_corridor(r, root);
  validate(file.corridor, source);
  if (root["camera"]) {
    file.camera = read_pose(r, root["camera"]);
    validate(*file.camera, file.corridor, source);
  }
  return file;
}

CorridorFile load_corridor(const std::string& path) {
  return parse_corridor(read_world_text<CorridorError>(path), path);
}

std::string corridor_to_yaml(const CorridorFile& file) {
  const Corridor& c = file.corridor;
  const auto num = yaml_number_text;
  YAML::Emitter out;
  auto pair = [&](const char* key, double v) { out << YAML::Key << key << YAML::Value << num(v); };
  out << YAML::BeginMap;
  out << YAML::Key << "format" << YAML::Value << "ceilnav_corridor";
  out << YAML::Key << "version" << YAML::Value << 1;
  out << YAML::Key << "name" << YAML::Value << YAML::DoubleQuoted << c.name;
  out << YAML::Key << "geometry" << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("width_m", c.width_m);
  pair("ceiling_height_m", c.ceiling_height_m);
  pair("x_start_m", c.x_start_m);
  pair("length_m", c.length_m);
  out << YAML::Key << "far_end" << YAML::Value << (c.far_end_open ? "open" : "wall");
  out << YAML::EndMap;
  out << YAML::Key << "surfaces" << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("ceiling_albedo", c.ceiling_albedo);
  pair("wall_albedo", c.wall_albedo);
  pair("floor_albedo", c.floor_albedo);
  pair("end_wall_albedo", c.end_wall_albedo);
  out << YAML::EndMap;
  out << YAML::Key << "lighting" << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("ceiling_light", c.lighting.ceiling_light);
  pair("wall_light_floor", c.lighting.wall_light_floor);
  pair("wall_light_ceiling", c.lighting.wall_light_ceiling);
  pair("floor_light", c.lighting.floor_light);
  pair("open_radiance", c.lighting.open_radiance);
  out << YAML::EndMap;
  out << YAML::Key << "lamps" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "rows_y_m" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double y : c.lamps.rows_y_m) out << num(y);
  out << YAML::EndSeq;
  pair("length_m", c.lamps.length_m);
  pair("width_m", c.lamps.width_m);
  pair("spacing_m", c.lamps.spacing_m);
  pair("first_x_m", c.lamps.first_x_m);
  pair("radiance", c.lamps.radiance);
  out << YAML::EndMap;
  out << YAML::Key << "seams" << YAML::Value << YAML::Flow << YAML::BeginMap;
  pair("along_pitch_m", c.seams.along_pitch_m);
  pair("along_origin_m", c.seams.along_origin_m);
  pair("across_pitch_m", c.seams.across_pitch_m);
  pair("across_origin_m", c.seams.across_origin_m);
  pair("width_m", c.seams.width_m);
  pair("albedo", c.seams.albedo);
  out << YAML::EndMap;
  for (const auto& [name, band] : {std::pair{"cornice", &c.cornice}, {"skirting", &c.skirting}}) {
    out << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap;
    pair("height_m", band->height_m);
    pair("albedo", band->albedo);
    out << YAML::EndMap;
  }
  out << YAML::Key << "doors" << YAML::Value << YAML::BeginSeq;
  for (const Door& d : c.doors) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "wall" << YAML::Value << (d.wall == Wall::left ? "left" : "right");
    pair("x_m", d.x_m);
    pair("width_m", d.width_m);
    pair("height_m", d.height_m);
    pair("frame_width_m", d.frame_width_m);
    pair("albedo", d.albedo);
    pair("frame_albedo", d.frame_albedo);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  if (file.camera) {
    const Pose& p = *file.camera;
    out << YAML::Key << "camera" << YAML::Value << YAML::Flow << YAML::BeginMap;
    pair("x_m", p.x_m);
    pair("y_m", p.y_m);
    pair("height_m", p.height_m);
    pair("pan_rad", p.pan_rad);
    pair("tilt_rad", p.tilt_rad);
    pair("swing_rad", p.swing_rad);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  if (!out.good()) throw CorridorError("corridor_to_yaml: " + out.GetLastError());
  return std::string(
             "# ceilnav corridor (docs/navigation_io.md, \"Corridor files\"; docs/renderer.md)\n") +
         out.c_str() + "\n";
}

void save_corridor(const CorridorFile& file, const std::string& path) {
  validate(file.corridor, path);
  if (file.camera) validate(*file.camera, file.corridor, path);
  write_world_file<CorridorError>(path, corridor_to_yaml(file));
}

}  // namespace ceilnav::golden::corridor
