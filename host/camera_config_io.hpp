// Reading and writing the scene/camera configuration (BRIEF §5) as OpenCV
// FileStorage YAML: the output of cv::calibrateCamera plus four keys.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "common/camera_config.hpp"

namespace ceilnav::host {

// Thrown for an unreadable, malformed, incomplete or out-of-range configuration.
// The message names the file and, where there is one, the offending key.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Checks every field of `cfg` (the ranges listed in docs/host_maths.md),
// including that the distortion is invertible over the image
// (distortion_fold); throws ConfigError naming `source` and the key on the
// first violation.
void validate_camera_config(const CameraConfig& cfg, const std::string& source);

// Why the distortion of `cfg` has no unique inverse over the image, or nothing
// when it has one (docs/host_maths.md §7): the radial map
// r_d = r (1 + k1 r^2 + k2 r^4 + k3 r^6) must rise (d r_d / d r > 0) from the
// centre until it reaches the distorted radius of the farthest image corner,
// and the Jacobian determinant of the whole map (tangential terms included)
// must be > 0 on the disc that reaches it. Needs a valid image size and
// camera_matrix (fx, fy > 0).
std::optional<std::string> distortion_fold(const CameraConfig& cfg);

// Reads keys image_width, image_height (int, 1..2048), camera_matrix (3x3
// opencv-matrix, zero skew, fx, fy > 0, principal point inside the image),
// distortion_coefficients (1x5, 5x1, 1x4 or 4x1; k3 = 0 for four), camera_pitch_deg
// (0 < pitch <= 90), camera_height_m, ceiling_height_m (> camera height),
// tape_width_m (> 0). Unknown keys are ignored.
//
// With ConfigKeys::camera_only (the pattern command, which uses only the
// lens) the four scene keys camera_pitch_deg, camera_height_m,
// ceiling_height_m and tape_width_m may be absent; an absent one keeps its
// CameraConfig default, a present one is read and checked as usual.
enum class ConfigKeys { scene, camera_only };
CameraConfig load_camera_config(const std::string& path, ConfigKeys keys = ConfigKeys::scene);

// Writes the same keys (camera_matrix 3x3 and distortion_coefficients 1x5 as
// CV_64F opencv-matrix) so that load_camera_config(path) returns `cfg` exactly.
// Validates first; throws ConfigError if the file cannot be written.
void save_camera_config(const CameraConfig& cfg, const std::string& path);

}  // namespace ceilnav::host
