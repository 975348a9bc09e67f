// `ceilnav profile`: frames streamed cycle by cycle through the device (the C++
// cycle-level model or the Verilated RTL) with a chosen video timing and
// run-stream back-pressure, measured at the device ports and through its
// registers, frame by frame. See docs/profile.md.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core.hpp>

#include "ceilnav/regs.hpp"
#include "common/camera_config.hpp"
#include "drivers/sim_bus.hpp"
#include "host/status.hpp"

namespace ceilnav::app {

// Idle cycles on s_axis_video between pixels.
enum class Blanking {
  none,    // pixels back to back, frames host-paced
  vga,     // vga_like_timing(): fixed blanking after every line and after the frame
  random,  // random gaps before pixels (ProfileScenario::gap_probability)
};
std::string_view to_string(Blanking b);
Blanking parse_blanking(const std::string& name);  // std::runtime_error if unknown

// 640x480@60 (VESA): 800 clocks per line of which 160 blanking, 525 lines of
// which 45 blanking. Other sizes keep both ratios: line blanking = round(W/4),
// frame blanking = round(45/480 H) lines of W + line blanking clocks.
struct VideoTiming {
  uint32_t line_blanking_cycles = 0;   // after every line but the last
  uint32_t frame_blanking_cycles = 0;  // after the last line (vertical blanking)
};
VideoTiming vga_like_timing(int width, int height);

struct ProfileScenario {
  int width = 640, height = 480;
  Blanking blanking = Blanking::none;
  double gap_probability = 0.25;  // random: before each pixel, idle cycles while P hits
  double backpressure = 0.0;      // P(m_axis_runs_tready low) on each cycle, in [0, 1)
  int tapes = 1;                  // parallel tapes in the rendered scene
  uint64_t seed = 1;              // gaps, back-pressure and the renderer's noise
  // The device's build-time configuration (regs::kConfigs: tape, full).
  regs::Config device_config = regs::kConfigFull;
};

// The feed of one frame on s_axis_video for the scenario. Every pattern ends
// with at least kMinFrameBlankingCycles idle cycles (none/random too).
inline constexpr uint32_t kMinFrameBlankingCycles = 16;
drivers::FrameFeed frame_feed(const ProfileScenario& s);

// Counts at the device ports over a window of edges (one frame's host cycle:
// configure, stream, interrupt, readout). Handshakes are taken as AXI defines
// them: inputs on an edge against the registered outputs before it.
class PortProbe : public drivers::SimObserver {
 public:
  struct Counts {
    // The frame: from the edge accepting the SOF beat (tvalid && tready &&
    // tuser) to the one accepting the lines_per_frame-th tlast, inclusive.
    bool sof_seen = false, eof_seen = false;
    int frames_started = 0;  // SOF beats accepted in the window (1 expected)
    uint64_t sof_edge = 0, eof_edge = 0;
    uint64_t frame_cycles = 0;    // edges in [sof_edge, eof_edge]
    uint64_t tvalid_cycles = 0;   // of those, edges with s_axis_video_tvalid
    uint64_t accepted_beats = 0;  // of those, edges with tvalid && tready
    uint64_t bubbles = 0;         // whole window: edges with tvalid && !tready
    // irq: first 0 -> 1 after the EOF edge; latency = rise edge - eof_edge
    // (the register EOF_TO_IRQ_CYCLES counts the same way).
    bool irq_rise_seen = false;
    uint64_t irq_rise_edge = 0;
    uint64_t run_beats = 0;         // m_axis_runs tvalid && tready (trailers included)
    uint64_t run_stall_cycles = 0;  // m_axis_runs tvalid && !tready
    uint64_t run_tready_low_cycles = 0;
    uint64_t axil_reads = 0;   // AR handshakes
    uint64_t axil_writes = 0;  // AW (= W) handshakes
    uint64_t first_edge = 0, edges = 0;
  };

  explicit PortProbe(int lines_per_frame) : lines_per_frame_(lines_per_frame) {}
  void on_edge(uint64_t edge, const drivers::SimInputs& in,
               const drivers::SimOutputs& out) override;
  // The counts since the previous take(); starts a new window.
  Counts take();

 private:
  int lines_per_frame_;
  Counts c_{};
  bool in_frame_ = false;
  int lines_ = 0;
  bool irq_prev_ = false;
  bool started_ = false;
};

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

// Renders frame `index` of the scenario: the demo drive down the corridor
// (golden/default_scene.hpp) at the scenario's size with `tapes` parallel tapes.
host::CameraConfig profile_camera(const ProfileScenario& s);
cv::Mat render_profile_frame(const ProfileScenario& s, const host::CameraConfig& camera,
                             size_t index, size_t count);

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

struct ProfileOptions {
  std::string backend = "model";  // model | rtl
  std::string config = "full";    // device configuration (regs::kConfigs): tape | full
  std::string frames_dir;         // empty: render
  std::string scene_file;         // with frames_dir; default <frames_dir>/scene.yaml
  std::string out_dir;            // empty: summary on stdout only
  int width = 640, height = 480;
  std::string blanking = "none";
  double gap_probability = 0.25;
  double backpressure = 0.0;
  int tapes = 1;
  int count = 0;  // 0: 10 rendered frames, or every frame of frames_dir
  uint64_t seed = 1;
  std::vector<double> sweep_duties{0.0, 0.25, 0.5, 0.75, 0.9};
  int sweep_frames = 2;  // frames per sweep point; 0: no sweep
};
int run_profile(const ProfileOptions& o);

}  // namespace ceilnav::app
