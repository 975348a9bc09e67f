// The types the corridor host maths (seed 002) pass between their steps:
// image lines in the normal form of the Hough transform, vanishing points,
// and the camera's fixed mounting on the vehicle. docs/corridor.md.
//
// Image coordinates: pixels of the undistorted (ideal pinhole) image, pixel
// (0, 0) at the origin, u right, v down, the same as
// golden::corridor::ImageLine and cv::HoughLines. A line is
//   u cos(theta) + v sin(theta) = rho,  theta in [0, pi).
#pragma once

#include <Eigen/Core>

namespace ceilnav::host::corridor {

struct ImageLine {
  double theta_rad = 0.0;
  double rho_px = 0.0;
  double strength = 0.0;  // the accumulator's vote weight behind it (0: unknown)
  // Homogeneous (a, b, c) with a u + b v + c = 0: (cos, sin, -rho).
  Eigen::Vector3d homogeneous() const;
};

// The camera's fixed angles: tilt and swing to the floor (constant while
// the vehicle drives on a flat floor, seed section 3.3) and its pan on the
// vehicle phi_CA (eq. 16), all from calibration. The one source of the
// tilt and swing for the pan (vanishing.hpp) and the model (corridor_model.hpp).
struct CameraMount {
  double tilt_rad = 0.0;
  double swing_rad = 0.0;
  double pan_on_vehicle_rad = 0.0;
};

// A line from homogeneous (a, b, c) (a, b not both 0), theta in [0, pi).
ImageLine line_from_homogeneous(const Eigen::Vector3d& abc, double strength = 0.0);

// A point of the undistorted image; finite = false for a point at infinity
// (then `direction` holds the image direction it lies in).
struct ImagePoint {
  bool finite = false;
  Eigen::Vector2d px{0.0, 0.0};
  Eigen::Vector2d direction{0.0, 0.0};
};

// The intersection of two lines (finite = false when parallel within 1e-12).
ImagePoint intersect(const ImageLine& a, const ImageLine& b);

}  // namespace ceilnav::host::corridor
