// The corridor file: a Corridor and optionally a camera pose, as YAML (or
// JSON read as YAML) of the course file family (format/version header,
// metres and radians or degrees). Format: docs/navigation_io.md, "Corridor
// files"; example: examples/corridor/default.yaml.
#pragma once

#include <optional>
#include <string>

#include "golden/corridor/corridor.hpp"

namespace ceilnav::golden::corridor {

struct CorridorFile {
  Corridor corridor;
  std::optional<Pose> camera;  // the file's `camera` view, when it has one
  bool operator==(const CorridorFile&) const = default;
};

// Throw CorridorError naming the file (or `source`), the key path (e.g.
// "doors[1].width_m") and what is wrong: not YAML, unknown or missing key,
// wrong type, or a value that breaks validate (negative width, lamps off
// the ceiling, a camera outside the corridor...).
CorridorFile parse_corridor(const std::string& text, const std::string& source = "corridor");
CorridorFile load_corridor(const std::string& path);

// YAML that parse_corridor reads back equal (every double as the shortest
// text that reads back the same; angles in radians). save_corridor
// validates first, writes "<path>.tmp" and renames it.
std::string corridor_to_yaml(const CorridorFile& file);
void save_corridor(const CorridorFile& file, const std::string& path);

}  // namespace ceilnav::golden::corridor
