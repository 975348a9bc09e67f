// 128-bit intermediates for the fixed-point library.
#pragma once

#include <cstdint>

namespace ceilnav::fp::detail {

// g++/clang extension; every value the library computes with is below 2^126 in
// magnitude (64-bit raws, their sums and products), so these never overflow.
__extension__ typedef __int128 i128;           // NOLINT(modernize-use-using)
__extension__ typedef unsigned __int128 u128;  // NOLINT(modernize-use-using)

inline constexpr int kMaxWidth = 64;  // storage limit of Fixed
inline constexpr int kMaxFrac = 512;  // keeps 2^-frac a normal double
inline constexpr int kMinFrac = -512;

// 2^exponent as a double, exact for -1074 <= exponent <= 1023.
constexpr double pow2(int exponent) {
  double result = 1.0;
  for (; exponent > 0; --exponent) result *= 2.0;
  for (; exponent < 0; ++exponent) result *= 0.5;
  return result;
}

// 2^exponent as an integer, 0 <= exponent <= 126.
constexpr i128 pow2_int(int exponent) {
  return static_cast<i128>(1) << exponent;
}

}  // namespace ceilnav::fp::detail
