// Frame-size limits of the device and the widths that follow from them.
// Every accumulator width in stream/ (and later rtl_model/) is derived here.
#pragma once

#include <cstdint>

namespace ceilnav::stream {

// Largest frame the device accepts: 2048 x 2048 (covers 1920x1080).
inline constexpr int kCoordBits = 11;                     // x in [0, 2047], y in [0, 2047]
inline constexpr uint32_t kMaxWidth = 1u << kCoordBits;   // pixels per line
inline constexpr uint32_t kMaxHeight = 1u << kCoordBits;  // lines per frame
inline constexpr int kPixelBits = 8;

// Number of bits needed to hold the unsigned value v.
constexpr int bits_for(uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n == 0 ? 1 : n;
}

}  // namespace ceilnav::stream
