// The ceiling file: a structured ceiling (ceiling.hpp) with the lighting its
// homing sites are recorded under and the one the robot returns under, the
// camera on the robot, and the homing sites (robot poses), as YAML (or JSON
// read as YAML) of the world-file family (format/version header, metres,
// angles as <name>_deg or <name>_rad). Format: docs/navigation_io.md,
// "Ceiling files"; example: examples/homing/office.yaml.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "golden/ceiling/ceiling.hpp"

namespace ceilnav::golden::ceiling {

// The camera looking up from the robot: its centre forward_m ahead of and
// left_m left of the wheel-axis midpoint, height_m above the floor, with
// small mounting errors (Pose's pitch_error_rad, roll_error_rad).
struct RobotCamera {
  double height_m = 0.5;
  double forward_m = 0.0, left_m = 0.0;
  double pitch_error_rad = 0.0, roll_error_rad = 0.0;
  bool operator==(const RobotCamera&) const = default;
};

// The camera's Pose when the robot's wheel-axis midpoint is at (x, y) with
// heading yaw.
Pose camera_pose(const RobotCamera& camera, double x_m, double y_m, double yaw_rad);

// A homing site: the robot's pose (wheel-axis midpoint, heading CCW from +X)
// where the site is recorded.
struct SitePose {
  std::string name;
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  bool operator==(const SitePose&) const = default;
};

struct CeilingFile {
  Ceiling ceiling;
  Lighting lighting;                        // when the sites are recorded
  std::optional<Lighting> return_lighting;  // when the robot comes back (default: lighting)
  RobotCamera camera;
  std::vector<SitePose> sites;
  const Lighting& lighting_at_return() const {
    return return_lighting ? *return_lighting : lighting;
  }
  bool operator==(const CeilingFile&) const = default;
};

// The built-in homing world: office_ceiling() with three sites (each beside a
// grille or diffuser and a detector, so that no quarter turn of its patch
// reads the same), recorded with all lamps on and returned to under a dimmer
// light with a gradient and one lamp row's worth of lamps at 80 %.
CeilingFile default_homing_world();

// Throw CeilingError naming the file (or `source`), the key path (e.g.
// "vents[1].slats") and what is wrong: not YAML, unknown or missing key,
// wrong type, a value that breaks validate, a camera not below the
// ceiling, duplicate or empty site names.
CeilingFile parse_ceiling(const std::string& text, const std::string& source = "ceiling");
CeilingFile load_ceiling(const std::string& path);

// YAML that parse_ceiling reads back equal (doubles as their shortest exact
// text; angles in radians). save_ceiling validates first and writes
// "<path>.tmp", then renames it.
std::string ceiling_to_yaml(const CeilingFile& file);
void save_ceiling(const CeilingFile& file, const std::string& path);
void validate(const CeilingFile& file, const std::string& source = "ceiling");

}  // namespace ceilnav::golden::ceiling
