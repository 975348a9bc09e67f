// Random bit-true comparison against SystemC's sc_fixed / sc_ufixed (IEEE
// 1666 fixed-point datatypes), the de-facto reference for HLS arithmetic.
// Mode mapping: truncate = SC_TRN, half_up = SC_RND, convergent = SC_RND_CONV,
// wrap = SC_WRAP, saturate = SC_SAT; sc iwl = Width - Frac.
#define SC_INCLUDE_FX
#include <systemc>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

#include "fixedpoint/fixed.hpp"

// Only the datatypes are used, but libsystemc's main() needs this symbol to
// link; gtest_main's main() is the one that runs.
int sc_main(int argc, char* argv[]) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

namespace ceilnav::fp {
namespace {

constexpr long kCasesPerCombination = 100000;
constexpr std::uint64_t kBaseSeed = 0x5eed'ce11'0000'0001;

constexpr sc_dt::sc_q_mode sc_q_mode_of(Rounding r) {
  switch (r) {
    case Rounding::truncate:
      return sc_dt::SC_TRN;
    case Rounding::half_up:
      return sc_dt::SC_RND;
    case Rounding::convergent:
      return sc_dt::SC_RND_CONV;
  }
  return sc_dt::SC_TRN;
}

constexpr sc_dt::sc_o_mode sc_o_mode_of(Overflow o) {
  return o == Overflow::wrap ? sc_dt::SC_WRAP : sc_dt::SC_SAT;
}

// The SystemC type with T's word, scale and modes.
template <FixedPoint T>
using ScOf = std::conditional_t<
    T::is_signed,
    sc_dt::sc_fixed<T::width, T::int_bits, sc_q_mode_of(T::rounding), sc_o_mode_of(T::overflow)>,
    sc_dt::sc_ufixed<T::width, T::int_bits, sc_q_mode_of(T::rounding), sc_o_mode_of(T::overflow)>>;

// Bits 0 (LSB) .. width-1 of an sc_fxnum are its raw word.
template <FixedPoint T>
ScOf<T> to_sc(const T& x) {
  ScOf<T> s;
  s.range(T::width - 1, 0) = static_cast<sc_dt::uint64>(x.raw());
  return s;
}

template <FixedPoint T>
std::int64_t sc_raw(const ScOf<T>& s) {
  // Through from_raw to sign-extend; the library's wrap is exhaustively tested.
  return static_cast<std::int64_t>(
      T::from_raw(static_cast<std::uint64_t>(s.range(T::width - 1, 0).to_uint64())).raw());
}

template <FixedPoint T>
std::string describe() {
  std::ostringstream os;
  os << (T::is_signed ? "sc_fixed<" : "sc_ufixed<") << T::width << "," << T::int_bits << ","
     << sc_q_mode_of(T::rounding) << "," << sc_o_mode_of(T::overflow) << ">";
  return os.str();
}

// Raw words: uniform over the word, and a quarter of them near 0, min and max.
template <FixedPoint T>
T random_value(std::mt19937_64& rng) {
  const std::uint64_t bits = rng();
  if ((bits & 3) != 0) return T::from_raw(rng());
  const auto delta = static_cast<std::int64_t>((bits >> 2) % 9) - 4;
  const std::int64_t bases[] = {0, static_cast<std::int64_t>(T::min_raw),
                                static_cast<std::int64_t>(T::max_raw)};
  // Unsigned sum: min_raw - 4 of a 64-bit word wraps (int64 would overflow).
  return T::from_raw(static_cast<std::uint64_t>(bases[(bits >> 8) % 3]) +
                     static_cast<std::uint64_t>(delta));
}

struct Tally {
  long checks = 0;
  long failures = 0;
  std::string first_failure;

  void check(std::int64_t got, std::int64_t want, std::uint64_t seed, long case_index,
             const std::string& what) {
    ++checks;
    if (got == want) return;
    if (failures++ != 0) return;
    std::ostringstream os;
    os << what << ": got raw " << got << ", SystemC raw " << want << " (seed " << seed << ", case "
       << case_index << ")";
    first_failure = os.str();
  }
};

void expect_clean(const Tally& tally) {
  std::printf("%ld checks\n", tally.checks);
  EXPECT_GT(tally.checks, 0);
  EXPECT_EQ(tally.failures, 0) << "of " << tally.checks << "; first: " << tally.first_failure;
}

// Calls fn with T under each of the six rounding x overflow combinations.
template <FixedPoint T, class Fn>
void for_each_modes_of(Fn&& fn) {
  fn(static_cast<typename T::template with_modes<Rounding::truncate, Overflow::wrap>*>(nullptr));
  fn(static_cast<typename T::template with_modes<Rounding::half_up, Overflow::wrap>*>(nullptr));
  fn(static_cast<typename T::template with_modes<Rounding::convergent, Overflow::wrap>*>(nullptr));
  fn(static_cast<typename T::template with_modes<Rounding::truncate, Overflow::saturate>*>(
      nullptr));
  fn(static_cast<typename T::template with_modes<Rounding::half_up, Overflow::saturate>*>(nullptr));
  fn(static_cast<typename T::template with_modes<Rounding::convergent, Overflow::saturate>*>(
      nullptr));
}

std::uint64_t seed_for(long combination) {
  return kBaseSeed + static_cast<std::uint64_t>(combination);
}

// ---- the helpers themselves ---------------------------------------------------

template <FixedPoint T>
void check_raw_round_trip(Tally& tally, long combination) {
  const std::uint64_t seed = seed_for(combination);
  std::mt19937_64 rng(seed);
  for (long i = 0; i < 1000; ++i) {
    const T x = random_value<T>(rng);
    const ScOf<T> s = to_sc(x);
    tally.check(sc_raw<T>(s), static_cast<std::int64_t>(x.raw()), seed, i,
                "raw round trip " + describe<T>());
    // Independent of the bit helpers: the value SystemC sees (exact, <= 53 bits).
    if constexpr (T::width <= 53) {
      tally.check(s.to_double() == x.to_double(), true, seed, i, "value " + describe<T>());
    }
  }
}

TEST(FixedSystemc, RawBitsMapToTheSameValue) {
  Tally tally;
  check_raw_round_trip<Fixed<8, 4, true>>(tally, 0);
  check_raw_round_trip<Fixed<12, 14, true>>(tally, 1);
  check_raw_round_trip<Fixed<6, -2, false>>(tally, 2);
  check_raw_round_trip<Fixed<53, 20, true>>(tally, 3);
  check_raw_round_trip<Fixed<64, 40, true>>(tally, 4);
  check_raw_round_trip<Fixed<64, 32, false>>(tally, 5);
  expect_clean(tally);
}

// ---- requantisation: wide source into a narrow target ------------------------

template <FixedPoint Source, FixedPoint TargetBase>
void check_requantise(Tally& tally, long shape) {
  long mode_index = 0;
  for_each_modes_of<TargetBase>([&]<class T>(T*) {
    const std::uint64_t seed = seed_for(shape * 16 + mode_index++);
    std::mt19937_64 rng(seed);
    const std::string what = describe<Source>() + " -> " + describe<T>();
    for (long i = 0; i < kCasesPerCombination; ++i) {
      const Source x = random_value<Source>(rng);
      const ScOf<T> s = to_sc(x);  // SystemC requantises on assignment
      tally.check(static_cast<std::int64_t>(convert<T>(x).raw()), sc_raw<T>(s), seed, i, what);
    }
  });
}

TEST(FixedSystemc, RequantiseMatchesScFixedAssignment) {
  Tally tally;
  check_requantise<Fixed<20, 11, true>, Fixed<8, 4, true>>(tally, 0);
  check_requantise<Fixed<24, 10, false>, Fixed<10, 3, false>>(tally, 1);
  check_requantise<Fixed<16, 8, true>, Fixed<6, 2, false>>(tally, 2);     // signed into unsigned
  check_requantise<Fixed<30, 20, true>, Fixed<12, 14, true>>(tally, 3);   // iwl < 0
  check_requantise<Fixed<16, 4, true>, Fixed<6, -2, true>>(tally, 4);     // iwl > wl
  check_requantise<Fixed<64, 40, true>, Fixed<32, 16, true>>(tally, 5);   // 64-bit source
  check_requantise<Fixed<64, 48, true>, Fixed<64, 32, false>>(tally, 6);  // 64-bit target
  check_requantise<Fixed<12, 2, false>, Fixed<16, 6, true>>(tally, 7);    // widening only
  expect_clean(tally);
}

// ---- from double -----------------------------------------------------------

template <FixedPoint TargetBase>
void check_from_double(Tally& tally, long shape) {
  long mode_index = 0;
  for_each_modes_of<TargetBase>([&]<class T>(T*) {
    const std::uint64_t seed = seed_for(1000 + shape * 16 + mode_index++);
    std::mt19937_64 rng(seed);
    const std::string what = "from_double " + describe<T>();
    const double lo = T::min_value().to_double();
    const double hi = T::max_value().to_double();
    std::uniform_real_distribution<double> anywhere(lo - (hi - lo) / 2, hi + (hi - lo) / 2);
    std::uniform_int_distribution<int> eighths(0, 7);
    for (long i = 0; i < kCasesPerCombination; ++i) {
      double x = anywhere(rng);
      if (i % 2 == 0) {
        // On the grid, halfway between, or at an eighth of an LSB (the edges
        // every rounding mode is about), from 1.5x the range.
        const double lsbs = std::floor(x / T::resolution);
        x = (lsbs + eighths(rng) / 8.0) * T::resolution;
      }
      const ScOf<T> s(x);
      tally.check(static_cast<std::int64_t>(T::from_double(x).raw()), sc_raw<T>(s), seed, i,
                  what + " of " + std::to_string(x));
    }
  });
}

TEST(FixedSystemc, FromDoubleMatchesScFixedConstruction) {
  Tally tally;
  check_from_double<Fixed<8, 4, true>>(tally, 0);
  check_from_double<Fixed<10, 3, false>>(tally, 1);
  check_from_double<Fixed<12, 14, true>>(tally, 2);
  check_from_double<Fixed<6, -2, false>>(tally, 3);
  check_from_double<Fixed<40, 30, true>>(tally, 4);
  expect_clean(tally);
}

// ---- exact add / mul, then narrowing ----------------------------------------

template <FixedPoint A, FixedPoint B, FixedPoint NarrowBase>
void check_arith(Tally& tally, long shape) {
  using Sum = SumType<A, B>;
  using Prod = ProductType<A, B>;
  using Diff = DifferenceType<A, B>;
  long mode_index = 0;
  for_each_modes_of<NarrowBase>([&]<class T>(T*) {
    const bool first_mode = mode_index == 0;
    const std::uint64_t seed = seed_for(2000 + shape * 16 + mode_index++);
    std::mt19937_64 rng(seed);
    const std::string operands = describe<A>() + " , " + describe<B>();
    for (long i = 0; i < kCasesPerCombination; ++i) {
      const A a = random_value<A>(rng);
      const B b = random_value<B>(rng);
      const ScOf<A> sa = to_sc(a);
      const ScOf<B> sb = to_sc(b);
      // SystemC computes a + b as an arbitrary-precision sc_fxval.
      const sc_dt::sc_fxval sc_sum = sa + sb;
      const sc_dt::sc_fxval sc_prod = sa * sb;
      if (first_mode) {  // the exact results do not depend on T's modes
        tally.check(static_cast<std::int64_t>((a + b).raw()), sc_raw<Sum>(ScOf<Sum>(sc_sum)), seed,
                    i, "a+b " + operands);
        tally.check(static_cast<std::int64_t>((a * b).raw()), sc_raw<Prod>(ScOf<Prod>(sc_prod)),
                    seed, i, "a*b " + operands);
        tally.check(static_cast<std::int64_t>((a - b).raw()), sc_raw<Diff>(ScOf<Diff>(sa - sb)),
                    seed, i, "a-b " + operands);
      }
      tally.check(static_cast<std::int64_t>(convert<T>(a + b).raw()), sc_raw<T>(ScOf<T>(sc_sum)),
                  seed, i, "a+b " + operands + " -> " + describe<T>());
      tally.check(static_cast<std::int64_t>(convert<T>(a * b).raw()), sc_raw<T>(ScOf<T>(sc_prod)),
                  seed, i, "a*b " + operands + " -> " + describe<T>());
    }
  });
}

TEST(FixedSystemc, AddSubMulMatchScFixed) {
  Tally tally;
  check_arith<Fixed<10, 4, true>, Fixed<12, 8, false>, Fixed<8, 3, true>>(tally, 0);
  check_arith<Fixed<30, 10, true>, Fixed<30, 20, true>, Fixed<16, 6, true>>(tally, 1);
  check_arith<Fixed<16, 16, false>, Fixed<16, 0, false>, Fixed<12, 4, false>>(tally, 2);
  check_arith<Fixed<7, -3, false>, Fixed<9, 12, true>, Fixed<10, 5, true>>(tally, 3);
  expect_clean(tally);
}

}  // namespace
}  // namespace ceilnav::fp
