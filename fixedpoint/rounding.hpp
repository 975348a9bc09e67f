// Quantisation (rounding) modes and the rounding right shift behind them.
#pragma once

#include "fixedpoint/wide_int.hpp"

namespace ceilnav::fp {

// What happens to the bits dropped when a value loses fractional bits.
enum class Rounding {
  truncate,    // floor: drop the bits (toward -inf), SystemC SC_TRN
  half_up,     // round to nearest, ties toward +inf, SystemC SC_RND
  convergent,  // round to nearest, ties to even, SystemC SC_RND_CONV
};

namespace detail {

// round(v / 2^shift) for shift >= 0 under the given mode; |v| < 2^126.
constexpr i128 shift_right_rounded(i128 v, int shift, Rounding rounding) {
  if (shift <= 0) return v;
  // |v| < 2^126 makes |v / 2^shift| < 1/2 for shift >= 127, where every mode
  // gives the same result as at shift == 127.
  if (shift > 127) shift = 127;
  const i128 floor_q = v >> shift;  // arithmetic shift: floor for negative v
  const u128 rem = static_cast<u128>(v) & ((static_cast<u128>(1) << shift) - 1);
  const u128 half = static_cast<u128>(1) << (shift - 1);
  switch (rounding) {
    case Rounding::truncate:
      return floor_q;
    case Rounding::half_up:
      return floor_q + (rem >= half ? 1 : 0);
    case Rounding::convergent:
      if (rem > half) return floor_q + 1;
      if (rem == half) return floor_q + (floor_q & 1);  // odd -> up to even
      return floor_q;
  }
  return floor_q;
}

}  // namespace detail
}  // namespace ceilnav::fp
