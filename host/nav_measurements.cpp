#include "host/nav_measurements.hpp"

#include <cmath>
#include <string_view>

namespace ceilnav::host {

nav::MeasurementStatus measurement_status(Status s) {
  switch (s) {
    case Status::ok:
      return nav::MeasurementStatus::ok;
    case Status::no_tape:
      return nav::MeasurementStatus::not_found;
    case Status::too_few_points:
    case Status::degenerate:
    case Status::bad_config:
      return nav::MeasurementStatus::degenerate;
    case Status::frame_invalid:
      return nav::MeasurementStatus::invalid;
    case Status::inconsistent:
    case Status::jump:
      return nav::MeasurementStatus::inconsistent;
  }
  return nav::MeasurementStatus::invalid;
}

nav::TapeMeasurement tape_measurement(const TapePose& pose, const nav::MeasurementTime& time,
                                      const TapeNoiseModel& noise) {
  nav::TapeMeasurement m;
  m.time = time;
  m.status = measurement_status(pose.status);
  m.zenith = std::string_view(pose.method) == "zenith_moments";
  if (m.status != nav::MeasurementStatus::ok) return m;
  m.yaw_rad = pose.yaw_rad;
  m.offset_m = pose.offset_m;
  const double offset_rel = noise.ceiling_relative_sigma * std::abs(pose.offset_m);
  // The inflation is the centre-line fit's (its residuals are correlated from
  // row to row); the zenith moments' covariance is their quantisation model.
  m.covariance = (m.zenith ? 1.0 : noise.statistical_inflation) * pose.covariance;
  m.covariance(0, 0) += noise.yaw_floor_rad * noise.yaw_floor_rad;
  m.covariance(1, 1) += noise.offset_floor_m * noise.offset_floor_m + offset_rel * offset_rel;
  return m;
}

}  // namespace ceilnav::host
