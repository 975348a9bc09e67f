// The cos/sin table of the hough block (seed 002 eq. 18 voter): one entry per
// degree over [0, 180), each in the fixed-point format TrigWord = s1.14
// (Fixed<16, 14, signed>, rounded to nearest, ties up). The C++ cycle model,
// the golden reference and the RTL (through ceilnav_widths_pkg, written by
// tools/regmap_gen from this header) use these same words, so every vote is
// bit exact across the levels. Error bound (docs/fixedpoint.md, "hough
// cos/sin table"): |entry * 2^-14 - cos| <= 2^-15 (+ the last-ulp error of the
// libm call, below 2^-52), so for x, y < 2^11 the quantised rho
// x C + y S differs from the exact x cos + y sin by at most
// (x + y) 2^-15 < 0.125 pixel.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "fixedpoint/fixed.hpp"

namespace ceilnav::fp::hough {

inline constexpr int kTrigFrac = 14;
inline constexpr int kTrigBits = 16;
using TrigWord = Fixed<kTrigBits, kTrigFrac, true, Rounding::half_up, Overflow::saturate>;
// Table entries: theta = k degrees, k in [0, 180).
inline constexpr int kTableEntries = 180;

struct TrigTable {
  std::array<int32_t, kTableEntries> cos{};
  std::array<int32_t, kTableEntries> sin{};
};

inline TrigTable make_trig_table() {
  TrigTable t;
  for (int k = 0; k < kTableEntries; ++k) {
    const double theta = static_cast<double>(k) * std::numbers::pi / 180.0;
    t.cos[static_cast<size_t>(k)] =
        static_cast<int32_t>(TrigWord::from_double(std::cos(theta)).raw());
    t.sin[static_cast<size_t>(k)] =
        static_cast<int32_t>(TrigWord::from_double(std::sin(theta)).raw());
  }
  return t;
}

// The table, computed once.
inline const TrigTable& trig_table() {
  static const TrigTable table = make_trig_table();
  return table;
}

}  // namespace ceilnav::fp::hough
