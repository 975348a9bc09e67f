#include "host/corridor/corridor_types.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace ceilnav::host::corridor {

Eigen::Vector3d ImageLine::homogeneous() const {
  return {std::cos(theta_rad), std::sin(theta_rad), -rho_px};
}

ImageLine line_from_homogeneous(const Eigen::Vector3d& abc, double strength) {
  const double n = std::hypot(abc.x(), abc.y());
  Eigen::Vector3d l = abc / n;
  double theta = std::atan2(l.y(), l.x());
  // theta in [0, pi): flip the line's sign to bring its normal there.
  if (theta < 0.0 || theta >= std::numbers::pi) {
    l = -l;
    theta = std::atan2(l.y(), l.x());
    if (theta >= std::numbers::pi) theta -= std::numbers::pi;
  }
  ImageLine out;
  out.theta_rad = theta;
  out.rho_px = -l.z();
  out.strength = strength;
  return out;
}

ImagePoint intersect(const ImageLine& a, const ImageLine& b) {
  const Eigen::Vector3d p = a.homogeneous().cross(b.homogeneous());
  ImagePoint out;
  if (std::abs(p.z()) <= 1e-12 * p.head<2>().norm()) {
    out.finite = false;
    out.direction = p.head<2>().normalized();
    return out;
  }
  out.finite = true;
  out.px = p.head<2>() / p.z();
  return out;
}

}  // namespace ceilnav::host::corridor
