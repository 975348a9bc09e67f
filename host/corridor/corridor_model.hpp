// Seed 002 section 4.1 (learning stage, steps 9-11): the corridor model, the
// lines along the corridor axis seen from a driven (learnt) path, and the
// geometry that relates an image line to the lateral position of the camera.
// docs/corridor.md, "Model learning"; file format: docs/navigation_io.md,
// "Corridor model files".
//
// Frames (BRIEF section 5, golden/corridor/corridor.hpp): world X along the
// corridor axis, Y left, Z up; camera pan about +Z (CCW from +X), tilt of the
// optical axis up from the horizontal, swing about the optical axis; OpenCV
// camera axes (x right, y down, z forward). The seed's global frame has its z
// along the corridor, x across it and y vertical; its Delta-x is our Delta-y.
//
// The plane of an axis line. A line along +X at lateral offset dy (its Y
// minus the camera's) and height h (its Z minus the camera's) lies in the
// plane through the camera centre with world normal
//   n_w = (P0 - C) x e_x = (0, dy, h) x (1, 0, 0) = (0, h, -dy).
// Its image is l ~ K^-T R n_w (R = world -> camera, K the camera matrix), so
// the image line gives back n_w = R^T K^T l up to scale, and the line's
// "inclination"
//   q = dy / h = -n_w.z / n_w.y                                        (M1)
// is a pure world quantity: it does not depend on the camera's pan, tilt,
// swing or K once they are undone. A vehicle shift Delta-y to the left
// changes dy by -Delta-y and leaves h, so Delta-y = h (q_model - q_now). The
// seed's eq. 21-25 compute the same thing through one image point and its
// depth z'_1, which it "treats as a scalar": the depth hides h (lateral_shift.hpp).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "host/corridor/corridor_types.hpp"

namespace ceilnav::host::corridor {

// The camera's fixed mounting and intrinsics as the model needs them: the
// undistorted pinhole K and the tilt and swing (constant while driving on a
// flat floor, seed section 3.3); the pan varies and is passed separately.
struct ModelCamera {
  int image_width = 640, image_height = 480;
  double fx = 500.0, fy = 500.0, cx = 319.5, cy = 239.5;
  double tilt_rad = 0.0, swing_rad = 0.0;
  Eigen::Matrix3d k() const;
  bool operator==(const ModelCamera&) const = default;
};

// K and the image size from the camera, tilt and swing from the mount (the
// same angles the pan is estimated with; CameraConfig's camera_pitch_deg is
// the tape system's and is not used).
ModelCamera model_camera(const CameraConfig& camera, const CameraMount& mount);

// World -> camera rotation for pan, tilt, swing: the same matrix as
// golden::world_to_camera_rotation(pan, tilt, swing) (rows: camera x right,
// y down, z forward in world coordinates).
Eigen::Matrix3d world_to_camera(double pan_rad, double tilt_rad, double swing_rad);

// The world normal n_w = R^T K^T l of an image line's plane (unit norm, the
// sign of l's normal form), for a camera at pan `pan_rad`.
Eigen::Vector3d plane_normal(const ImageLine& line, const ModelCamera& camera, double pan_rad);

// The inclination q = dy / h of an axis line (M1) from its image line. The
// pan only matters at second order: n_w of a wrong pan is the true one turned
// about Z by the pan error, which keeps n_w.z and |n_w.xy|; the horizontal
// part is therefore taken as sign(n_w.y) |n_w.xy|, with the pan resolving
// the sign only. nullopt when the plane is (nearly) horizontal (|n_w.xy| <
// 1e-9 |n_w|: a line at the camera's height, or not along the axis).
std::optional<double> inclination(const ImageLine& line, const ModelCamera& camera, double pan_rad);

// d q / d theta and d q / d rho of inclination() (chain rule through M1).
Eigen::Vector2d inclination_gradient(const ImageLine& line, const ModelCamera& camera,
                                     double pan_rad);

// The image line of an axis line of inclination q (dy = q h, h > 0) for a
// camera at pan `pan_rad`: l ~ K^-T R (0, 1, -q).
ImageLine line_of_inclination(double q, const ModelCamera& camera, double pan_rad,
                              double strength = 0.0);

// One line of the model.
struct ModelLine {
  ImageLine line;      // at the model's pan (seed step 11: median theta, averaged rho)
  double inclination;  // q = dy / h of `line` (M1), the value lateral_shift compares
  double height_m;     // h: the line's height above the camera (> 0), the scale of Delta-y
  int support;         // how many learning images saw it
};

struct CorridorModel {
  static constexpr int kVersion = 1;
  ModelCamera camera;
  double pan_rad = 0.0;               // the model's pan: the median of the learning images' pans
  Eigen::Vector3d axis_vp{0, 0, 1};   // homogeneous vanishing point of +X (unit norm)
  Eigen::Vector3d cross_vp{0, 0, 1};  // homogeneous vanishing point of +Y (unit norm)
  int images = 0;                     // learning images
  std::vector<ModelLine> lines;       // left to right (decreasing inclination)
};

// One image of the learning drive: its lines (as found in it, at its own
// pan) and its pan (from the vanishing line, seed eq. 14-16).
struct LearningImage {
  std::vector<ImageLine> lines;
  double pan_rad = 0.0;
};

struct LearnOptions {
  // h of every model line: the ceiling above the camera (all lines the
  // model keeps are taken to lie on the ceiling).
  double line_height_m = 1.8;
  // A line joins the group whose running median inclination is nearest when
  // the inclinations' angles atan(q) differ by at most this.
  double gate_rad = 0.02;
  // Seed step 11's "same theta": thetas within this of the median theta
  // (default: well below a Hough bin) share their rho average.
  double same_theta_rad = 1e-4;
  // Groups seen in fewer than this fraction of the images are dropped.
  double min_support_fraction = 0.5;
  // Keep at most this many groups (the best supported); 0 = all. The seed
  // keeps i = 2 (step 8).
  int max_lines = 0;
};

// Steps 9-11 with the deviations of docs/corridor.md ("Model learning"):
// each image's lines are moved to the model pan (their planes are pan-free,
// M1), grouped by nearest running median inclination (not by rank), and the
// model line of a group is its median-theta line with the rho of its
// equal-theta lines averaged. Throws std::invalid_argument for no images, a
// non-positive height or a bad option.
CorridorModel learn_model(const std::vector<LearningImage>& images, const ModelCamera& camera,
                          const LearnOptions& options = {});

// Model files (JSON, docs/navigation_io.md "Corridor model files").
class CorridorModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
std::string model_to_json(const CorridorModel& model);
// Throws CorridorModelError naming `source` and the offending key.
CorridorModel model_from_json(const std::string& text, const std::string& source = "model");
void write_model_file(const std::string& path, const CorridorModel& model);
CorridorModel read_model_file(const std::string& path);

}  // namespace ceilnav::host::corridor
