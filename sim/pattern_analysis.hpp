// One frame of seed 003's standard pattern through the device and the host
// maths: shared by `ceilnav pattern`, `ceilnav pattern-accuracy` and the
// closed-loop drive's pattern stations (sim::Drive). In sim/, the lowest
// library that links golden::pattern (the device programming), the drivers
// and host::pattern together.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "drivers/device.hpp"
#include "golden/pattern/pattern.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/pattern/pattern_pose.hpp"
#include "host/pattern/photometry.hpp"

namespace ceilnav::sim {

// What the device and the host make of one frame.
struct PatternFrameAnalysis : host::pattern::PatternAnalysis {
  host::pattern::FrameMoments moments{};
  std::vector<stream::RunRecord> runs;
  // The frame's photometric calibration and the levels the device was
  // programmed with for the analysis (the calibrated ones when it is ok).
  host::pattern::PhotometricCalibration photometry;
  golden::pattern::Radiometry radiometry;
  int passes = 0;  // frames streamed through the device for the analysis
};

// The frame streams through the device (class LUT, run mask of bars and
// disc, whole-frame class window); the host works on its class moments and
// run records (host::pattern::analyse_pattern). With self_calibrate (the
// default) the first pass, programmed from `radiometry` (the nominal camera),
// gives the histogram the host calibrates the levels from
// (host::pattern::calibrate_photometry); the frame then streams again with
// the LUT and the coverage model of the calibrated levels. A frame whose
// calibration fails while it shows a disc (to the first pass's class
// moments or to the calibration) gets status `uncalibrated` on every
// pose and on an ok code (never a pose with ok); one without a disc keeps the
// first pass's analysis (no pattern, or the bars alone).
PatternFrameAnalysis analyse_pattern_frame(drivers::Device& device, const cv::Mat& grey,
                                           const golden::pattern::Radiometry& radiometry,
                                           const host::CameraModel& model,
                                           const host::pattern::PoseOptions& pose_options,
                                           bool self_calibrate = true);

// The photometry options of a nominal radiometry and the camera's noise.
host::pattern::PhotometryOptions photometry_options_for(const golden::pattern::Radiometry& r,
                                                        double noise_grey);
// The radiometry of calibrated levels: the scene's albedos, black level and
// scale from the calibration.
golden::pattern::Radiometry calibrated_radiometry(const golden::pattern::Radiometry& nominal,
                                                  const host::pattern::PhotometricCalibration& c);

// The pose options of a pattern's geometry (radius, thickness, rim).
host::pattern::PoseOptions pose_options_for(const golden::pattern::PatternGeometry& g);

}  // namespace ceilnav::sim
