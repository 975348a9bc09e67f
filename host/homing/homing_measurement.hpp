// From the tracker's result (the site point's pixel and the content's turn
// gamma) to the navigation layer's HomingMeasurement (nav/measurement.hpp):
// the camera looks up with the image's v axis along the robot's heading and
// u to its right (golden::ceiling::view_of), so the site point at
// undistorted normalised (x, y) lies D (x right + y forward) from the
// current camera, D the ceiling's distance above it; that point was above
// the site camera (the recorded frame's principal point), so the site
// camera is (forward, left) = (D y, -D x) away. The robot turned by +dpsi
// sees the ceiling turned by -dpsi: the turn to the site's heading is
// +gamma. docs/homing.md, "Servoing".
#pragma once

#include "host/camera_model.hpp"
#include "host/homing/tracker.hpp"
#include "nav/measurement.hpp"

namespace ceilnav::host::homing {

struct HomingNoiseModel {
  // The tracker's scatter on renders (docs/homing.md, "Tracking"): 0.03 px
  // and 0.08 deg at worst; sigmas with a margin for the ceiling's relief
  // and lens-model residuals.
  double position_sigma_px = 0.1;
  double turn_sigma_rad = 0.002;
  // The ceiling distance's relative error scales the position.
  double ceiling_relative_sigma = 0.01;
};

// status: ok -> ok, ambiguous -> inconsistent, not_found -> not_found; the
// quantities are set for ok only. ceiling_distance_m: the ceiling above the
// camera (> 0, else std::invalid_argument).
nav::HomingMeasurement homing_measurement(const TrackResult& track, const CameraModel& camera,
                                          double ceiling_distance_m, int site = -1,
                                          const HomingNoiseModel& noise = {});

}  // namespace ceilnav::host::homing
