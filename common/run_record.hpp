// One run of mask = 1 pixels on one row, as the run scanner emits it.
#pragma once

#include <compare>
#include <cstdint>

namespace ceilnav::stream {

// Run bounds are inclusive: pixels x_start .. x_end have mask = 1.
// sum_w and sum_xw are taken over x_start-1 .. x_end+1 clipped to the line,
// i.e. the run plus one pixel of margin each side, so that partly covered edge
// pixels below the mask threshold still weigh in (see docs/blocks/run_scanner.md).
// w = max(0, remap - background_level).
struct RunRecord {
  uint16_t row = 0;
  uint16_t x_start = 0;
  uint16_t x_end = 0;
  uint32_t sum_w = 0;   // <= 255 * 2050             -> 19 bits
  uint64_t sum_xw = 0;  // <= 255 * sum(x), x < 2048  -> 30 bits

  friend bool operator==(const RunRecord&, const RunRecord&) = default;
};

}  // namespace ceilnav::stream
