// Reading and writing the scene/camera configuration (BRIEF §5) as OpenCV
// FileStorage YAML: the output of cv::calibrateCamera plus four keys.
#pragma once

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

// Checks every field of `cfg` (the ranges listed in docs/host_maths.md);
// throws ConfigError naming `source` and the key on the first violation.
void validate_camera_config(const CameraConfig& cfg, const std::string& source);

// Reads keys image_width, image_height (int, 1..2048), camera_matrix (3x3
// opencv-matrix, zero skew, fx, fy > 0, principal point inside the image),
// distortion_coefficients (1x5, 5x1, 1x4 or 4x1; k3 = 0 for four), camera_pitch_deg
// (0 < pitch <= 90), camera_height_m, ceiling_height_m (> camera height),
// tape_width_m (> 0). Unknown keys are ignored.
CameraConfig load_camera_config(const std::string& path);

// Writes the same keys (camera_matrix 3x3 and distortion_coefficients 1x5 as
// CV_64F opencv-matrix) so that load_camera_config(path) returns `cfg` exactly.
// Validates first; throws ConfigError if the file cannot be written.
void save_camera_config(const CameraConfig& cfg, const std::string& path);

}  // namespace ceilnav::host
