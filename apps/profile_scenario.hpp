// `ceilnav profile`, the scenario: frame size, video timing on s_axis_video,
// run-stream back-pressure, the rendered frames. See docs/profile.md.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

#include "ceilnav/regs.hpp"
#include "common/camera_config.hpp"
#include "drivers/sim_bus.hpp"

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
  // The device's build-time configuration (regs::kConfigs: tape, corridor, full, homing).
  regs::Config device_config = regs::kConfigFull;
};

// The feed of one frame on s_axis_video for the scenario. Every pattern ends
// with at least kMinFrameBlankingCycles idle cycles (none/random too).
inline constexpr uint32_t kMinFrameBlankingCycles = 16;
drivers::FrameFeed frame_feed(const ProfileScenario& s);

// Renders frame `index` of the scenario: the demo drive down the corridor
// (golden/default_scene.hpp) at the scenario's size with `tapes` parallel tapes.
host::CameraConfig profile_camera(const ProfileScenario& s);
cv::Mat render_profile_frame(const ProfileScenario& s, const host::CameraConfig& camera,
                             size_t index, size_t count);

}  // namespace ceilnav::app
