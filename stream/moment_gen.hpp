// moment_gen: m00 m10 m01 m20 m11 m02 of the grey image (LUT remap) and of the
// mask, built as in seed 003 eq. 20-28: the factors p_ab(x, y) = x^a y^b come
// from counters and adders, each bit plane of the pixel is ANDed with them
// into a per-plane accumulator F_k, and m_ab = sum_k 2^k F_k is formed once per
// frame by a sequential Horner unit. See docs/blocks/moment_gen.md.
#pragma once

#include <array>
#include <cstdint>

#include "fixedpoint/fixed.hpp"
#include "stream/beat.hpp"
#include "stream/limits.hpp"
#include "stream/results.hpp"

namespace ceilnav::stream {

namespace moment_gen_widths {

inline constexpr uint64_t kW = kMaxWidth;
inline constexpr uint64_t kH = kMaxHeight;

// Largest factor p_ab = x^a y^b, x <= W-1, y <= H-1 (order kM00..kM02).
inline constexpr std::array<uint64_t, kMomentCount> kFactorMax = {
    1, kW - 1, kH - 1, (kW - 1) * (kW - 1), (kW - 1) * (kH - 1), (kH - 1) * (kH - 1)};

// Largest plane sum F_k = sum over the frame of p_ab (every bit of the plane set).
inline constexpr std::array<uint64_t, kMomentCount> kPlaneSumMax = {
    kW * kH,                                  // sum 1
    kH*(kW*(kW - 1) / 2),                     // sum x
    kW*(kH*(kH - 1) / 2),                     // sum y
    kH*((kW - 1) * kW * (2 * kW - 1) / 6),    // sum x^2
    (kW*(kW - 1) / 2) * (kH * (kH - 1) / 2),  // sum x y
    kW*((kH - 1) * kH * (2 * kH - 1) / 6)};   // sum y^2

inline constexpr int kFactorBits[kMomentCount] = {bits_for(kFactorMax[0]), bits_for(kFactorMax[1]),
                                                  bits_for(kFactorMax[2]), bits_for(kFactorMax[3]),
                                                  bits_for(kFactorMax[4]), bits_for(kFactorMax[5])};
inline constexpr int kPlaneBits[kMomentCount] = {
    bits_for(kPlaneSumMax[0]), bits_for(kPlaneSumMax[1]), bits_for(kPlaneSumMax[2]),
    bits_for(kPlaneSumMax[3]), bits_for(kPlaneSumMax[4]), bits_for(kPlaneSumMax[5])};
// m_ab <= 255 * F_max (every pixel 255).
inline constexpr int kMomentBits[kMomentCount] = {
    bits_for(255 * kPlaneSumMax[0]), bits_for(255 * kPlaneSumMax[1]),
    bits_for(255 * kPlaneSumMax[2]), bits_for(255 * kPlaneSumMax[3]),
    bits_for(255 * kPlaneSumMax[4]), bits_for(255 * kPlaneSumMax[5])};

static_assert(kFactorBits[kM10] == kCoordBits && kFactorBits[kM20] == 2 * kCoordBits);
static_assert(kPlaneBits[kM00] == 23 && kPlaneBits[kM10] == 32 && kPlaneBits[kM01] == 32);
static_assert(kPlaneBits[kM20] == 43 && kPlaneBits[kM11] == 42 && kPlaneBits[kM02] == 43);
static_assert(kMomentBits[kM00] == 30 && kMomentBits[kM10] == 40 && kMomentBits[kM20] == 51);
static_assert(kMomentBits[kM11] == 50 && kMomentBits[kM02] == 51);

}  // namespace moment_gen_widths

class MomentGen {
 public:
  static constexpr int kPlanes = kPixelBits;
  // Horner unit: one plane per cycle (MSB first), all 12 moments in parallel.
  // done() is high in the kCombineCycles-th cycle after the EOF pixel's cycle.
  static constexpr int kCombineCycles = kPlanes;

  // Fast path state: plain per-frame sums (software only, no hardware meaning).
  struct FrameSums {
    std::array<uint64_t, kMomentCount> grey{};
    std::array<uint64_t, kMomentCount> mask{};
  };

  MomentGen() { reset(); }

  // Asynchronous active-low reset: all registers to zero, no frame open.
  void reset();

  // One rising clock edge; samples the LutBeat port (remap, mask, pix.*).
  void clock(const LutBeat& in);

  // Registered outputs.
  bool done() const { return done_q_; }  // one-cycle pulse: results() just updated
  const MomentResults& results() const { return results_q_; }  // last completed frame
  bool combine_busy() const { return combine_busy_q_; }
  // Frames whose results were discarded because they ended while the combine
  // of the previous frame was still running (only frames of fewer than
  // kCombineCycles pixels with less blanking can do that). Saturating.
  uint32_t overrun_count() const { return overrun_count_q_; }

  // Fast frame-at-a-time path, equal to clock()-ing the frame. Rows may come in
  // any order; mask bytes: nonzero = 1.
  static void accumulate_row(FrameSums& sums, uint32_t y, const uint8_t* remap, const uint8_t* mask,
                             uint32_t width);
  static MomentResults finish(const FrameSums& sums) { return {sums.grey, sums.mask}; }

 private:
  template <int K>
  using Plane = fp::UInt<moment_gen_widths::kPlaneBits[K]>;
  // One set of six plane accumulators F (p00, p10, p01, p20, p11, p02).
  struct PlaneSet {
    Plane<kM00> m00;
    Plane<kM10> m10;
    Plane<kM01> m01;
    Plane<kM20> m20;
    Plane<kM11> m11;
    Plane<kM02> m02;
  };
  using Planes = std::array<PlaneSet, kPlanes>;

  template <int K>
  using Moment = fp::UInt<moment_gen_widths::kMomentBits[K]>;
  struct MomentSet {
    Moment<kM00> m00;
    Moment<kM10> m10;
    Moment<kM01> m01;
    Moment<kM20> m20;
    Moment<kM11> m11;
    Moment<kM02> m02;
  };

  // Factor generator (eq. 23-25): values for the NEXT pixel of the frame.
  fp::UInt<kCoordBits> x_q_;                              // p10
  fp::UInt<kCoordBits> y_q_;                              // p01
  fp::UInt<moment_gen_widths::kFactorBits[kM20]> p20_q_;  // x^2
  fp::UInt<moment_gen_widths::kFactorBits[kM11]> p11_q_;  // x y
  fp::UInt<moment_gen_widths::kFactorBits[kM02]> p02_q_;  // y^2
  bool frame_open_q_ = false;

  Planes grey_acc_q_{};  // F_k of the frame being received
  PlaneSet mask_acc_q_{};
  Planes grey_snap_q_{};  // F_k of the frame being combined (loaded at EOF)
  PlaneSet mask_snap_q_{};

  bool combine_busy_q_ = false;
  uint8_t combine_step_q_ = 0;  // plane kPlanes-1-step is added at the next edge
  MomentSet horner_q_{};

  MomentResults results_q_{};
  bool done_q_ = false;
  uint32_t overrun_count_q_ = 0;
};

}  // namespace ceilnav::stream
