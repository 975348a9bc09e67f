#include "host/homing/homing_measurement.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace ceilnav::host::homing {

nav::HomingMeasurement homing_measurement(const TrackResult& track, const CameraModel& camera,
                                          double ceiling_distance_m, int site,
                                          const HomingNoiseModel& noise) {
  if (!(ceiling_distance_m > 0.0) || !std::isfinite(ceiling_distance_m)) {
    throw std::invalid_argument("homing measurement: the ceiling distance must be > 0");
  }
  nav::HomingMeasurement m;
  m.site = site;
  switch (track.status) {
    case TrackStatus::ok:
      m.status = nav::MeasurementStatus::ok;
      break;
    case TrackStatus::ambiguous:
      m.status = nav::MeasurementStatus::inconsistent;
      return m;
    case TrackStatus::not_found:
      m.status = nav::MeasurementStatus::not_found;
      return m;
  }
  const Eigen::Vector2d xy = camera.normalise(track.x_px, track.y_px);
  m.forward_m = ceiling_distance_m * xy.y();
  m.left_m = -ceiling_distance_m * xy.x();
  m.turn_rad = std::remainder(track.gamma_deg * std::numbers::pi / 180.0, 2.0 * std::numbers::pi);
  const double pos_sigma = ceiling_distance_m * noise.position_sigma_px / camera.fx();
  const double rel = noise.ceiling_relative_sigma;
  m.covariance.setZero();
  m.covariance(0, 0) = pos_sigma * pos_sigma + rel * rel * m.forward_m * m.forward_m;
  m.covariance(1, 1) = pos_sigma * pos_sigma + rel * rel * m.left_m * m.left_m;
  m.covariance(0, 1) = m.covariance(1, 0) = rel * rel * m.forward_m * m.left_m;
  m.covariance(2, 2) = noise.turn_sigma_rad * noise.turn_sigma_rad;
  return m;
}

}  // namespace ceilnav::host::homing
