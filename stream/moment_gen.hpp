// moment_gen: m00 m10 m01 m20 m11 m02 of the grey image (LUT remap) and of the
// mask. Counters and adders, no multiplier on the pixel path (seed 003's
// spirit, not its bit planes): cascaded accumulators along each row and down
// the frame give sums of I weighted by u = W - x and v = H - y and by
// u(u+1)/2, v(v+1)/2, u v; a bit-serial combine after EOF turns them into the
// moments with W and H. See docs/blocks/moment_gen.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "stream/beat.hpp"
#include "stream/limits.hpp"
#include "stream/results.hpp"

namespace ceilnav::stream {

namespace moment_gen_widths {

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

}  // namespace moment_gen_widths

// One word of the moments on the result-word output (see MomentGen::mom_wr).
struct MomentWord {
  bool valid = false;
  uint8_t index = 0;  // register word: 6 * {grey lo, grey hi, mask lo, mask hi} + MomentIndex
  uint32_t data = 0;
  friend bool operator==(const MomentWord&, const MomentWord&) = default;
};

class MomentGen {
 public:
  // The moments as register words: kMomentWords words, written out one per
  // edge for kMomentWords edges after the done edge, in kWordOrder (widest
  // significant width first: the RTL holds them in a chain of slots that
  // shifts towards the output, each slot as wide as its widest content).
  static constexpr int kMomentWords = 4 * kMomentCount;
  static constexpr std::array<uint8_t, kMomentWords> kWordOrder = {
      1, 2, 3, 4, 5, 13, 14, 15, 16, 17, 0, 12, 9, 11, 10, 21, 23, 22, 7, 8, 6, 18, 19, 20};
  // Word w of a result set: lo (w / 6 even) or hi 32 bits of grey (w < 12) or
  // mask moment w % 6.
  static uint32_t moment_word(const MomentResults& r, int w);

  // Edges from the EOF pixel's edge e to the edge that raises done():
  // the last frame accumulator settles at e+3 (the cascade is skewed one edge
  // per stage), the snapshots load at e+2..e+4, the grey and the mask pass
  // (one serial unit each, side by side) shift at e+5 .. e+5+kPassBits, then
  // the results load.
  static constexpr int kSkewCycles = 4;
  static constexpr int kPassBits =
      moment_gen_widths::kGreyPassBits > moment_gen_widths::kMaskPassBits
          ? moment_gen_widths::kGreyPassBits
          : moment_gen_widths::kMaskPassBits;
  static constexpr int kCombineCycles = kSkewCycles + 1 + kPassBits + 1;
  static_assert(kCombineCycles == 57);

  // Fast path state: plain per-frame sums (software only, no hardware meaning).
  struct FrameSums {
    std::array<uint64_t, kMomentCount> grey{};
    std::array<uint64_t, kMomentCount> mask{};
  };

  MomentGen() { reset(); }

  // Asynchronous active-low reset: all registers to zero, no frame open.
  void reset();

  // One rising clock edge; samples the LutBeat port (remap, mask, pix.*).
  // Throws std::logic_error if pix.x / pix.y differ from the block's counters
  // or the frame is not rectangular (frame_check rules both out).
  void clock(const LutBeat& in);

  // Registered outputs.
  bool done() const { return done_q_; }  // one-cycle pulse: results() just updated
  // The result-word output: valid for the kMomentWords cycles from done() on.
  MomentWord mom_wr() const {
    if (!wr_active_q_) return {};
    const int w = kWordOrder[static_cast<size_t>(wr_step_q_)];
    return {true, static_cast<uint8_t>(w), moment_word(results_q_, w)};
  }
  const MomentResults& results() const { return results_q_; }  // last completed frame
  bool combine_busy() const { return combine_busy_q_; }
  // done() rises on the next edge (a function of registers only).
  bool done_next() const { return combine_busy_q_ && combine_left_q_ == 1; }
  // Frames whose results were discarded because their EOF came fewer than
  // kCombineCycles edges after the previous accepted EOF (only frames of
  // fewer than kCombineCycles pixels plus blanking can do that). Saturating.
  uint32_t overrun_count() const { return overrun_count_q_; }

  // Fast frame-at-a-time path, equal to clock()-ing the frame. Rows may come in
  // any order; mask bytes: nonzero = 1.
  static void accumulate_row(FrameSums& sums, uint32_t y, const uint8_t* remap, const uint8_t* mask,
                             uint32_t width);
  static MomentResults finish(const FrameSums& sums) { return {sums.grey, sums.mask}; }

 private:
  // Row accumulators A1..A3 and frame accumulators F00 F10 F01 F20 F11 F02
  // of one image (grey or mask), each kept to its RTL width.
  struct Cascade {
    std::array<uint64_t, moment_gen_widths::kRowCount> a{};
    std::array<uint64_t, kMomentCount> f{};
  };
  template <bool kGrey>
  static void add_pixel(Cascade& c, uint64_t value, bool row_start);
  template <bool kGrey>
  static void end_row(Cascade& c, bool first_row);
  template <bool kGrey>
  static std::array<uint64_t, kMomentCount> combine(const Cascade& c, uint64_t w, uint64_t h);

  // Pixel path.
  bool frame_open_q_ = false;
  bool row_start_q_ = false;  // the next pixel starts a row
  bool first_row_q_ = false;  // the next pixel is in the frame's first row
  uint32_t x_q_ = 0;          // position check only (the RTL checks by assertion)
  uint32_t y_q_ = 0;
  uint32_t width_q_ = 0;  // row length of the open frame, 0 until its first EOL
  Cascade grey_q_{};
  Cascade mask_q_{};

  // Combine. The model forms the moments at the EOF edge (exact in 64-bit
  // integers) and shows them at the done edge, as the RTL's serial unit does.
  bool combine_busy_q_ = false;
  int combine_left_q_ = 0;  // edges until done, while busy
  MomentResults pending_q_{};

  MomentResults results_q_{};
  bool done_q_ = false;
  bool wr_active_q_ = false;  // result words being written out
  int wr_step_q_ = 0;         // position in kWordOrder
  uint32_t overrun_count_q_ = 0;
};

}  // namespace ceilnav::stream
