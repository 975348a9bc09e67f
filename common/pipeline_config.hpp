// Device configuration as the host programs it. The host writes a shadow copy
// at any time; the pipeline copies it to the active copy at the next start of
// frame (SOF), so a frame is always processed with one consistent setting.
#pragma once

#include <array>
#include <cstdint>

#include "common/limits.hpp"

namespace ceilnav::stream {

// One threshold-LUT entry: bits 7:0 = remapped grey, bit 8 = mask,
// bits 10:9 = pixel class (PixelClass, for class_moments).
using LutEntry = uint16_t;
inline constexpr LutEntry kLutRemapMask = 0x00FF;
inline constexpr LutEntry kLutMaskBit = 0x0100;
inline constexpr int kLutClassShift = 9;
inline constexpr LutEntry kLutClassMask = 0x0600;
inline constexpr LutEntry kLutEntryMask = kLutClassMask | kLutMaskBit | kLutRemapMask;

// Pixel class codes of the LUT's CLASS field (fixed: the host is written
// against them).
enum PixelClass : uint8_t {
  kClassBackground = 0,
  kClassPattern = 1,  // the circle
  kClassShadow = 2,
  kClassBar = 3,
  kClassCount
};

constexpr LutEntry lut_entry(uint8_t remap, bool mask, uint8_t pixel_class = kClassBackground) {
  return static_cast<LutEntry>(remap | (mask ? kLutMaskBit : 0u) |
                               ((unsigned{pixel_class} << kLutClassShift) & kLutClassMask));
}
constexpr uint8_t lut_class(LutEntry e) {
  return static_cast<uint8_t>((e & kLutClassMask) >> kLutClassShift);
}

// class_moments window [x0, x1) x [y0, y1) in frame coordinates (12-bit
// register fields; bounds above the frame act as the frame edge, x1 <= x0 or
// y1 <= y0 is empty). Default: the whole frame.
struct ClassWindow {
  uint16_t x0 = 0;
  uint16_t x1 = static_cast<uint16_t>(kMaxWidth);
  uint16_t y0 = 0;
  uint16_t y1 = static_cast<uint16_t>(kMaxHeight);
  friend bool operator==(const ClassWindow&, const ClassWindow&) = default;
};

struct PipelineConfig {
  uint16_t width = 640;             // pixels per line, 1 .. kMaxWidth
  uint16_t height = 480;            // lines per frame, 1 .. kMaxHeight
  std::array<LutEntry, 256> lut{};  // default: all zero (remap 0, mask 0)
  uint8_t background_level = 0;     // run scanner: w = max(0, remap - background_level)
  uint16_t min_run_length = 1;      // shorter runs are not emitted (pixels)
  uint16_t max_runs_per_row = 8;    // further runs on the row are dropped and counted
  bool hist_source_remap = false;   // histogram of: false = camera grey, true = LUT remap
  ClassWindow class_window{};       // class_moments window (default: the whole frame)

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
