// Compile-time properties of the fixed-point types, plus a few value checks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "fixedpoint/fixed.hpp"

namespace ceilnav::fp {
namespace {

using Q4_4 = Fixed<8, 4, true>;    // s3.4
using UQ2_6 = Fixed<8, 6, false>;  // u2.6

// Storage and ranges.
static_assert(Q4_4::width == 8 && Q4_4::frac == 4 && Q4_4::int_bits == 4 && Q4_4::is_signed);
static_assert(Q4_4::min_raw == -128 && Q4_4::max_raw == 127);
static_assert(UQ2_6::min_raw == 0 && UQ2_6::max_raw == 255);
static_assert(Q4_4::resolution == 0.0625 && UQ2_6::resolution == 1.0 / 64);
static_assert(std::is_same_v<Q4_4::raw_type, std::int64_t>);
static_assert(std::is_same_v<UQ2_6::raw_type, std::uint64_t>);
static_assert(Int<64>::min_raw == std::numeric_limits<std::int64_t>::min());
static_assert(Int<64>::max_raw == std::numeric_limits<std::int64_t>::max());
static_assert(UInt<64>::max_raw == std::numeric_limits<std::uint64_t>::max());
static_assert(Int<1>::min_raw == -1 && Int<1>::max_raw == 0);
static_assert(UInt<1>::max_raw == 1);
static_assert(Fixed<4, -3, false>::int_bits == 7 && Fixed<4, -3, false>::resolution == 8.0);
static_assert(Fixed<4, 6, true>::int_bits == -2);
static_assert(std::is_same_v<UInt<8>, Fixed<8, 0, false, Rounding::truncate, Overflow::wrap>>);
static_assert(std::is_same_v<Q4_4::with_modes<Rounding::convergent, Overflow::saturate>,
                             Fixed<8, 4, true, Rounding::convergent, Overflow::saturate>>);
static_assert(FixedPoint<Q4_4> && FixedPoint<const UInt<3>> && !FixedPoint<int>);

// Widening rules: sums.
static_assert(std::is_same_v<SumType<UInt<8>, UInt<8>>, UInt<9>>);
static_assert(std::is_same_v<SumType<Int<8>, Int<3>>, Int<9>>);
static_assert(std::is_same_v<SumType<UInt<8>, Int<4>>, Int<10>>);  // unsigned gains a sign bit
static_assert(std::is_same_v<SumType<Int<4>, UInt<8>>, Int<10>>);
static_assert(std::is_same_v<SumType<Int<8>, UInt<4>>, Int<9>>);
static_assert(std::is_same_v<SumType<Q4_4, UQ2_6>, Fixed<11, 6, true>>);  // i = max(4, 3) + 1
static_assert(std::is_same_v<SumType<Fixed<4, -2, false>, Fixed<4, 2, false>>,
                             Fixed<9, 2, false>>);  // i = max(6, 2) + 1
static_assert(std::is_same_v<SumType<UInt<63>, UInt<63>>, UInt<64>>);
// Differences are always signed.
static_assert(std::is_same_v<DifferenceType<UInt<8>, UInt<8>>, Int<9>>);
static_assert(std::is_same_v<DifferenceType<UInt<8>, Int<4>>, Int<10>>);
static_assert(std::is_same_v<DifferenceType<Int<5>, Int<5>>, Int<6>>);
static_assert(std::is_same_v<NegateType<UInt<5>>, Int<6>>);
static_assert(std::is_same_v<NegateType<Q4_4>, Fixed<9, 4, true>>);
// Products.
static_assert(std::is_same_v<ProductType<Q4_4, UQ2_6>, Fixed<16, 10, true>>);
static_assert(std::is_same_v<ProductType<UInt<32>, UInt<32>>, UInt<64>>);
static_assert(
    std::is_same_v<ProductType<Fixed<4, -2, false>, Fixed<3, 5, false>>, Fixed<7, 3, false>>);
// Results are exact, so they carry the default modes.
static_assert(
    std::is_same_v<decltype(Q4_4::with_modes<Rounding::half_up, Overflow::saturate>{} + Q4_4{}),
                   Fixed<9, 4, true>>);

// Constant evaluation works end to end.
static_assert((UInt<8>::from_raw(255) + UInt<8>::from_raw(255)).raw() == 510);
static_assert((Int<4>::from_raw(-8) * Int<4>::from_raw(-8)).raw() == 64);
static_assert(Q4_4::from_double(1.03125).raw() == 16);  // 16.5 LSB truncates
static_assert(Q4_4::with_modes<Rounding::half_up, Overflow::wrap>::from_double(1.03125).raw() ==
              17);
static_assert(
    convert<Fixed<4, 1, true, Rounding::truncate, Overflow::saturate>>(Q4_4::from_raw(127)).raw() ==
    7);
static_assert(UInt<3>::from_raw(5) > Int<2>::from_raw(-1));
static_assert(Fixed<8, 4, false>::from_raw(24) == Fixed<4, 1, false>::from_raw(3));  // 1.5

TEST(FixedTraits, FromRawWrapsIntoWidth) {
  EXPECT_EQ(UInt<8>::from_raw(-1).raw(), 255u);
  EXPECT_EQ(UInt<8>::from_raw(256 + 7).raw(), 7u);
  EXPECT_EQ(Int<8>::from_raw(128).raw(), -128);
  EXPECT_EQ(Int<8>::from_raw(255).raw(), -1);
  EXPECT_EQ(UInt<64>::from_raw(std::int64_t{-1}).raw(), std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(Int<64>::from_raw(std::numeric_limits<std::uint64_t>::max()).raw(), -1);
}

TEST(FixedTraits, ToDoubleScalesByResolution) {
  EXPECT_EQ(Q4_4::from_raw(-3).to_double(), -0.1875);
  using Coarse = Fixed<4, -3, false>;
  using Fine = Fixed<4, 6, true>;
  EXPECT_EQ(Coarse::from_raw(5).to_double(), 40.0);
  EXPECT_EQ(Fine::from_raw(-8).to_double(), -0.125);
  EXPECT_EQ(Q4_4::max_value().to_double(), 7.9375);
  EXPECT_EQ(Q4_4::min_value().to_double(), -8.0);
}

TEST(FixedTraits, FromDoubleSpecialValues) {
  using Sat = Fixed<8, 4, true, Rounding::truncate, Overflow::saturate>;
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(Sat::from_double(std::nan("")).raw(), 0);
  EXPECT_EQ(Sat::from_double(inf).raw(), 127);
  EXPECT_EQ(Sat::from_double(-inf).raw(), -128);
  EXPECT_EQ(Q4_4::from_double(inf).raw(), 0);
  EXPECT_EQ(Sat::from_double(1e300).raw(), 127);
  EXPECT_EQ(Sat::from_double(-1e-300).raw(), -1);  // floor of a tiny negative value
  using SatHalfUp = Sat::with_modes<Rounding::half_up, Overflow::saturate>;
  EXPECT_EQ(SatHalfUp::from_double(-1e-300).raw(), 0);
  EXPECT_EQ(Sat::from_double(std::numeric_limits<double>::denorm_min()).raw(), 0);
  EXPECT_EQ(Q4_4::from_double(4096.0 + 1.0).raw(), 16);  // wraps: 65552 mod 256
}

TEST(FixedTraits, WideValuesStayExact) {
  const auto big = UInt<64>::from_raw(std::numeric_limits<std::uint64_t>::max());
  const auto one = UInt<1>::from_raw(1);
  EXPECT_TRUE(big > UInt<63>::max_value());
  EXPECT_TRUE(Int<64>::min_value() < Int<63>::min_value());
  // Frac far apart: the comparison must not lose the low bits.
  using Tiny = Fixed<64, 300, true>;
  using Huge = Fixed<2, -300, false>;
  EXPECT_TRUE(Tiny::from_raw(1) > UInt<1>{});
  EXPECT_TRUE(Tiny::from_raw(-1) < UInt<1>{});
  EXPECT_TRUE(Tiny::from_raw(0) == UInt<1>{});
  EXPECT_TRUE(Huge::from_raw(1) > big);
  EXPECT_TRUE(Huge::from_raw(0) < one);
  auto acc = UInt<64>::from_raw(std::numeric_limits<std::uint64_t>::max() - 1);
  acc += one;
  EXPECT_EQ(acc.raw(), std::numeric_limits<std::uint64_t>::max());
  acc += one;  // wraps
  EXPECT_EQ(acc.raw(), 0u);
  auto sat = UInt<64>::with_modes<Rounding::truncate, Overflow::saturate>::max_value();
  sat += one;
  EXPECT_EQ(sat.raw(), std::numeric_limits<std::uint64_t>::max());
  sat -= UInt<64>::max_value();
  sat -= one;
  EXPECT_EQ(sat.raw(), 0u);
}

TEST(FixedTraits, CompoundAssignmentRequantisesWithOwnModes) {
  using Acc = Fixed<8, 2, true, Rounding::convergent, Overflow::saturate>;
  auto acc = Acc::from_raw(4);             // 1.0
  acc += Fixed<8, 4, false>::from_raw(6);  // + 0.375 = 1.375 -> 5.5 LSB -> 6 (even)
  EXPECT_EQ(acc.raw(), 6);
  acc *= Fixed<8, 4, true>::from_raw(-24);  // 1.5 * -1.5 = -2.25 -> -9 LSB
  EXPECT_EQ(acc.raw(), -9);
  acc *= Int<8>::from_raw(100);  // saturates
  EXPECT_EQ(acc.raw(), -128);
  acc -= Int<8>::from_raw(-127);  // -32 + 127 = 95 -> 380 LSB, saturates
  EXPECT_EQ(acc.raw(), 127);
}

// The tables in docs/fixedpoint.md.
TEST(FixedTraits, DocumentedRoundingAndOverflowExamples) {
  using Half = Fixed<8, 2, true>;  // holds the quarter-valued inputs exactly
  const double inputs[] = {2.5, 3.5, -2.5, 2.25, -2.75};
  const std::int64_t truncate[] = {2, 3, -3, 2, -3};
  const std::int64_t half_up[] = {3, 4, -2, 2, -3};
  const std::int64_t convergent[] = {2, 4, -2, 2, -3};
  for (int i = 0; i < 5; ++i) {
    const auto x = Half::from_double(inputs[i]);
    EXPECT_EQ(convert<Int<8>>(x).raw(), truncate[i]) << inputs[i];
    EXPECT_EQ((convert<Int<8>::with_modes<Rounding::half_up, Overflow::wrap>>(x).raw()), half_up[i])
        << inputs[i];
    EXPECT_EQ((convert<Int<8>::with_modes<Rounding::convergent, Overflow::wrap>>(x).raw()),
              convergent[i])
        << inputs[i];
  }
  using SatInt8 = Int<8>::with_modes<Rounding::truncate, Overflow::saturate>;
  using SatUInt8 = UInt<8>::with_modes<Rounding::truncate, Overflow::saturate>;
  EXPECT_EQ(convert<Int<8>>(Int<16>::from_raw(130)).raw(), -126);
  EXPECT_EQ(convert<SatInt8>(Int<16>::from_raw(130)).raw(), 127);
  EXPECT_EQ(convert<UInt<8>>(Int<16>::from_raw(-1)).raw(), 255u);
  EXPECT_EQ(convert<SatUInt8>(Int<16>::from_raw(-1)).raw(), 0u);
}

}  // namespace
}  // namespace ceilnav::fp
