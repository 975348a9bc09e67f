// The scene/camera configuration of BRIEF §5: the output of cv::calibrateCamera
// plus four keys, stored as OpenCV FileStorage YAML.
//
// Pixel convention (everywhere in ceilnav): pixel (col i, row j) has its centre
// at image coordinates (u, v) = (i, j) and covers [i-0.5, i+0.5] x [j-0.5, j+0.5],
// as in OpenCV. Normalised coordinates: (x, y) = K^-1 (u, v, 1) after undistortion.
#pragma once

#include <array>
#include <string>

namespace ceilnav::host {

struct CameraConfig {
  int image_width = 640;
  int image_height = 480;
  // Row-major 3x3 camera matrix [fx 0 cx; 0 fy cy; 0 0 1].
  std::array<double, 9> camera_matrix{500.0, 0.0, 319.5, 0.0, 500.0, 239.5, 0.0, 0.0, 1.0};
  // OpenCV order k1, k2, p1, p2, k3.
  std::array<double, 5> distortion_coefficients{};
  double camera_pitch_deg = 45.0;  // optical axis above the horizontal; 90 = zenith
  double camera_height_m = 0.5;    // camera centre above the floor
  double ceiling_height_m = 3.0;   // ceiling above the floor
  double tape_width_m = 0.05;

  double fx() const { return camera_matrix[0]; }
  double fy() const { return camera_matrix[4]; }
  double cx() const { return camera_matrix[2]; }
  double cy() const { return camera_matrix[5]; }
  double ceiling_above_camera_m() const { return ceiling_height_m - camera_height_m; }
  bool has_distortion() const {
    for (double k : distortion_coefficients) {
      if (k != 0.0) return true;
    }
    return false;
  }
};

}  // namespace ceilnav::host
