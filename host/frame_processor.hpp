// The device as the host's per-frame loops use it: program a PipelineConfig,
// stream one grey frame through it, collect the result registers and the run
// records. The tape Navigator and the pattern commands are written against
// this interface; drivers::Device implements it on every backend (the
// pipeline's frame-at-a-time path, the C++ cycle model, the Verilated RTL),
// and a program on real hardware would implement it over its own bus.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"

namespace ceilnav::host {

class FrameProcessor {
 public:
  virtual ~FrameProcessor() = default;

  // Processes one frame with `cfg` (its width and height must be the
  // frame's: std::invalid_argument otherwise). `runs` receives the frame's
  // runs in stream order; `cycles` the device clock cycles spent (0 where the
  // backend has no clock).
  virtual stream::FrameResults process(const cv::Mat& grey, const stream::PipelineConfig& cfg,
                                       std::vector<stream::RunRecord>& runs, uint64_t& cycles) = 0;
};

}  // namespace ceilnav::host
