// The fixed-point vote of the orientation block (docs/blocks/orientation.md):
// from a 3 x 3 Sobel gradient (gx, gy), |gx|, |gy| <= 1020, the folded angle
// (modulo 90 degrees) by a quadrant and an octant fold, a rounded ratio
// min/max and an arctangent table, its bin, and an alpha-max-beta-min
// magnitude. The C++ cycle model (stream/orientation), the bit-true golden
// (golden::orientation_histogram_fixed) and the RTL (through
// ceilnav_widths_pkg, written by tools/regmap_gen from this header) use these
// same words, so every vote is bit exact across the levels.
//
// Formats:
//   ratio   q = round(min * 2^8 / max) in [0, 256]: u0.8 (0 .. 1), computed as
//           (floor(min * 2^9 / max) + 1) >> 1 (a 9-bit restoring division).
//   angle   phi in [0, 4096]: u0.12 of 90 degrees (one unit 90 / 4096 =
//           0.022 degrees); the table entry of q is atan(q / 256) in that
//           unit, rounded to nearest (ties up), 11 bits (< 45 degrees =
//           2048; q = 256 is 45 degrees exactly, not in the table).
//   bin     round(phi * bins / 4096) mod bins (ties up).
//   weight  (max(8 M, 7 M + 4 m) + 4) >> 3, M = max(|gx|, |gy|), m = min.
// Bounds (derived in docs/blocks/orientation.md, checked exhaustively by
// golden/tests/orientation_fixed_test.cpp): |phi - folded atan2| <=
// 2^-9 rad + 1/2 unit = 0.1229 degrees; 0.97014 L2 - 1/2 <= weight <=
// 1.00778 L2 + 1/2 (L2 = sqrt(gx^2 + gy^2)).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>

namespace ceilnav::fp::orientation {

inline constexpr int kGradMax = 1020;            // |gx|, |gy| of a 3 x 3 Sobel on 8-bit pixels
inline constexpr int kGradBits = 11;             // gx, gy signed
inline constexpr int kAbsBits = 10;              // |gx|, |gy|
inline constexpr int kRatioFrac = 8;             // q: u0.8
inline constexpr int kDivBits = kRatioFrac + 1;  // quotient bits after the integer bit
inline constexpr int kAngleFrac = 12;            // phi: u0.12 of 90 degrees
inline constexpr uint32_t kAngleOne = 1u << kAngleFrac;  // 90 degrees
inline constexpr uint32_t kAngleHalf = kAngleOne / 2;    // 45 degrees
inline constexpr int kAtanEntries = 1 << kRatioFrac;     // q = 0 .. 255
inline constexpr int kAtanBits = kAngleFrac - 1;         // entries < 2048
inline constexpr int kWeightBits = 11;                   // weight <= 1403
inline constexpr uint32_t kWeightMax = (11u * kGradMax + 4u) >> 3;
inline constexpr int kBinBits = 32;  // histogram bins, saturating
inline constexpr int kThresholdBits = 12;
inline constexpr int kMaxBins = 256;  // the block's bin address is 8 bits
static_assert(kWeightMax < (1u << kWeightBits) && kWeightMax >= (1u << (kWeightBits - 1)));
static_assert(kGradMax < (1 << kAbsBits));

// The arctangent table: entry q = atan(q / 256) in units of 90 / 4096 degrees,
// rounded to nearest (ties up).
inline std::array<uint16_t, kAtanEntries> make_atan_table() {
  std::array<uint16_t, kAtanEntries> t{};
  for (int q = 0; q < kAtanEntries; ++q) {
    const double a = std::atan(static_cast<double>(q) / kAtanEntries);  // radians
    const double units = a / (std::numbers::pi / 2.0) * kAngleOne;
    t[static_cast<size_t>(q)] = static_cast<uint16_t>(std::floor(units + 0.5));
  }
  return t;
}

inline const std::array<uint16_t, kAtanEntries>& atan_table() {
  static const std::array<uint16_t, kAtanEntries> table = make_atan_table();
  return table;
}

// The octant fold: the larger and the smaller of the two components that the
// quadrant fold orders, and whether the folded angle is above 45 degrees.
struct Folded {
  uint32_t big = 0;    // M
  uint32_t small = 0;  // m <= M
  bool upper = false;  // the folded angle is 90 - atan(m / M)
};

// Quadrant fold: angle mod 90 of (gx, gy) is atan2(v, u) with (u, v) =
// (|gx|, |gy|) in quadrants 1 and 3 (gx > 0, gy >= 0 or gx < 0, gy <= 0),
// (|gy|, |gx|) in 2 and 4. Octant fold: above 45 degrees (v > u) it is 90
// minus atan2(u, v).
inline Folded fold(int gx, int gy) {
  const auto ax = static_cast<uint32_t>(std::abs(gx));
  const auto ay = static_cast<uint32_t>(std::abs(gy));
  const bool same = (gx > 0 && gy >= 0) || (gx < 0 && gy <= 0);
  const uint32_t u = same ? ax : ay;
  const uint32_t v = same ? ay : ax;
  return v > u ? Folded{v, u, true} : Folded{u, v, false};
}

// q = round(m 2^8 / M) by the 9-bit restoring division; M = 0 gives 256
// (as the divider: the integer bit of 0 / 0 is 1).
inline uint32_t ratio(uint32_t big, uint32_t small) {
  const uint32_t q9 = big == 0 ? (1u << kDivBits) : (small << kDivBits) / big;
  return (q9 + 1) >> 1;
}

// phi in [0, 4096]: the folded angle in units of 90 / 4096 degrees.
inline uint32_t folded_angle(const Folded& f) {
  const uint32_t q = ratio(f.big, f.small);
  const uint32_t t = q == kAtanEntries ? kAngleHalf : atan_table()[q];
  return f.upper ? kAngleOne - t : t;
}
inline uint32_t folded_angle(int gx, int gy) {
  return folded_angle(fold(gx, gy));
}

// The bin of phi: round(phi * bins / 4096) mod bins.
inline uint32_t bin_of(uint32_t phi, uint32_t bins) {
  const uint32_t k = (phi * bins + kAngleHalf) >> kAngleFrac;
  return k == bins ? 0u : k;
}

// The magnitude estimate of the folded components.
inline uint32_t weight(const Folded& f) {
  const uint32_t a = 8 * f.big;
  const uint32_t b = 7 * f.big + 4 * f.small;
  return ((a > b ? a : b) + 4) >> 3;
}

struct Vote {
  bool valid = false;  // weight > threshold
  uint32_t bin = 0;
  uint32_t weight = 0;

  friend bool operator==(const Vote&, const Vote&) = default;
};

// The vote of a gradient: weight > threshold votes `weight` into `bin`.
inline Vote vote(int gx, int gy, uint32_t threshold, uint32_t bins) {
  const Folded f = fold(gx, gy);
  const uint32_t w = weight(f);
  return {w > threshold, bin_of(folded_angle(f), bins), w};
}

// A saturating bin: b + w, at most 2^32 - 1.
inline uint32_t add_saturating(uint32_t b, uint32_t w) {
  const uint64_t s = uint64_t{b} + w;
  return s > UINT32_MAX ? UINT32_MAX : static_cast<uint32_t>(s);
}

}  // namespace ceilnav::fp::orientation
