// Requantisation: an exact dyadic value raw * 2^-src_frac into a Width-bit
// word with dst_frac fractional bits, rounding first, then overflow (the
// order SystemC uses).
#pragma once

#include <bit>
#include <cstdint>

#include "fixedpoint/overflow.hpp"
#include "fixedpoint/rounding.hpp"
#include "fixedpoint/wide_int.hpp"

namespace ceilnav::fp::detail {

struct Format {
  int width;
  int frac;
  bool is_signed;
  Rounding rounding;
  Overflow overflow;
};

// |raw| < 2^126.
constexpr i128 requantise(i128 raw, int src_frac, const Format& dst) {
  const int drop = src_frac - dst.frac;
  if (drop >= 0) {
    return apply_overflow(shift_right_rounded(raw, drop, dst.rounding), dst.width, dst.is_signed,
                          dst.overflow);
  }
  // Gaining fractional bits is exact; only overflow can happen.
  const int gain = -drop;
  if (raw == 0) return 0;
  if (dst.overflow == Overflow::wrap) {
    // Shifting modulo 2^128 keeps the low width (<= 64) bits right.
    if (gain >= 128) return 0;
    return wrap_bits(static_cast<i128>(static_cast<u128>(raw) << gain), dst.width, dst.is_signed);
  }
  // |raw * 2^gain| >= 2^126 lies beyond every 64-bit word: saturate without
  // computing it.
  const i128 saturated =
      raw < 0 ? min_raw(dst.width, dst.is_signed) : max_raw(dst.width, dst.is_signed);
  if (gain >= 64) return saturated;
  const i128 limit = pow2_int(126 - gain);
  if (raw >= limit || raw < -limit) return saturated;
  return apply_overflow(raw * pow2_int(gain), dst.width, dst.is_signed, Overflow::saturate);
}

// A finite double is exactly mantissa * 2^exponent with |mantissa| < 2^53.
struct DecomposedDouble {
  i128 mantissa;
  int exponent;
  bool is_nan;
  bool is_inf;
};

constexpr DecomposedDouble decompose(double value) {
  const auto bits = std::bit_cast<std::uint64_t>(value);
  const bool negative = (bits >> 63) != 0;
  const int biased_exponent = static_cast<int>((bits >> 52) & 0x7ff);
  const auto fraction = static_cast<i128>(bits & ((std::uint64_t{1} << 52) - 1));
  if (biased_exponent == 0x7ff) return {0, 0, fraction != 0, fraction == 0};
  i128 mantissa = fraction;
  int exponent = -1074;  // subnormal: no hidden bit
  if (biased_exponent != 0) {
    mantissa += pow2_int(52);
    exponent = biased_exponent - 1075;
  }
  return {negative ? -mantissa : mantissa, exponent, false, false};
}

// NaN -> 0; +-inf -> max/min under saturate, 0 under wrap (2^inf mod 2^width).
constexpr i128 quantise_double(double value, const Format& dst) {
  const DecomposedDouble d = decompose(value);
  if (d.is_nan) return 0;
  if (d.is_inf) {
    if (dst.overflow == Overflow::wrap) return 0;
    return value < 0 ? min_raw(dst.width, dst.is_signed) : max_raw(dst.width, dst.is_signed);
  }
  return requantise(d.mantissa, -d.exponent, dst);
}

}  // namespace ceilnav::fp::detail
