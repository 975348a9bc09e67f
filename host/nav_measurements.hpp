// From the host's per-frame results to the navigation layer's measurement
// contract (nav/measurement.hpp, BRIEF section 7): the quantity, its
// covariance, its times and its status. The covariance is the fit's own
// (TapePose::covariance, the noise's part) inflated for the correlation of
// neighbouring rows, plus floors for what the fit cannot see: the renderer-
// and lens-model bias of the accuracy study and the ceiling height's error,
// which scales the offset (docs/navigation.md, "Measurement contract").
#pragma once

#include "host/tape_pose.hpp"
#include "nav/measurement.hpp"

namespace ceilnav::host {

struct TapeNoiseModel {
  // TapePose::covariance takes the residuals as independent; the scatter over
  // noise reaches 2.4 times its variance (host_tape_pose_covariance_test).
  double statistical_inflation = 2.5;
  // Systematic floors (sigma): five times the accuracy study's RMS (yaw
  // 0.002 deg, offset 0.1 mm; docs/results.md), for blur, lens model and
  // the mount's calibration residual.
  double yaw_floor_rad = 0.01 * 3.14159265358979323846 / 180.0;
  double offset_floor_m = 0.5e-3;
  // The offset is proportional to the ceiling height above the camera
  // (pose_from_centre_line): its relative error adds |offset| x this.
  double ceiling_relative_sigma = 0.002;
};

nav::MeasurementStatus measurement_status(Status s);

// The tape measurement of a frame's pose (centre line or zenith). Its status
// is not ok unless the pose is, and then it carries no quantity.
nav::TapeMeasurement tape_measurement(const TapePose& pose, const nav::MeasurementTime& time,
                                      const TapeNoiseModel& noise = {});

}  // namespace ceilnav::host
