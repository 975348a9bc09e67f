// Test support: the run records the device gives for a rendered pattern frame
// with golden::pattern::device_config (stream::Pipeline's frame-at-a-time
// path), bar runs and disc runs together.
#pragma once

#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "golden/pattern/pattern.hpp"
#include "stream/pipeline.hpp"

namespace ceilnav::test_support {

inline std::vector<stream::RunRecord> device_runs(const cv::Mat& grey,
                                                  const golden::pattern::Radiometry& r) {
  if (grey.type() != CV_8UC1) throw std::invalid_argument("device_runs: needs an 8-bit grey frame");
  stream::Pipeline pipeline;
  pipeline.set_config(golden::pattern::device_config(grey.cols, grey.rows, r));
  std::vector<stream::RunRecord> runs;
  pipeline.process_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], &runs);
  return runs;
}

// The error study's camera (640x480, barrel distortion).
inline host::CameraConfig study_camera() {
  host::CameraConfig c;
  c.camera_matrix = {520.0, 0.0, 321.7, 0.0, 518.5, 238.2, 0.0, 0.0, 1.0};
  c.distortion_coefficients = {-0.08, 0.015, 0.0004, -0.0003, 0.0};
  return c;
}

}  // namespace ceilnav::test_support
