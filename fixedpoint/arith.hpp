// Exact (widening) arithmetic and compound assignment.
//
// Widening rules, with I = int_bits = width - frac of each operand:
//   a + b : frac = max(Fa, Fb); int_bits = max(Ia', Ib') + 1;
//           signed if either operand is signed.
//   a - b : the same widths, always signed.
//   -a    : Fixed<Wa + 1, Fa, signed>.
//   a * b : Fixed<Wa + Wb, Fa + Fb, Sa || Sb>.
// Ia' = Ia + 1 for an unsigned operand meeting a signed one (it needs a sign
// bit), else Ia. Results use the default modes (truncate, wrap); they never
// round or overflow. A result wider than 64 bits is a compile-time error.
#pragma once

#include <algorithm>

#include "fixedpoint/convert.hpp"
#include "fixedpoint/fixed_type.hpp"
#include "fixedpoint/quantise.hpp"
#include "fixedpoint/wide_int.hpp"

namespace ceilnav::fp {

namespace detail {

template <FixedPoint A, FixedPoint B, bool ForceSigned>
struct SumFormat {
  static constexpr bool is_signed = ForceSigned || A::is_signed || B::is_signed;
  static constexpr bool mixed = A::is_signed != B::is_signed;
  static constexpr int ia = A::int_bits + (mixed && !A::is_signed ? 1 : 0);
  static constexpr int ib = B::int_bits + (mixed && !B::is_signed ? 1 : 0);
  static constexpr int frac = std::max(A::frac, B::frac);
  static constexpr int int_bits = std::max(ia, ib) + 1;
  static constexpr int width = int_bits + frac;
  // Largest exact sum the int128 intermediate holds (used by += and -=).
  static constexpr bool fits_i128 = width <= 126;
};

template <FixedPoint A, FixedPoint B, bool ForceSigned>
struct SumTypeOf {
  using F = SumFormat<A, B, ForceSigned>;
  static_assert(F::width <= kMaxWidth,
                "fp: exact sum/difference needs more than 64 bits; convert the operands first");
  using type = Fixed<F::width, F::frac, F::is_signed>;
};

template <FixedPoint A, FixedPoint B>
struct ProductTypeOf {
  static_assert(A::width + B::width <= kMaxWidth,
                "fp: exact product needs more than 64 bits; convert the operands first");
  using type = Fixed<A::width + B::width, A::frac + B::frac, A::is_signed || B::is_signed>;
};

// x's raw rescaled to `to_frac` >= X::frac fractional bits (exact).
template <FixedPoint X>
constexpr i128 aligned_raw(const X& x, int to_frac) {
  return static_cast<i128>(x.raw()) * pow2_int(to_frac - X::frac);
}

}  // namespace detail

template <FixedPoint A, FixedPoint B>
using SumType = typename detail::SumTypeOf<A, B, false>::type;
template <FixedPoint A, FixedPoint B>
using DifferenceType = typename detail::SumTypeOf<A, B, true>::type;
template <FixedPoint A, FixedPoint B>
using ProductType = typename detail::ProductTypeOf<A, B>::type;
template <FixedPoint A>
using NegateType = Fixed<A::width + 1, A::frac, true>;

template <FixedPoint A, FixedPoint B>
constexpr SumType<A, B> operator+(const A& a, const B& b) {
  using T = SumType<A, B>;
  return T::from_raw(static_cast<typename T::raw_type>(detail::aligned_raw(a, T::frac) +
                                                       detail::aligned_raw(b, T::frac)));
}

template <FixedPoint A, FixedPoint B>
constexpr DifferenceType<A, B> operator-(const A& a, const B& b) {
  using T = DifferenceType<A, B>;
  return T::from_raw(static_cast<typename T::raw_type>(detail::aligned_raw(a, T::frac) -
                                                       detail::aligned_raw(b, T::frac)));
}

template <FixedPoint A>
constexpr NegateType<A> operator-(const A& a) {
  using T = NegateType<A>;
  return T::from_raw(static_cast<typename T::raw_type>(-static_cast<detail::i128>(a.raw())));
}

template <FixedPoint A, FixedPoint B>
constexpr ProductType<A, B> operator*(const A& a, const B& b) {
  using T = ProductType<A, B>;
  return T::from_raw(static_cast<typename T::raw_type>(static_cast<detail::i128>(a.raw()) *
                                                       static_cast<detail::i128>(b.raw())));
}

// Compound assignment: a = exact(a op b), requantised with A's rounding and
// overflow. Exact intermediates are held in 126 bits, so e.g. a 64-bit
// accumulator may take += of a 64-bit sample.
template <FixedPoint A, FixedPoint B>
constexpr A& operator+=(A& a, const B& b) {
  using F = detail::SumFormat<A, B, false>;
  static_assert(F::fits_i128, "fp: += operands too far apart in scale");
  const detail::i128 sum = detail::aligned_raw(a, F::frac) + detail::aligned_raw(b, F::frac);
  a = A::from_raw(static_cast<typename A::raw_type>(detail::requantise(sum, F::frac, A::format)));
  return a;
}

template <FixedPoint A, FixedPoint B>
constexpr A& operator-=(A& a, const B& b) {
  using F = detail::SumFormat<A, B, true>;
  static_assert(F::fits_i128, "fp: -= operands too far apart in scale");
  const detail::i128 diff = detail::aligned_raw(a, F::frac) - detail::aligned_raw(b, F::frac);
  a = A::from_raw(static_cast<typename A::raw_type>(detail::requantise(diff, F::frac, A::format)));
  return a;
}

template <FixedPoint A, FixedPoint B>
constexpr A& operator*=(A& a, const B& b) {
  static_assert(A::width + B::width <= 126, "fp: *= operands too wide");
  const detail::i128 product =
      static_cast<detail::i128>(a.raw()) * static_cast<detail::i128>(b.raw());
  a = A::from_raw(
      static_cast<typename A::raw_type>(detail::requantise(product, A::frac + B::frac, A::format)));
  return a;
}

}  // namespace ceilnav::fp
