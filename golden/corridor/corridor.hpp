// Seed 002's corridor as a cube: ceiling, two walls, floor and end walls,
// with the straight lines a ceiling-line navigator uses (lamp rows, ceiling
// panel seams, the wall-ceiling junctions, cornice and skirting), doors on
// the walls and a simple smooth illumination; a camera with pan, tilt and
// swing; and the exact geometric truth of a frame (the image lines of every
// line along the corridor axis and the vanishing points of the axis, cross
// and vertical directions). docs/renderer.md, "Corridor scenes".
//
// World frame (BRIEF §5): X along the corridor axis, Y left, Z up; floor
// z = 0, ceiling z = ceiling_height_m, walls y = +-width_m / 2.
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "golden/renderer.hpp"

namespace ceilnav::golden::corridor {

// Rows of rectangular lamps on the ceiling: one row per entry of rows_y_m
// (the row's centre line), lamps length_m along X by width_m along Y, centres
// at first_x_m + k spacing_m up to the far end. Emissive: their radiance is
// `radiance` whatever the lighting.
struct Lamps {
  std::vector<double> rows_y_m;
  double length_m = 1.2, width_m = 0.3;
  double spacing_m = 3.0, first_x_m = 0.0;
  double radiance = 2.4;
  bool operator==(const Lamps&) const = default;
};

// Ceiling panel seams: thin strips width_m wide of albedo `albedo`. Along the
// axis at y = along_origin_m + k along_pitch_m, across it at x =
// across_origin_m + k across_pitch_m, over the whole ceiling; a pitch of 0
// means no seams in that direction.
struct Seams {
  double along_pitch_m = 0.0, along_origin_m = 0.0;
  double across_pitch_m = 0.0, across_origin_m = 0.0;
  double width_m = 0.01;
  double albedo = 0.35;
  bool operator==(const Seams&) const = default;
};

// A band along both walls: the cornice from the ceiling down by height_m,
// the skirting from the floor up by height_m; height 0 = none.
struct Band {
  double height_m = 0.0;
  double albedo = 0.5;
  bool operator==(const Band&) const = default;
};

enum class Wall { left, right };  // y = +width/2, y = -width/2

// A door on a side wall: the opening x in [x_m, x_m + width_m], z in [0,
// height_m], of albedo `albedo`, in a frame frame_width_m wide (around the
// sides and the top) of albedo frame_albedo.
struct Door {
  Wall wall = Wall::left;
  double x_m = 0.0, width_m = 0.9, height_m = 2.05;
  double frame_width_m = 0.06;
  double albedo = 0.25, frame_albedo = 0.85;
  bool operator==(const Door&) const = default;
};

// Smooth illumination: radiance = albedo x light. The ceiling is lit
// indirectly (ceiling_light), the walls by the lamps above them, brighter
// towards the ceiling (linear in z from wall_light_floor at z = 0 to
// wall_light_ceiling at the ceiling), the floor directly (floor_light), the
// end walls like the side walls. An open far end shows open_radiance.
struct Lighting {
  double ceiling_light = 0.55;
  double wall_light_floor = 0.55, wall_light_ceiling = 1.0;
  double floor_light = 1.0;
  double open_radiance = 0.02;
  bool operator==(const Lighting&) const = default;
};

struct Corridor {
  std::string name;
  double width_m = 2.4;
  double ceiling_height_m = 2.8;
  double x_start_m = -5.0,
         length_m = 60.0;     // near end wall at x_start, far end at x_start + length
  bool far_end_open = false;  // true: no far wall (open_radiance beyond)
  double ceiling_albedo = 0.85, wall_albedo = 0.6, floor_albedo = 0.3, end_wall_albedo = 0.5;
  Lamps lamps;
  Seams seams;
  Band cornice, skirting;
  std::vector<Door> doors;
  Lighting lighting;
  double x_end_m() const { return x_start_m + length_m; }
  bool operator==(const Corridor&) const = default;
};

// The camera: centre (x_m, y_m, height_m); pan = yaw about +Z (counter-
// clockwise from +X, as BRIEF §5's yaw), tilt = pitch of the optical axis up
// from the horizontal, swing = roll about the optical axis (positive turns
// the camera's x axis toward its y axis: the image content turns counter-
// clockwise). Rotation: golden::world_to_camera_rotation(pan, tilt, swing).
struct Pose {
  double x_m = 0.0, y_m = 0.0, height_m = 1.0;
  double pan_rad = 0.0, tilt_rad = 0.0, swing_rad = 0.0;
  bool operator==(const Pose&) const = default;
};

// Thrown for a corridor or pose that breaks the rules of validate (and by
// the file reader, corridor_file.hpp). The message names the source and key.
class CorridorError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Positive width, height, length; albedos and lights >= 0; lamps inside the
// ceiling, not overlapping along the row (length < spacing); seams narrower
// than their pitch; bands below the ceiling height together; doors on the
// wall and below the cornice. Throws CorridorError naming `source` and the key.
void validate(const Corridor& corridor, const std::string& source = "corridor");
// Finite, strictly inside the corridor (not on a face).
void validate(const Pose& pose, const Corridor& corridor, const std::string& source = "pose");

// The camera view (centre, world -> camera rotation) of a pose.
CameraView view_of(const Pose& pose);

// The built-in corridor (docs/renderer.md, "Corridor scenes"): 2.4 m wide,
// 2.8 m high, 60 m long with a far wall; two lamp rows at y = +-0.6 m
// (1.2 x 0.3 m every 3 m), panel seams every 0.6 m both ways, a 6 cm
// cornice, a 10 cm skirting and four doors. examples/corridor/default.yaml.
Corridor default_corridor();
// A camera on a vehicle in it: 1.0 m high, 0.3 m left of the centre line,
// pan 4 deg, tilt 35 deg, swing 0.
Pose default_pose();

// A straight scene line along the corridor axis: point + s (1, 0, 0) for s
// in [x0_m, x1_m] (where the feature exists).
enum class LineKind {
  lamp_edge,       // a long side of a lamp row (the line through all its lamps' sides)
  seam,            // the centre line of a ceiling seam along the axis
  junction,        // wall-ceiling junction
  cornice_edge,    // lower edge of the cornice on a wall
  skirting_edge,   // upper edge of the skirting on a wall
  floor_junction,  // wall-floor junction
  door_top,        // a door's top edge, or its frame's, on a side wall (over the door only)
};
const char* line_kind_name(LineKind kind);

struct AxisLine {
  LineKind kind;
  std::string name;  // e.g. "lamp_row[1].left", "junction.right"
  Eigen::Vector3d point;
  double x0_m, x1_m;
  bool operator==(const AxisLine&) const = default;
};
// Every line along the axis the corridor has, in a fixed order (lamp rows,
// seams, junctions, cornice, skirting, floor junctions, door tops). The
// skirting's edge is cut where a door's leaf or frame covers it; its extent
// is still the corridor's.
std::vector<AxisLine> axis_lines(const Corridor& corridor);

// The image of a line on the undistorted image, in pixels, in the normal
// form of cv::HoughLines: u cos(theta) + v sin(theta) = rho, theta in [0,
// pi), pixel (0, 0) at the origin. visible: some point of the line's
// extent in front of the camera projects, with the lens distortion, into
// the frame ([-1/2, W - 1/2) x [-1/2, H - 1/2)); from_px, to_px: the ends of
// that visible part on the undistorted image (0, 0 when not visible).
struct ImageLine {
  AxisLine line;
  double theta_rad = 0.0, rho_px = 0.0;
  bool defined = false;  // false when the camera centre lies on the line
  bool visible = false;
  Eigen::Vector2d from_px{0.0, 0.0}, to_px{0.0, 0.0};
};

// A vanishing point on the undistorted image: homogeneous K R d (unit
// norm), and (u, v) in pixels when finite (|z| > 1e-12 of the norm).
struct VanishingPoint {
  Eigen::Vector3d homogeneous;
  bool finite = false;
  double u_px = 0.0, v_px = 0.0;
};

struct FrameTruth {
  Pose pose;
  Eigen::Matrix3d world_to_camera;
  std::vector<ImageLine> lines;  // axis_lines(corridor), in order
  VanishingPoint axis;           // direction +X: every line of `lines`
  VanishingPoint cross;          // +Y: lamp ends, seams across, end-wall edges
  VanishingPoint vertical;       // +Z: door jambs, corridor corners
};

// The truth of a camera at `pose` (intrinsics and image size from `camera`;
// its pitch and heights are not used).
FrameTruth truth_for(const host::CameraConfig& camera, const Corridor& corridor, const Pose& pose);

// The normal form (theta in [0, pi), rho) of a homogeneous image line
// (a, b, c): a u + b v + c = 0 (a, b not both 0).
void normal_form(const Eigen::Vector3d& line, double& theta_rad, double& rho_px);

}  // namespace ceilnav::golden::corridor
