// Overflow modes: bringing an exact integer into a Width-bit word.
#pragma once

#include "fixedpoint/wide_int.hpp"

namespace ceilnav::fp {

// What happens when a value does not fit the target word.
enum class Overflow {
  wrap,      // keep the low Width bits (modular, two's complement), SystemC SC_WRAP
  saturate,  // clamp to the nearest representable value, SystemC SC_SAT
};

namespace detail {

constexpr i128 min_raw(int width, bool is_signed) {
  return is_signed ? -pow2_int(width - 1) : 0;
}

constexpr i128 max_raw(int width, bool is_signed) {
  return is_signed ? pow2_int(width - 1) - 1 : pow2_int(width) - 1;
}

// v modulo 2^width, read as a width-bit two's-complement or unsigned word.
constexpr i128 wrap_bits(i128 v, int width, bool is_signed) {
  const u128 mask = (static_cast<u128>(1) << width) - 1;
  const i128 low = static_cast<i128>(static_cast<u128>(v) & mask);
  if (is_signed && low > max_raw(width, true)) return low - pow2_int(width);
  return low;
}

constexpr i128 apply_overflow(i128 v, int width, bool is_signed, Overflow overflow) {
  if (overflow == Overflow::wrap) return wrap_bits(v, width, is_signed);
  if (v < min_raw(width, is_signed)) return min_raw(width, is_signed);
  if (v > max_raw(width, is_signed)) return max_raw(width, is_signed);
  return v;
}

}  // namespace detail
}  // namespace ceilnav::fp
