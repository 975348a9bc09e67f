// The bit-true fixed-point type: a Width-bit two's-complement (or unsigned)
// integer `raw` standing for the value raw * 2^-Frac.
#pragma once

#include <concepts>
#include <cstdint>
#include <type_traits>

#include "fixedpoint/overflow.hpp"
#include "fixedpoint/quantise.hpp"
#include "fixedpoint/rounding.hpp"
#include "fixedpoint/wide_int.hpp"

namespace ceilnav::fp {

// Rounding R and overflow O apply whenever a value is brought INTO this type
// (from_double, convert, compound assignment); arithmetic results are exact.
template <int Width, int Frac, bool Signed, Rounding R = Rounding::truncate,
          Overflow O = Overflow::wrap>
class Fixed {
  static_assert(Width >= 1 && Width <= detail::kMaxWidth, "Fixed: Width must be in 1..64");
  static_assert(Frac >= detail::kMinFrac && Frac <= detail::kMaxFrac,
                "Fixed: Frac must be in -512..512");

 public:
  using raw_type = std::conditional_t<Signed, std::int64_t, std::uint64_t>;

  static constexpr int width = Width;
  static constexpr int frac = Frac;
  static constexpr int int_bits = Width - Frac;  // SystemC's iwl
  static constexpr bool is_signed = Signed;
  static constexpr Rounding rounding = R;
  static constexpr Overflow overflow = O;
  static constexpr raw_type min_raw = static_cast<raw_type>(detail::min_raw(Width, Signed));
  static constexpr raw_type max_raw = static_cast<raw_type>(detail::max_raw(Width, Signed));
  static constexpr double resolution = detail::pow2(-Frac);  // value of one LSB
  static constexpr detail::Format format{Width, Frac, Signed, R, O};

  // The same word with other rounding/overflow modes.
  template <Rounding R2, Overflow O2>
  using with_modes = Fixed<Width, Frac, Signed, R2, O2>;

  constexpr Fixed() = default;

  // Keeps the low Width bits of `raw` (two's complement), whatever the modes.
  template <std::integral T>
  static constexpr Fixed from_raw(T raw) {
    Fixed x;
    x.raw_ =
        static_cast<raw_type>(detail::wrap_bits(static_cast<detail::i128>(raw), Width, Signed));
    return x;
  }

  // Exact decomposition of the double, then this type's rounding and overflow.
  // NaN gives 0; +-inf saturates, or gives 0 under wrap.
  static constexpr Fixed from_double(double value) {
    return from_raw(static_cast<raw_type>(detail::quantise_double(value, format)));
  }

  static constexpr Fixed min_value() { return from_raw(min_raw); }
  static constexpr Fixed max_value() { return from_raw(max_raw); }

  constexpr raw_type raw() const { return raw_; }

  // Exact when Width <= 53 (and the result is a normal double); otherwise
  // raw is rounded to nearest double first.
  constexpr double to_double() const { return static_cast<double>(raw_) * resolution; }

 private:
  raw_type raw_{};
};

template <class T>
struct is_fixed : std::false_type {};
template <int W, int F, bool S, Rounding R, Overflow O>
struct is_fixed<Fixed<W, F, S, R, O>> : std::true_type {};

template <class T>
concept FixedPoint = is_fixed<std::remove_cv_t<T>>::value;

// Counters and accumulators of the stream blocks.
template <int W>
using UInt = Fixed<W, 0, false>;
template <int W>
using Int = Fixed<W, 0, true>;

}  // namespace ceilnav::fp
