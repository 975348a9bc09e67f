// Device configuration as the host programs it. The host writes a shadow copy
// at any time; the pipeline copies it to the active copy at the next start of
// frame (SOF), so a frame is always processed with one consistent setting.
#pragma once

#include <array>
#include <cstdint>

namespace ceilnav::stream {

// One threshold-LUT entry: bits 7:0 = remapped grey, bit 8 = mask.
using LutEntry = uint16_t;
inline constexpr LutEntry kLutRemapMask = 0x00FF;
inline constexpr LutEntry kLutMaskBit = 0x0100;

constexpr LutEntry lut_entry(uint8_t remap, bool mask) {
  return static_cast<LutEntry>(remap | (mask ? kLutMaskBit : 0u));
}

struct PipelineConfig {
  uint16_t width = 640;             // pixels per line, 1 .. kMaxWidth
  uint16_t height = 480;            // lines per frame, 1 .. kMaxHeight
  std::array<LutEntry, 256> lut{};  // default: all zero (remap 0, mask 0)
  uint8_t background_level = 0;     // run scanner: w = max(0, remap - background_level)
  uint16_t min_run_length = 1;      // shorter runs are not emitted (pixels)
  uint16_t max_runs_per_row = 8;    // further runs on the row are dropped and counted
  bool hist_source_remap = false;   // histogram of: false = camera grey, true = LUT remap

  friend bool operator==(const PipelineConfig&, const PipelineConfig&) = default;
};

// Identity remap, mask = (grey >= threshold).
inline std::array<LutEntry, 256> threshold_lut(uint8_t threshold) {
  std::array<LutEntry, 256> lut{};
  for (unsigned g = 0; g < 256; ++g) {
    lut[g] = lut_entry(static_cast<uint8_t>(g), g >= threshold);
  }
  return lut;
}

}  // namespace ceilnav::stream
