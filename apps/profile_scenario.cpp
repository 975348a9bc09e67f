// Video timing and blanking of a `ceilnav profile` scenario: the s_axis_video
// feed of one frame.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "apps/profile_scenario.hpp"

namespace ceilnav::app {

std::string_view to_string(Blanking b) {
  switch (b) {
    case Blanking::none:
      return "none";
    case Blanking::vga:
      return "vga";
    case Blanking::random:
      return "random";
  }
  return "?";
}

Blanking parse_blanking(const std::string& name) {
  if (name == "none") return Blanking::none;
  if (name == "vga") return Blanking::vga;
  if (name == "random") return Blanking::random;
  throw std::runtime_error("unknown blanking '" + name + "' (none, vga or random)");
}

VideoTiming vga_like_timing(int width, int height) {
  // VESA 640x480@60: 640 + 160 clocks per line, 480 + 45 lines per frame.
  constexpr double kLineBlankPerPixel = 160.0 / 640.0;
  constexpr double kFrameBlankLinesPerLine = 45.0 / 480.0;
  VideoTiming t;
  t.line_blanking_cycles = static_cast<uint32_t>(std::lround(kLineBlankPerPixel * width));
  const auto lines = static_cast<uint32_t>(std::lround(kFrameBlankLinesPerLine * height));
  t.frame_blanking_cycles = lines * (static_cast<uint32_t>(width) + t.line_blanking_cycles);
  return t;
}

drivers::FrameFeed frame_feed(const ProfileScenario& s) {
  drivers::FrameFeed f;
  f.blanking_cycles = kMinFrameBlankingCycles;
  if (s.blanking == Blanking::vga) {
    const VideoTiming t = vga_like_timing(s.width, s.height);
    f.line_blanking_cycles = t.line_blanking_cycles;
    f.blanking_cycles = std::max(t.frame_blanking_cycles, kMinFrameBlankingCycles);
  } else if (s.blanking == Blanking::random) {
    f.gap_probability = s.gap_probability;
  }
  return f;
}

}  // namespace ceilnav::app
