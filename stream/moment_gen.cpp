#include "stream/moment_gen.hpp"

#include <stdexcept>

namespace ceilnav::stream {

namespace {

// F += bit ? p : 0 — the AND gates and the adder of one plane accumulator
// (eq. 28). from_raw keeps the accumulator's width (wrap, as the hardware).
template <class Acc>
Acc and_add(const Acc& acc, bool bit, uint64_t p) {
  return Acc::from_raw(acc.raw() + (bit ? p : uint64_t{0}));
}

// h = 2 h + F: one Horner step of eq. 27; first = the MSB plane (h starts at 0).
template <class M, class Acc>
M horner_step(const M& h, bool first, const Acc& f) {
  return M::from_raw((first ? uint64_t{0} : h.raw() << 1) + f.raw());
}

}  // namespace

void MomentGen::reset() {
  x_q_ = {};
  y_q_ = {};
  p20_q_ = {};
  p11_q_ = {};
  p02_q_ = {};
  frame_open_q_ = false;
  grey_acc_q_ = {};
  mask_acc_q_ = {};
  grey_snap_q_ = {};
  mask_snap_q_ = {};
  combine_busy_q_ = false;
  combine_step_q_ = 0;
  horner_q_ = {};
  results_q_ = {};
  done_q_ = false;
  overrun_count_q_ = 0;
}

void MomentGen::clock(const LutBeat& in) {
  // ---- Horner combine of the snapshot (reads only pre-edge registers).
  bool done_d = false;
  bool combine_busy_d = combine_busy_q_;
  uint8_t combine_step_d = combine_step_q_;
  MomentSet horner_d = horner_q_;
  MomentResults results_d = results_q_;
  if (combine_busy_q_) {
    const bool first = combine_step_q_ == 0;
    const PlaneSet& f = grey_snap_q_[static_cast<size_t>(kPlanes - 1 - combine_step_q_)];
    horner_d.m00 = horner_step(horner_q_.m00, first, f.m00);
    horner_d.m10 = horner_step(horner_q_.m10, first, f.m10);
    horner_d.m01 = horner_step(horner_q_.m01, first, f.m01);
    horner_d.m20 = horner_step(horner_q_.m20, first, f.m20);
    horner_d.m11 = horner_step(horner_q_.m11, first, f.m11);
    horner_d.m02 = horner_step(horner_q_.m02, first, f.m02);
    if (combine_step_q_ == kPlanes - 1) {
      results_d.grey = {horner_d.m00.raw(), horner_d.m10.raw(), horner_d.m01.raw(),
                        horner_d.m20.raw(), horner_d.m11.raw(), horner_d.m02.raw()};
      results_d.mask = {mask_snap_q_.m00.raw(), mask_snap_q_.m10.raw(), mask_snap_q_.m01.raw(),
                        mask_snap_q_.m20.raw(), mask_snap_q_.m11.raw(), mask_snap_q_.m02.raw()};
      done_d = true;
      combine_busy_d = false;
      combine_step_d = 0;
    } else {
      combine_step_d = static_cast<uint8_t>(combine_step_q_ + 1);
    }
  }

  // ---- Pixel path: factor generator, AND gates, plane accumulators.
  const PixelBeat& pix = in.pix;
  const bool take = pix.valid && (pix.sof || frame_open_q_);
  if (take) {
    // Top of screen / left margin: every factor of the SOF pixel is 0.
    const uint64_t x = pix.sof ? 0 : x_q_.raw();
    const uint64_t y = pix.sof ? 0 : y_q_.raw();
    const uint64_t p20 = pix.sof ? 0 : p20_q_.raw();
    const uint64_t p11 = pix.sof ? 0 : p11_q_.raw();
    const uint64_t p02 = pix.sof ? 0 : p02_q_.raw();
    if (x != pix.x || y != pix.y) {
      throw std::logic_error("MomentGen: pixel position differs from the counters");
    }

    Planes grey_acc_d;
    for (int k = 0; k < kPlanes; ++k) {
      const auto ku = static_cast<size_t>(k);
      const PlaneSet& a = pix.sof ? PlaneSet{} : grey_acc_q_[ku];
      const bool bit = ((in.remap >> k) & 1u) != 0;
      PlaneSet& d = grey_acc_d[ku];
      d.m00 = and_add(a.m00, bit, 1);
      d.m10 = and_add(a.m10, bit, x);
      d.m01 = and_add(a.m01, bit, y);
      d.m20 = and_add(a.m20, bit, p20);
      d.m11 = and_add(a.m11, bit, p11);
      d.m02 = and_add(a.m02, bit, p02);
    }
    const PlaneSet& am = pix.sof ? PlaneSet{} : mask_acc_q_;
    PlaneSet mask_acc_d;
    mask_acc_d.m00 = and_add(am.m00, in.mask, 1);
    mask_acc_d.m10 = and_add(am.m10, in.mask, x);
    mask_acc_d.m01 = and_add(am.m01, in.mask, y);
    mask_acc_d.m20 = and_add(am.m20, in.mask, p20);
    mask_acc_d.m11 = and_add(am.m11, in.mask, p11);
    mask_acc_d.m02 = and_add(am.m02, in.mask, p02);

    // Factors of the next pixel: eq. 23-24 along the row, eq. 25 per row.
    if (pix.eol) {
      x_q_ = {};
      p20_q_ = {};
      p11_q_ = {};
      y_q_ = decltype(y_q_)::from_raw(y + 1);
      p02_q_ = decltype(p02_q_)::from_raw(p02 + (y << 1) + 1);
    } else {
      x_q_ = decltype(x_q_)::from_raw(x + 1);
      p20_q_ = decltype(p20_q_)::from_raw(p20 + (x << 1) + 1);
      p11_q_ = decltype(p11_q_)::from_raw(p11 + y);
      y_q_ = decltype(y_q_)::from_raw(y);
      p02_q_ = decltype(p02_q_)::from_raw(p02);
    }
    grey_acc_q_ = grey_acc_d;
    mask_acc_q_ = mask_acc_d;
    frame_open_q_ = !pix.eof;

    if (pix.eof) {
      // The snapshot may be reloaded on the edge where the combine reads its
      // last plane (F_0), not earlier.
      if (combine_busy_q_ && combine_step_q_ != kPlanes - 1) {
        if (overrun_count_q_ != UINT32_MAX) ++overrun_count_q_;
      } else {
        grey_snap_q_ = grey_acc_d;
        mask_snap_q_ = mask_acc_d;
        combine_busy_d = true;
        combine_step_d = 0;
      }
    }
  } else if (pix.abort) {
    frame_open_q_ = false;  // the partial sums are never snapshot
  }

  combine_busy_q_ = combine_busy_d;
  combine_step_q_ = combine_step_d;
  horner_q_ = horner_d;
  results_q_ = results_d;
  done_q_ = done_d;
}

void MomentGen::accumulate_row(FrameSums& sums, uint32_t y, const uint8_t* remap,
                               const uint8_t* mask, uint32_t width) {
  // Per-row sums, then the row's weight y^b: the same integers as eq. 20.
  uint32_t g0 = 0;  // sum I       <= 255 * 2048
  uint32_t g1 = 0;  // sum I x     <= 255 * 2047 * 2048 / 2 < 2^32
  uint64_t g2 = 0;  // sum I x^2
  uint32_t c0 = 0;
  uint32_t c1 = 0;
  uint64_t c2 = 0;
  for (uint32_t x = 0; x < width; ++x) {
    const uint32_t i = remap[x];
    const uint32_t m = mask[x] != 0 ? 1u : 0u;
    const uint32_t xx = x * x;
    g0 += i;
    g1 += i * x;
    g2 += uint64_t{i * xx};
    c0 += m;
    c1 += m * x;
    c2 += uint64_t{m * xx};
  }
  const uint64_t yy = uint64_t{y} * y;
  sums.grey[kM00] += g0;
  sums.grey[kM10] += g1;
  sums.grey[kM01] += uint64_t{g0} * y;
  sums.grey[kM20] += g2;
  sums.grey[kM11] += uint64_t{g1} * y;
  sums.grey[kM02] += g0 * yy;
  sums.mask[kM00] += c0;
  sums.mask[kM10] += c1;
  sums.mask[kM01] += uint64_t{c0} * y;
  sums.mask[kM20] += c2;
  sums.mask[kM11] += uint64_t{c1} * y;
  sums.mask[kM02] += c0 * yy;
}

}  // namespace ceilnav::stream
