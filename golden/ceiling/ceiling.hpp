// Structured ceilings for seed 004's homing (docs/renderer.md, "Structured
// ceilings"): a flat ceiling of acoustic tiles in a grid, rectangular lamps,
// ventilation grilles with slats, beams and small round fixtures (sprinklers,
// detectors), under a lighting that may change between the recording of a
// homing site and the return to it (gain, a linear gradient, lamps on or
// off). Seen by a camera looking up (the seed's vertical camera), with small
// mounting errors. The radiance of a ceiling point is a pure function of
// (X, Y): the renderer (render.hpp) integrates it over pixel footprints.
//
// World frame (BRIEF section 5): X, Y on the floor, Z up; the ceiling is the
// plane Z = height_m. Feature angles are counter-clockwise from +X.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

namespace ceilnav::golden::ceiling {

// Square-edged tiles: a grid of gaps (the T-bar grid) width gap_m wide at x
// = origin_x_m + i pitch_x_m and y = origin_y_m + j pitch_y_m, turned by
// angle_rad about the origin. pitch 0: no grid in that direction.
struct Tiles {
  double pitch_x_m = 0.6, pitch_y_m = 0.6;
  double origin_x_m = 0.0, origin_y_m = 0.0;
  double angle_rad = 0.0;
  double gap_m = 0.024;
  double tile_albedo = 0.8, grid_albedo = 0.55;
  bool operator==(const Tiles&) const = default;
};

// A rectangle on the ceiling: centre, size along its own axes, turned by
// angle_rad.
struct Rect {
  double x_m = 0.0, y_m = 0.0;
  double length_m = 1.2, width_m = 0.3;  // along its axis / across
  double angle_rad = 0.0;
  bool operator==(const Rect&) const = default;
};

// An emissive lamp (its diffuser), with a darker frame border_m wide.
struct Lamp {
  Rect rect;
  double radiance = 3.0;  // when on
  double border_m = 0.02;
  double frame_albedo = 0.9;
  bool operator==(const Lamp&) const = default;
};

// A grille: a frame border_m wide, inside it `slats` dark slots across its
// length (slot and bar of equal width).
struct Vent {
  Rect rect;
  int slats = 8;
  double border_m = 0.03;
  double frame_albedo = 0.85, slot_albedo = 0.1;
  bool operator==(const Vent&) const = default;
};

// A straight beam or duct seen from below: a strip between two points.
struct Beam {
  double x0_m = 0.0, y0_m = 0.0, x1_m = 1.0, y1_m = 0.0;
  double width_m = 0.2;
  double albedo = 0.6;
  bool operator==(const Beam&) const = default;
};

// A round fixture: sprinkler, detector, downlight rim.
struct Spot {
  double x_m = 0.0, y_m = 0.0, radius_m = 0.04;
  double albedo = 0.3;
  bool operator==(const Spot&) const = default;
};

struct Ceiling {
  std::string name;
  double height_m = 3.5;      // above the floor
  double plain_albedo = 0.8;  // where no tile grid is given (pitches 0)
  Tiles tiles;
  std::vector<Lamp> lamps;
  std::vector<Vent> vents;
  std::vector<Beam> beams;
  std::vector<Spot> spots;
  bool operator==(const Ceiling&) const = default;
};

// The light on the ceiling: light(X, Y) = gain (1 + gradient . (X, Y) -
// origin), at least 0; lamps emit `radiance` x lamp_gain when lamps_on, else
// their diffuser shows albedo lamp_off_albedo under the light. A homing site
// recorded under one Lighting and returned to under another: the template
// must match across the change.
struct Lighting {
  double gain = 1.0;
  double gradient_x_per_m = 0.0, gradient_y_per_m = 0.0;
  double origin_x_m = 0.0, origin_y_m = 0.0;
  bool lamps_on = true;
  double lamp_gain = 1.0;
  double lamp_off_albedo = 0.7;
  bool operator==(const Lighting&) const = default;
};

class CeilingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Positive height and sizes, albedos and radiances >= 0 and finite, a gap
// narrower than its pitch, borders inside their rectangles, at least one
// slat, finite positions. Throws CeilingError naming `source` and the key.
void validate(const Ceiling& ceiling, const std::string& source = "ceiling");
void validate(const Lighting& lighting, const std::string& source = "lighting");

// What covers a ceiling point, topmost first: lamps, vents, spots, beams,
// then the tile grid or plain ceiling. `id` tells painted regions apart (the
// renderer's uniform-footprint test): two points with the same id have the
// same albedo or emission.
struct Paint {
  int id = 0;
  bool emissive = false;
  double value = 0.0;  // albedo, or radiance when emissive (before the lighting)
};
Paint paint_at(const Ceiling& ceiling, const Lighting& lighting, double x_m, double y_m);
double light_at(const Lighting& lighting, double x_m, double y_m);
// A lower bound of the distance from (x, y) to the nearest border between
// two paints (of any feature, covered or not): a disc of that radius lies
// on one paint. The renderer's test for a footprint without a border (thin
// strips, the 24 mm grid, can cross a footprint between its corners).
double border_distance(const Ceiling& ceiling, double x_m, double y_m);
// The radiance seen at a ceiling point: emissive value x lamp_gain, or
// albedo x light.
double radiance_at(const Ceiling& ceiling, const Lighting& lighting, double x_m, double y_m);

// The built-in homing ceilings (docs/renderer.md): an office ceiling of 0.6 m
// tiles at 3.5 m with lamps, grilles and sprinklers ("office"), a corridor
// of 1.2 x 0.6 m tiles with a beam ("hall").
Ceiling office_ceiling();
Ceiling hall_ceiling();

// The camera looking up: centre (x_m, y_m, height_m), heading yaw_rad (the
// direction the image's top edge... see view_of), optical axis vertical up
// to within the small mounting errors pitch_error_rad (tilt toward the
// heading) and roll_error_rad (toward the left).
struct Pose {
  double x_m = 0.0, y_m = 0.0, height_m = 0.5;
  double yaw_rad = 0.0;
  double pitch_error_rad = 0.0, roll_error_rad = 0.0;
  bool operator==(const Pose&) const = default;
};

}  // namespace ceilnav::golden::ceiling
