// Ceiling courses: retroreflective tape polylines with gaps, the ceiling
// height (a default and zones), seed-003 pattern stations, the start pose
// and the route; their junctions; the course file (YAML or JSON); the
// built-in default course and a random course generator. File format:
// docs/navigation.md, "Course files".
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "golden/scene.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::sim {

struct Point2 {
  double x_m = 0.0, y_m = 0.0;
  bool operator==(const Point2&) const = default;
};

// One tape: a centre-line polyline of >= 2 points, its width and
// reflectance, and gaps cut out of it as [start, end] arc-length intervals
// (metres from the first point), sorted, disjoint, inside [0, length].
struct TapePolyline {
  std::string name;
  std::vector<Point2> points;
  double width_m = 0.05;
  double reflectance = 1.0;
  std::vector<std::pair<double, double>> gaps_m;
  double length_m() const;
  bool operator==(const TapePolyline&) const = default;
};

// A ceiling zone of its own height: a polygon (>= 3 vertices, either
// orientation, not self-intersecting). A rectangle is stored as its four
// corners. Where zones overlap, the later one in the list holds.
struct HeightZone {
  std::vector<Point2> polygon;
  double height_m = 0.0;
  bool contains(double x_m, double y_m) const;
  bool operator==(const HeightZone&) const = default;
};

// A seed-003 pattern on the ceiling, face down: disc centre at (x, y) on the
// ceiling, its +y axis (the bar code's "up") along yaw_rad (CCW from +X),
// identity in [0, golden::pattern::kIdentityCount).
struct PatternStation {
  int id = 0;
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;
  bool operator==(const PatternStation&) const = default;
};

enum class Turn { left, right, straight };
const char* turn_name(Turn turn);

struct Course {
  std::string name;
  std::vector<TapePolyline> tapes;
  double ceiling_height_m = 2.5;  // default ceiling height above the floor
  std::vector<HeightZone> zones;
  std::vector<PatternStation> patterns;
  nav::Pose2 start;
  // The turn taken at each junction with a choice (T-branch or crossing),
  // in the order met; an L-turn offers none and takes no entry.
  std::vector<Turn> route;

  double ceiling_height_at(double x_m, double y_m) const;
  // The zone whose height holds at (x, y): its index in `zones`, -1 for the
  // default ceiling.
  int zone_at(double x_m, double y_m) const;
  double tape_length_m() const;                // centre-line length of every tape, gaps included
  bool operator==(const Course& other) const;  // every field exactly
};

// A problem in a course or its file. The message names the file (where
// there is one), the key path (e.g. "tapes[2].gaps[0]") and what is wrong.
class CourseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws CourseError on the first violation of the rules in
// docs/navigation.md (points, widths, gaps, heights, pattern ids, zones).
void validate(const Course& course, const std::string& source = "course");

// Reads YAML or JSON (JSON is read as YAML: one parser, one format).
Course load_course(const std::string& path);
Course parse_course(const std::string& text, const std::string& source = "course");
// Writes YAML, or JSON when the path ends in ".json"; every double as the
// shortest text that reads back equal, so load_course(path) == course. Validates first;
// written to "<path>.tmp" and renamed.
void save_course(const Course& course, const std::string& path);
std::string course_to_yaml(const Course& course);
std::string course_to_json(const Course& course);

// Junctions derived from the geometry (gaps do not matter: a junction
// stays one where the tape is cut):
//   tee      - a tape's end point on another tape's interior (within half
//              the wider tape's width of its centre line);
//   crossing - two tapes' segments crossing in both interiors;
//   l_turn   - an interior vertex of one tape turning by 60..120 deg.
// headings_rad: the directions (CCW from +X, in [-pi, pi)) of the tape
// centre lines that leave the junction, sorted ascending.
struct Junction {
  enum class Kind { tee, crossing, l_turn } kind;
  Point2 position;
  std::vector<double> headings_rad;
  std::vector<int> tapes;  // indices of the tapes that meet there
};
std::vector<Junction> junctions(const Course& course);

// The ceiling as the renderer sees it: every tape piece between gaps as
// straight strips (one per polyline segment, lengthened at a vertex by the
// miter half width * tan(turn / 2), at most the width, so corners are
// closed), split where they cross a zone border, each with the ceiling
// height at its midpoint (golden::TapeSegment::ceiling_height_m).
// reference_y_m = 0: truth_for has no meaning for a course.
golden::CeilingScene ceiling_scene(const Course& course);

// The built-in default course (docs/navigation.md): a 40 m x 20 m loop with
// a cross branch, 142 m of tape, gaps of 0.5..1 m, two T-branches on the
// route, L-turns, one pattern station and a 2.5 -> 2.8 m ceiling step.
Course default_course();

// A random course of the default course's kinds, total tape length about
// `length_m` (>= 60), from `seed`: a rotated and shifted loop of random
// aspect with a cross branch at a random place, random gaps (0.2..1 m, away
// from junctions), one zone of random height step, one pattern station, the
// loop's route. Valid by construction.
Course random_course(uint64_t seed, double length_m);

}  // namespace ceilnav::sim
