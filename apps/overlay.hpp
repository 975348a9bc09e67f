// A picture of what the device and the host saw: runs, their centres, the
// fitted centre line and the vanishing point.
#pragma once

#include <opencv2/core.hpp>

#include "host/navigator.hpp"

namespace ceilnav::app {

// BGR image: the grey frame, runs in green (dropped-from-fit in red), run
// centres as dots, the fitted centre line (through the lens distortion) in
// yellow, the horizon row in blue, the vanishing point as a cross, or as an
// arrow at the border when it lies outside the frame. A text line says the pose.
cv::Mat draw_overlay(const cv::Mat& grey, const host::FrameOutcome& outcome,
                     const host::CameraModel& camera);

}  // namespace ceilnav::app
