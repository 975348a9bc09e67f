// One frame of seed 003's standard pattern through the device and the host
// maths: shared by `ceilnav pattern` and `ceilnav pattern-accuracy`.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "apps/commands.hpp"
#include "drivers/device.hpp"
#include "golden/pattern/pattern.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/pattern/pattern_pose.hpp"

namespace ceilnav::app {

// What the device and the host make of one frame.
struct PatternFrameAnalysis : host::pattern::PatternAnalysis {
  host::pattern::FrameMoments moments{};
  std::vector<stream::RunRecord> runs;
};

// The frame streams through the device (class LUT, run mask of bars and
// disc, whole-frame class window); the host works on its class moments and
// run records (host::pattern::analyse_pattern).
PatternFrameAnalysis analyse_pattern_frame(drivers::Device& device, const cv::Mat& grey,
                                           const golden::pattern::Radiometry& radiometry,
                                           const host::CameraModel& model,
                                           const host::pattern::PoseOptions& pose_options);

// The pose options of a pattern's geometry (radius, thickness, rim).
host::pattern::PoseOptions pose_options_for(const golden::pattern::PatternGeometry& g);

}  // namespace ceilnav::app
