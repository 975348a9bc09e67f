// The device on one of three backends, as the host's FrameProcessor: the
// pipeline's frame-at-a-time path (fast), or the host Driver programming the
// device through its registers on a simulation bus — the C++ cycle model
// (ModelBus) or the Verilated RTL (rtl_bus_factory, drivers/rtl_backend.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "ceilnav/regs.hpp"
#include "common/corridor_results.hpp"
#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "drivers/sim_bus.hpp"
#include "host/driver.hpp"
#include "host/frame_processor.hpp"
#include "stream/pipeline.hpp"

namespace ceilnav::drivers {

enum class Backend { fast, model, rtl };

// Creates the simulation bus of a backend with the given stream timing.
using BusFactory = std::function<std::unique_ptr<SimBus>(const SimBusOptions&)>;

struct DeviceOptions {
  // fast: the pipeline's frame-at-a-time path, no registers (the default:
  // fastest). model / rtl: the Driver programs the device through its
  // registers on a Bus backend — the C++ cycle-level register model
  // (ModelBus) or the Verilated RTL (bus_factory, see rtl_backend.hpp) — while the frame
  // streams in beat by beat with random tvalid gaps, run-stream back-pressure
  // and AXI-Lite stalls (probabilities in [0, 1)). Every backend gives the
  // same results and runs, bit for bit.
  Backend backend = Backend::fast;
  double gap_probability = 0.0;
  double backpressure_probability = 0.0;
  uint64_t seed = 1;
  uint32_t fifo_depth = 1024;
  // The device configuration (the RTL top's Has* parameters, FEATURES): which
  // optional blocks it has (regs::kConfigs: tape, corridor, full, homing).
  regs::Config device_config = regs::kConfigFull;
  // Creates the Bus for Backend::rtl (and, if set, for Backend::model).
  BusFactory bus_factory;
};

class Device : public host::FrameProcessor {
 public:
  // Bus backends: creates the bus and identifies the device (throws
  // std::runtime_error if it is not a ceilnav device; std::invalid_argument
  // for rtl without a bus factory).
  explicit Device(const DeviceOptions& options = {});

  // Processes one frame with `cfg` (its width and height must be the frame's:
  // std::invalid_argument otherwise). `runs` receives the frame's runs in
  // stream order; `cycles` the device clock cycles spent (0 on fast).
  stream::FrameResults process(const cv::Mat& grey, const stream::PipelineConfig& cfg,
                               std::vector<stream::RunRecord>& runs, uint64_t& cycles) override;

  const DeviceOptions& options() const { return options_; }

  // The corridor blocks (edge -> hough) for the following frames: after
  // this, process() also fetches each frame's accumulator (corridor()). The
  // fast backend runs the pipeline model's fast frame path; the bus backends
  // program EDGE_CONTROL / HOUGH_* and read the accumulator through the
  // registers (host::Driver::read_corridor). Throws std::runtime_error on a
  // device without the corridor blocks.
  void set_corridor(const stream::EdgeConfig& edge, const stream::HoughConfig& hough);
  // The last processed frame's corridor readout (valid = false before
  // set_corridor() or while no frame has been published).
  const stream::CorridorReadout& corridor() const { return corridor_; }

  // The orientation block (seed 004's FindOrientation histogram) for the
  // following frames: after this, process() also fetches the histogram it
  // publishes for each frame (orientation()). The fast backend runs the
  // block's fast frame path; the bus backends program ORI_CONTROL and read
  // ORI_INDEX / ORI_DATA (host::Driver::read_orientation). Throws
  // std::runtime_error on a device without the block (device_config).
  void set_orientation(const host::OrientationControl& ori);
  // The last processed frame's orientation readout (valid = false before
  // set_orientation() or while no frame has been published).
  const host::OrientationReadout& orientation() const { return orientation_; }

 private:
  DeviceOptions options_;
  stream::Pipeline pipeline_;    // Backend::fast
  std::unique_ptr<SimBus> bus_;  // Backend::model / rtl
  std::unique_ptr<host::Driver> driver_;
  bool corridor_on_ = false;
  stream::EdgeConfig edge_cfg_{};
  stream::HoughConfig hough_cfg_{};
  stream::CorridorReadout corridor_;
  uint32_t fast_hough_frames_ = 0;  // Backend::fast: HOUGH_FRAME_COUNT
  stream::CorridorReadout fast_corridor() const;
  bool orientation_on_ = false;
  host::OrientationControl ori_cfg_{};
  host::OrientationReadout orientation_;
  host::OrientationReadout fast_orientation() const;
};

// The device of `options` (see Device) behind the host's interface.
std::unique_ptr<host::FrameProcessor> make_device(const DeviceOptions& options = {});

}  // namespace ceilnav::drivers
