// `ceilnav profile`, the run: frames streamed cycle by cycle through the
// device on a SimBus, measured frame by frame at the ports and through the
// registers, and the rules the figures must meet. See docs/profile.md.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "apps/profile_scenario.hpp"
#include "common/camera_config.hpp"
#include "drivers/sim_bus.hpp"
#include "host/status.hpp"

namespace ceilnav::app {

// Per-frame figures: ports (PortProbe), registers (read by the driver) and host.
struct FrameProfile {
  uint64_t cycles = 0;               // SOF pixel .. EOF pixel, inclusive, at the ports
  uint64_t tvalid_cycles = 0;        // cycles in that span with tvalid high
  uint64_t accepted = 0;             // pixels accepted (tvalid && tready) in that span
  uint64_t bubbles = 0;              // tvalid && !tready cycles
  uint64_t pixels_counted = 0;       // sum of the frame's histogram bins (device side)
  uint64_t device_cycles = 0;        // CYCLES_PER_FRAME
  int64_t eof_to_irq_cycles = -1;    // at the ports; -1: no irq rise after the EOF
  uint32_t eof_to_irq_register = 0;  // EOF_TO_IRQ_CYCLES
  uint32_t fifo_high_water = 0;      // RUN_FIFO_HIGH_WATER
  uint32_t runs_dropped_overflow = 0;
  uint32_t runs_dropped_row_limit = 0;
  uint32_t runs_emitted = 0;      // RUNS_EMITTED
  uint64_t runs = 0;              // run records the driver received for the frame
  uint64_t run_beats = 0;         // m_axis_runs beats over the frame's host cycle
  uint64_t run_stall_cycles = 0;  // m_axis_runs tvalid && !tready
  uint64_t words_read = 0;        // AXI4-Lite reads of the host for the frame
  uint64_t words_written = 0;     // AXI4-Lite writes (configuration) for the frame
  uint64_t configure_cycles = 0;  // Driver::configure (settings, 256 LUT entries) before it
  uint64_t readout_cycles = 0;    // irq rise .. the driver's last transaction
  uint64_t host_cycles = 0;       // the whole window: configure .. readout done
  bool frame_ok = false;          // valid results, trailer seen, no frame errors
  double host_driver_us = 0.0;    // wall time of Driver::configure + read_frame (simulation in)
  double host_pose_us = 0.0;      // wall time of the threshold choice and the pose maths
  host::Status pose_status = host::Status::no_tape;

  double pixels_per_valid_cycle() const {
    return tvalid_cycles == 0 ? 0.0
                              : static_cast<double>(accepted) / static_cast<double>(tvalid_cycles);
  }
};

// The SimBus of a backend ("model" or "rtl"); std::runtime_error when this
// build has no RTL or the name is unknown.
std::unique_ptr<drivers::SimBus> make_profile_bus(const std::string& backend,
                                                  const drivers::SimBusOptions& options);

// Streams `count` frames through the device on `bus`, one pass each; the
// threshold of frame i comes from frame i-1's histogram, and frame 0's from a
// first, unreported pass of frame 0. The bus must be fresh (no observer).
std::vector<FrameProfile> profile_frames(drivers::SimBus& bus,
                                         const std::function<cv::Mat(size_t)>& frame_at,
                                         size_t count, const ProfileScenario& s,
                                         const host::CameraConfig& camera);

// One message per violated rule: II (pixels per tvalid cycle) == 1, no
// bubbles, every pixel counted by the device, port and register cycle
// figures equal, one irq per frame, frame ok. Empty: all met.
std::vector<std::string> check_profile(const std::vector<FrameProfile>& frames,
                                       const ProfileScenario& s);

}  // namespace ceilnav::app
