// The disc's image ellipse in normalised (undistorted) coordinates from its
// class moments (the seed's eq. 17-19, 29-32, through the camera model;
// docs/pattern.md).
#pragma once

#include <Eigen/Core>
#include <optional>

#include "host/camera_model.hpp"
#include "host/pattern/class_moments.hpp"

namespace ceilnav::host::pattern {

// An ellipse in normalised (undistorted) coordinates: centre, semi-axes
// a <= b, and psi = angle of the minor axis from image "up" (-y) toward +x,
// in [0, pi) (seed Fig. 2, eq. 19).
struct Ellipse {
  double cx = 0, cy = 0, a = 0, b = 0, psi = 0;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();  // second central moments / m00
  // Uncertainty of (cx, cy, S11, S12, S22), S = 4 cov, when the estimate
  // comes with one (fit_disc_coverage); zero = not known.
  Eigen::Matrix<double, 5, 5> param_cov = Eigen::Matrix<double, 5, 5>::Zero();
};
// The ellipse of a uniform region with centre c and covariance cov (both in
// normalised coordinates); empty unless cov is positive definite.
std::optional<Ellipse> ellipse_from_covariance(const Eigen::Vector2d& c,
                                               const Eigen::Matrix2d& cov);
// Eq. 29-32 (with Sheppard's 1/12 px^2) then eq. 17-19 on the moments mapped
// to normalised coordinates: the centroid through the camera model, the
// covariance through the local Jacobian of the undistortion, refined with a
// distortion present until the lens image of the ellipse has the measured
// moments (docs/pattern.md).
std::optional<Ellipse> ellipse_from_moments(const ClassMoments& m, const CameraModel& camera);

}  // namespace ceilnav::host::pattern
