#include "stream/moment_gen.hpp"

#include <stdexcept>

namespace ceilnav::stream {

namespace {

using namespace moment_gen_widths;

constexpr uint64_t mask_of(int bits) {
  return (uint64_t{1} << bits) - 1;
}

template <size_t N>
constexpr std::array<uint64_t, N> masks_of(const std::array<int, N>& bits) {
  std::array<uint64_t, N> m{};
  for (size_t i = 0; i < N; ++i) m[i] = mask_of(bits[i]);
  return m;
}

constexpr auto kGreyRowMask = masks_of(kGreyRowBits);
constexpr auto kMaskRowMask = masks_of(kMaskRowBits);
constexpr auto kGreyFrameMask = masks_of(kGreyFrameBits);
constexpr auto kMaskFrameMask = masks_of(kMaskFrameBits);
constexpr auto kGreyMomentMask = masks_of(kGreyMomentBits);
constexpr auto kMaskMomentMask = masks_of(kMaskMomentBits);

}  // namespace

void MomentGen::reset() {
  frame_open_q_ = false;
  row_start_q_ = false;
  first_row_q_ = false;
  x_q_ = 0;
  y_q_ = 0;
  width_q_ = 0;
  grey_q_ = {};
  mask_q_ = {};
  combine_busy_q_ = false;
  combine_left_q_ = 0;
  pending_q_ = {};
  results_q_ = {};
  done_q_ = false;
  wr_active_q_ = false;
  wr_step_q_ = 0;
  overrun_count_q_ = 0;
}

// A1 += I, A2 += A1, A3 += A2 (each with the value after this pixel); the
// first pixel of a row starts them from 0.
template <bool kGrey>
void MomentGen::add_pixel(Cascade& c, uint64_t value, bool row_start) {
  const auto& m = kGrey ? kGreyRowMask : kMaskRowMask;
  auto& a = c.a;
  a[0] = ((row_start ? 0 : a[0]) + value) & m[0];
  a[1] = ((row_start ? 0 : a[1]) + a[0]) & m[1];
  a[2] = ((row_start ? 0 : a[2]) + a[1]) & m[2];
}

// At a row end: F00 += A1, F01 += F00, F02 += F01 (v weights down the frame),
// F10 += A2, F11 += F10, F20 += A3; the first row starts them from 0.
template <bool kGrey>
void MomentGen::end_row(Cascade& c, bool first_row) {
  const auto& m = kGrey ? kGreyFrameMask : kMaskFrameMask;
  auto& f = c.f;
  const auto acc = [first_row](uint64_t old, uint64_t add) { return (first_row ? 0 : old) + add; };
  f[kM00] = acc(f[kM00], c.a[0]) & m[kM00];
  f[kM01] = acc(f[kM01], f[kM00]) & m[kM01];
  f[kM02] = acc(f[kM02], f[kM01]) & m[kM02];
  f[kM10] = acc(f[kM10], c.a[1]) & m[kM10];
  f[kM11] = acc(f[kM11], f[kM10]) & m[kM11];
  f[kM20] = acc(f[kM20], c.a[2]) & m[kM20];
}

// With x = W - u, y = H - v, u^2 = 2 u(u+1)/2 - u:
//   m10 = W F00 - F10                 m01 = H F00 - F01
//   m20 = W (m10 - F10) + 2 F20 - F10 m02 = H (m01 - F01) + 2 F02 - F01
//   m11 = W m01 - H F10 + F11
// Intermediates may be negative; unsigned arithmetic is exact modulo 2^64
// and every moment is below 2^51. The RTL computes the same modulo 2^pass.
template <bool kGrey>
std::array<uint64_t, kMomentCount> MomentGen::combine(const Cascade& c, uint64_t w, uint64_t h) {
  const auto& f = c.f;
  const auto& m = kGrey ? kGreyMomentMask : kMaskMomentMask;
  std::array<uint64_t, kMomentCount> r{};
  r[kM00] = f[kM00];
  r[kM10] = w * f[kM00] - f[kM10];
  r[kM01] = h * f[kM00] - f[kM01];
  r[kM20] = w * (r[kM10] - f[kM10]) + 2 * f[kM20] - f[kM10];
  r[kM11] = w * r[kM01] - h * f[kM10] + f[kM11];
  r[kM02] = h * (r[kM01] - f[kM01]) + 2 * f[kM02] - f[kM01];
  for (size_t k = 0; k < kMomentCount; ++k) r[k] &= m[k];
  return r;
}

uint32_t MomentGen::moment_word(const MomentResults& r, int w) {
  const auto k = static_cast<size_t>(w % kMomentCount);
  const uint64_t m = w < 2 * kMomentCount ? r.grey[k] : r.mask[k];
  return static_cast<uint32_t>((w / kMomentCount) % 2 == 0 ? m : m >> 32);
}

void MomentGen::clock(const LutBeat& in, bool eof_drop) {
  // ---- Combine: only its timing is modelled (the values were formed at EOF).
  const bool last_step = combine_busy_q_ && combine_left_q_ == 1;
  const bool combine_free = (!combine_busy_q_ || last_step) && !eof_drop;
  done_q_ = last_step;
  if (last_step) {
    wr_active_q_ = true;
    wr_step_q_ = 0;
  } else if (wr_active_q_) {
    wr_active_q_ = wr_step_q_ != kMomentWords - 1;
    ++wr_step_q_;
  }
  if (last_step) {
    results_q_ = pending_q_;
    combine_busy_q_ = false;
  } else if (combine_busy_q_) {
    --combine_left_q_;
  }

  // ---- Pixel path.
  const PixelBeat& pix = in.pix;
  const bool take = pix.valid && (pix.sof || frame_open_q_);
  if (take) {
    const uint32_t x = pix.sof ? 0 : x_q_;
    const uint32_t y = pix.sof ? 0 : y_q_;
    const bool row_start = pix.sof || row_start_q_;
    const bool first_row = pix.sof || first_row_q_;
    if (x != pix.x || y != pix.y) {
      throw std::logic_error("MomentGen: pixel position differs from the counters");
    }
    if ((pix.eol && !first_row && x + 1 != width_q_) || (pix.eof && !pix.eol)) {
      throw std::logic_error("MomentGen: the frame is not rectangular");
    }
    add_pixel<true>(grey_q_, in.remap, row_start);
    add_pixel<false>(mask_q_, in.mask ? uint64_t{1} : uint64_t{0}, row_start);
    if (pix.eol) {
      end_row<true>(grey_q_, first_row);
      end_row<false>(mask_q_, first_row);
      if (first_row) width_q_ = x + 1;
      x_q_ = 0;
      y_q_ = y + 1;
    } else {
      x_q_ = x + 1;
      y_q_ = y;
    }
    row_start_q_ = pix.eol;
    first_row_q_ = first_row && !pix.eol;
    frame_open_q_ = !pix.eof;

    if (pix.eof) {
      if (combine_free) {
        pending_q_.grey = combine<true>(grey_q_, x + 1, y + 1);
        pending_q_.mask = combine<false>(mask_q_, x + 1, y + 1);
        combine_busy_q_ = true;
        combine_left_q_ = kCombineCycles;
      } else if (overrun_count_q_ != UINT32_MAX) {
        ++overrun_count_q_;
      }
    }
  } else if (pix.abort) {
    frame_open_q_ = false;  // the partial sums are never combined
  }
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
