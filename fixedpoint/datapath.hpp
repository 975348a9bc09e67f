// The datapath formats of the stream blocks: every accumulator, counter and
// sum width of frame_check .. class_moments is derived here, once, from the
// largest frame the device accepts, with a compile-time proof that the
// largest value it can hold fits (and that the width is the smallest that
// does). The C++ cycle models (stream/) use these constants; the RTL
// (rtl_model/) reads the same numbers from the generated SystemVerilog
// package ceilnav_widths_pkg (tools/regmap_gen writes it from this header).
// See docs/fixedpoint.md, "Datapath formats".
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace ceilnav::fp::datapath {

// Largest frame: 2048 x 2048 (covers 1920x1080); 8-bit pixels.
inline constexpr int kCoordBits = 11;                     // x in [0, 2047], y in [0, 2047]
inline constexpr uint32_t kMaxWidth = 1u << kCoordBits;   // pixels per line
inline constexpr uint32_t kMaxHeight = 1u << kCoordBits;  // lines per frame
inline constexpr int kPixelBits = 8;
inline constexpr int kMomentCount = 6;  // m00 m10 m01 m20 m11 m02

// Number of bits needed to hold the unsigned value v.
constexpr int bits_for(uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n == 0 ? 1 : n;
}
// v fits in `bits` bits and needs all of them.
constexpr bool exact_width(uint64_t v, int bits) {
  return bits_for(v) == bits;
}

// Error and frame counters of frame_check, cycle and loss counters: 32 bits,
// saturating at 2^32 - 1 (a documented limit, not a proof: they count since
// reset).
inline constexpr int kCounterBits = 32;

// moment_gen: cascaded row (A1..A3) and frame (F00..F02) accumulators and
// the combine registers, for the grey (LUT remap) and the mask image.
namespace moment_gen {

inline constexpr uint64_t kW = kMaxWidth;
inline constexpr uint64_t kH = kMaxHeight;
inline constexpr uint64_t kGreyMax = (1u << kPixelBits) - 1;

// Cascade weights: a pixel at u = W - x (1..W) adds 1, u, u(u+1)/2 to the
// three row accumulators; their sums over a row of n pixels are at most:
constexpr uint64_t sum1(uint64_t n) {
  return n;
}
constexpr uint64_t sum2(uint64_t n) {
  return n * (n + 1) / 2;
}
constexpr uint64_t sum3(uint64_t n) {
  return n * (n + 1) * (n + 2) / 6;
}

// Index order of the frame accumulators (F_ab: weight u^(a) v^(b) with
// u^(1) = u, u^(2) = u(u+1)/2), the same order as kM00..kM02.
inline constexpr int kRowCount = 3;  // A1 = sum I, A2 = sum I u, A3 = sum I u(u+1)/2

// Largest row / frame accumulator per unit pixel value (all pixels 1).
inline constexpr std::array<uint64_t, kRowCount> kRowWeightMax = {sum1(kW), sum2(kW), sum3(kW)};
inline constexpr std::array<uint64_t, kMomentCount> kFrameWeightMax = {
    sum1(kW) * sum1(kH), sum2(kW) * sum1(kH), sum1(kW) * sum2(kH),
    sum3(kW) * sum1(kH), sum2(kW) * sum2(kH), sum1(kW) * sum3(kH)};
// Largest moment per unit pixel value: sum over the frame of x^a y^b.
inline constexpr std::array<uint64_t, kMomentCount> kMomentWeightMax = {
    kW * kH,
    kH*(kW*(kW - 1) / 2),
    kW*(kH*(kH - 1) / 2),
    kH*((kW - 1) * kW * (2 * kW - 1) / 6),
    (kW * (kW - 1) / 2) * (kH * (kH - 1) / 2),
    kW*((kH - 1) * kH * (2 * kH - 1) / 6)};

template <std::size_t N>
constexpr std::array<int, N> widths(const std::array<uint64_t, N>& max, uint64_t scale) {
  std::array<int, N> w{};
  for (std::size_t i = 0; i < N; ++i) w[i] = bits_for(max[i] * scale);
  return w;
}
template <std::size_t N>
constexpr std::array<int, N> wider(const std::array<int, N>& a, const std::array<int, N>& b) {
  std::array<int, N> w{};
  for (std::size_t i = 0; i < N; ++i) w[i] = a[i] > b[i] ? a[i] : b[i];
  return w;
}
template <std::size_t N>
constexpr int largest(const std::array<int, N>& a) {
  int m = 0;
  for (int v : a) m = v > m ? v : m;
  return m;
}

inline constexpr std::array<int, kRowCount> kGreyRowBits = widths(kRowWeightMax, kGreyMax);
inline constexpr std::array<int, kRowCount> kMaskRowBits = widths(kRowWeightMax, 1);
inline constexpr std::array<int, kMomentCount> kGreyFrameBits = widths(kFrameWeightMax, kGreyMax);
inline constexpr std::array<int, kMomentCount> kMaskFrameBits = widths(kFrameWeightMax, 1);
// Output port widths (unchanged from the bit-plane design).
inline constexpr std::array<int, kMomentCount> kGreyMomentBits = widths(kMomentWeightMax, kGreyMax);
inline constexpr std::array<int, kMomentCount> kMaskMomentBits = widths(kMomentWeightMax, 1);
// Combine shift registers: hold F_ab on entry and m_ab on exit.
inline constexpr std::array<int, kMomentCount> kGreyWorkBits =
    wider(kGreyFrameBits, kGreyMomentBits);
inline constexpr std::array<int, kMomentCount> kMaskWorkBits =
    wider(kMaskFrameBits, kMaskMomentBits);
// Bit-serial passes run over every bit of the widest work register.
inline constexpr int kGreyPassBits = largest(kGreyWorkBits);
inline constexpr int kMaskPassBits = largest(kMaskWorkBits);
inline constexpr int kDimBits = bits_for(kW);  // W, H in 1 .. 2048

static_assert(kW == kH, "the RTL sizes W and H alike");
static_assert(kGreyRowBits == std::array<int, 3>{19, 29, 39});
static_assert(kMaskRowBits == std::array<int, 3>{12, 22, 31});
static_assert(kGreyFrameBits == std::array<int, 6>{30, 40, 40, 50, 50, 50});
static_assert(kMaskFrameBits == std::array<int, 6>{23, 33, 33, 42, 43, 42});
static_assert(kGreyMomentBits == std::array<int, 6>{30, 40, 40, 51, 50, 51});
static_assert(kMaskMomentBits == std::array<int, 6>{23, 32, 32, 43, 42, 43});
static_assert(kGreyWorkBits == std::array<int, 6>{30, 40, 40, 51, 50, 51});
static_assert(kMaskWorkBits == std::array<int, 6>{23, 33, 33, 43, 43, 43});
static_assert(kGreyPassBits == 51 && kMaskPassBits == 43 && kDimBits == 12);
// Every accumulator and intermediate fits a uint64_t with room to spare.
static_assert(kGreyPassBits < 64);

}  // namespace moment_gen

// run_scanner: per-run sums and per-row / per-frame run counts.
namespace run_scanner {

inline constexpr uint64_t kW = kMaxWidth;
inline constexpr uint64_t kH = kMaxHeight;
inline constexpr uint64_t kGreyMax = (1u << kPixelBits) - 1;
// A run plus its margins is clipped to the line: at most W pixels.
inline constexpr int kSumWBits = bits_for(kGreyMax * kW);
inline constexpr int kSumXwBits = bits_for(kGreyMax * (kW * (kW - 1) / 2));
// Runs on one row: at most ceil(W / 2) (a run needs a following 0 or the EOL).
inline constexpr int kRowRunCountBits = bits_for((kW + 1) / 2);
inline constexpr int kFrameRunCountBits = bits_for(kH * ((kW + 1) / 2));
inline constexpr int kRunLengthBits = bits_for(kW);  // a run is at most W pixels
static_assert(kSumWBits == 19 && kSumXwBits == 29);
static_assert(kRowRunCountBits == 11 && kFrameRunCountBits == 22 && kRunLengthBits == 12);

}  // namespace run_scanner

// edge: the edge detector's differences, magnitudes and per-frame counts.
namespace edge {

inline constexpr uint64_t kGreyMax = (1u << kPixelBits) - 1;
// Horizontal / vertical difference p_i - p_{i-1}: -255 .. 255; |d| <= 255.
inline constexpr int kDiffMagBits = bits_for(kGreyMax);
// Sobel: gx, gy = (column/row with weights 1 2 1) - (the opposite one): at
// most 4 * 255 = 1020 in magnitude, a sign bit more as two's complement;
// |gx| + |gy| <= 2040. The beat's 12-bit magnitude field is "saturated to
// 4095", which the largest value never reaches.
inline constexpr uint64_t kSobelGMax = 4 * kGreyMax;
inline constexpr int kSobelGBits = bits_for(kSobelGMax) + 1;
inline constexpr int kSobelMagBits = bits_for(2 * kSobelGMax);
inline constexpr int kMagFieldBits = 12;   // beat field magnitude[11:0]
inline constexpr int kThresholdBits = 12;  // EDGE_CONTROL.THRESHOLD
// Edges per frame: at most one per pixel.
inline constexpr int kFrameEdgeCountBits = bits_for(uint64_t{kMaxWidth} * kMaxHeight);
static_assert(kDiffMagBits == 8 && kSobelGBits == 11 && kSobelMagBits == 11);
static_assert(exact_width(2 * kSobelGMax, kSobelMagBits) && kSobelMagBits < kMagFieldBits);
static_assert(2 * kSobelGMax < (1u << kMagFieldBits) - 1, "the magnitude never saturates");
static_assert(kFrameEdgeCountBits == 23 && kFrameEdgeCountBits < 32,
              "the trailer's 32-bit edge count never saturates");

}  // namespace edge

// histogram: a bin counts at most every pixel of the largest frame.
namespace histogram {

inline constexpr int kBinBits = bits_for(uint64_t{kMaxWidth} * kMaxHeight);
static_assert(kBinBits == 23);

}  // namespace histogram

// hough: the weight of a vote (seed 002 eq. 18, w = (row - r) / s with r
// counted from the bottom: row - r = y + 1 for y counted from the top) is
// (y + 1) >> weight_shift, at most 2^kCoordBits: kWeightBits, exact (no
// saturation needed). The accumulator cells have a width chosen per
// configuration (RTL parameter AccBits) and saturate; the per-frame counters
// are kCounterBits wide and saturate. rho index arithmetic (s1.14 table,
// fixedpoint/hough_trig.hpp): x C + y S + (W << 14) + 2^(13 + rho_shift) with
// x, y <= 2^kCoordBits - 1, |C|, |S| <= 2^14, the bias W < 2^12 (register
// field) and rho_shift <= 7 needs kRhoSumBits signed bits.
namespace hough {

inline constexpr int kWeightBits = bits_for(kMaxHeight);  // (y + 1) for y <= 2047
inline constexpr int kTrigFrac = 14;
inline constexpr int kWidthFieldBits = 12;
inline constexpr int kMaxRhoShift = 7;
inline constexpr uint64_t kRhoSumMax =
    ((2 * (uint64_t{kMaxWidth} - 1) + ((uint64_t{1} << kWidthFieldBits) - 1)) << kTrigFrac) +
    (uint64_t{1} << (kTrigFrac - 1 + kMaxRhoShift));
inline constexpr int kRhoSumBits = bits_for(kRhoSumMax) + 1;  // + sign
static_assert(kWeightBits == 12 && kRhoSumBits == 29);

}  // namespace hough

// class_moments: for frames up to 2^k x 2^k the sums of x^a y^b over a full
// frame need {2k+1, 3k-1, 3k-1, 4k-1, 4k-2, 4k-1} bits -- the maxima of the
// mask moments of moment_gen (a class mask of all ones is the worst case).
namespace class_moments {

constexpr std::array<int, kMomentCount> moment_bits(int k) {
  return {2 * k + 1, 3 * k - 1, 3 * k - 1, 4 * k - 1, 4 * k - 2, 4 * k - 1};
}
inline constexpr std::array<int, kMomentCount> kMomentBits = moment_bits(kCoordBits);
static_assert(kMomentBits == moment_gen::kMaskMomentBits);
static_assert(kMomentBits == std::array<int, kMomentCount>{23, 32, 32, 43, 42, 43});
// Pixel terms x^2, x y, y^2 <= (2^k - 1)^2: 2k bits; x, y: k bits; 2x + 1: k + 1.
inline constexpr int kTermBits = 2 * kCoordBits;
static_assert(exact_width(uint64_t{kMaxWidth - 1} * (kMaxHeight - 1), kTermBits));
// Window bounds: 0 .. 2^k (one more bit than a coordinate).
inline constexpr int kWindowBits = kCoordBits + 1;

}  // namespace class_moments

}  // namespace ceilnav::fp::datapath
