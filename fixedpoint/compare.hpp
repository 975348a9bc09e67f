// Exact comparison of fixed-point values of any two formats.
#pragma once

#include <compare>

#include "fixedpoint/fixed_type.hpp"
#include "fixedpoint/wide_int.hpp"

namespace ceilnav::fp {

namespace detail {

// x <=> y * 2^-shift, shift > 0, |x|, |y| < 2^64.
constexpr std::strong_ordering compare_scaled(i128 x, i128 y, int shift) {
  // |y| < 2^64 makes floor and exactness the same for every shift >= 127.
  if (shift > 127) shift = 127;
  const i128 floor_q = y >> shift;
  const bool inexact = (static_cast<u128>(y) & ((static_cast<u128>(1) << shift) - 1)) != 0;
  if (x != floor_q) return x <=> floor_q;
  return inexact ? std::strong_ordering::less : std::strong_ordering::equal;
}

}  // namespace detail

template <FixedPoint A, FixedPoint B>
constexpr std::strong_ordering operator<=>(const A& a, const B& b) {
  const auto ra = static_cast<detail::i128>(a.raw());
  const auto rb = static_cast<detail::i128>(b.raw());
  if constexpr (A::frac == B::frac) {
    return ra <=> rb;
  } else if constexpr (A::frac < B::frac) {
    return detail::compare_scaled(ra, rb, B::frac - A::frac);
  } else {
    return 0 <=> detail::compare_scaled(rb, ra, A::frac - B::frac);
  }
}

template <FixedPoint A, FixedPoint B>
constexpr bool operator==(const A& a, const B& b) {
  return (a <=> b) == 0;
}

}  // namespace ceilnav::fp
