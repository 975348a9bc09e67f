// Seed 004's topological map (sections 3.4, 4.3): nodes are homing sites
// (a recorded patch of ceiling and the robot's pose there), edges the
// odometric paths between them (turn in place, straight leg, turn in place:
// what the robot drives on its wheel odometry alone before homing at the
// next site). Stored as a folder: map.json (format, sites, paths) and one
// 16-bit PNG per site's patch. Format: docs/navigation_io.md, "Site maps".
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "host/homing/tracker.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::host::homing {

struct MapSite {
  std::string name;
  nav::Pose2 pose;  // the robot's (wheel-axis midpoint) when recorded
  Site site;
  // The camera's look point on the ceiling ahead of / left of the wheel-axis
  // midpoint (nav::look_offset_from_turns at the site; the servo's
  // camera offset when homing here).
  double look_forward_m = 0.0, look_left_m = 0.0;
  // Empty when the site can be homed on; else why not (the turns in place
  // at the recording did not find it again: it reads alike elsewhere or
  // turned). The race does not home on such a site.
  std::string unusable;
};

// From site `from`'s pose: turn by turn_rad, drive distance_m straight,
// turn by final_turn_rad: site `to`'s pose.
struct OdometricPath {
  int from = 0, to = 0;
  double turn_rad = 0.0, distance_m = 0.0, final_turn_rad = 0.0;
};
// The path from pose a to pose b (turns wrapped to [-pi, pi)).
OdometricPath path_between(const nav::Pose2& a, const nav::Pose2& b, int from, int to);

struct SiteMap {
  std::vector<MapSite> sites;
  std::vector<OdometricPath> paths;
  // The path leaving `from` (the first listed); nullptr without one.
  const OdometricPath* path_from(int from) const;
};

class SiteMapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes folder/map.json and folder/site_<k>.png (the patch x 256, 16 bit:
// 1/256 grey resolution); the folder must exist. Throws SiteMapError.
void save_site_map(const SiteMap& map, const std::string& folder);
// Reads a map written by save_site_map; every problem (missing file, bad
// JSON, unknown format, a path naming no site, a patch of the wrong size)
// is a SiteMapError naming the file and key.
SiteMap load_site_map(const std::string& map_json);

}  // namespace ceilnav::host::homing
