#include "stream/class_moments.hpp"

#include <algorithm>
#include <stdexcept>

namespace ceilnav::stream {

namespace {

using namespace class_moments_widths;

constexpr std::array<uint64_t, kMomentCount> kMomentMask = [] {
  std::array<uint64_t, kMomentCount> m{};
  for (size_t i = 0; i < m.size(); ++i) m[i] = (uint64_t{1} << kMomentBits[i]) - 1;
  return m;
}();
constexpr uint32_t kTermMask = (1u << kTermBits) - 1;
constexpr uint32_t kWindowMask = (1u << kWindowBits) - 1;

// The window ports are kWindowBits wide: higher bits of the fields are ignored.
ClassWindow port_window(const ClassWindow& w) {
  return {static_cast<uint16_t>(w.x0 & kWindowMask), static_cast<uint16_t>(w.x1 & kWindowMask),
          static_cast<uint16_t>(w.y0 & kWindowMask), static_cast<uint16_t>(w.y1 & kWindowMask)};
}

bool in_window(const ClassWindow& w, uint32_t x, uint32_t y) {
  return x >= w.x0 && x < w.x1 && y >= w.y0 && y < w.y1;
}

}  // namespace

void ClassMoments::reset() {
  frame_open_q_ = false;
  row_start_q_ = false;
  win_q_ = ClassWindow{0, 0, 0, 0};  // the RTL's reset value; every frame latches its own
  t_valid_q_ = false;
  t_start_q_ = false;
  t_end_q_ = false;
  t_cls_q_ = 0;
  t_x_q_ = 0;
  t_y_q_ = 0;
  t_x2_q_ = 0;
  t_xy_q_ = 0;
  t_y2_q_ = 0;
  acc_q_ = {};
  end_q_ = false;
  results_q_ = {};
  done_q_ = false;
}

void ClassMoments::clock(const LutBeat& in, const ClassWindow& win, bool eof_keep) {
  // ---- Stage 2 -> results: the accumulators of a finished frame.
  done_q_ = end_q_;
  if (end_q_) {
    results_q_.cls = acc_q_;
  }

  // ---- Stage 1 -> stage 2: add the pixel's terms to its class (if inside the
  // window); the frame's first pixel starts every accumulator.
  end_q_ = t_valid_q_ && t_end_q_;
  if (t_valid_q_) {
    const bool inside = in_window(win_q_, t_x_q_, t_y_q_);
    const std::array<uint64_t, kMomentCount> term = {1, t_x_q_, t_y_q_, t_x2_q_, t_xy_q_, t_y2_q_};
    for (int c = 0; c < kMomentClasses; ++c) {
      const bool hit = inside && t_cls_q_ == c + 1;
      auto& acc = acc_q_[static_cast<size_t>(c)];
      for (size_t k = 0; k < kMomentCount; ++k) {
        const uint64_t base = t_start_q_ ? 0 : acc[k];
        acc[k] = (base + (hit ? term[k] : 0)) & kMomentMask[k];
      }
    }
  }

  // ---- Stage 0 -> stage 1: take the pixel, form its terms by increments.
  const PixelBeat& pix = in.pix;
  const bool take = pix.valid && (pix.sof || frame_open_q_);
  t_valid_q_ = take;
  if (take) {
    const bool row_start = pix.sof || row_start_q_;
    const uint32_t want_x = row_start ? 0 : t_x_q_ + 1;
    const uint32_t want_y = pix.sof ? 0 : (row_start_q_ ? t_y_q_ + 1 : t_y_q_);
    if (pix.x != want_x || pix.y != want_y) {
      throw std::logic_error("ClassMoments: pixel position does not follow the previous pixel");
    }
    const uint32_t x2 = row_start ? 0 : (t_x2_q_ + 2 * t_x_q_ + 1) & kTermMask;
    const uint32_t xy = row_start ? 0 : (t_xy_q_ + t_y_q_) & kTermMask;
    const uint32_t y2 =
        pix.sof ? 0 : (row_start_q_ ? (t_y2_q_ + 2 * t_y_q_ + 1) & kTermMask : t_y2_q_);
    t_start_q_ = pix.sof;
    t_end_q_ = pix.eof && eof_keep;
    t_cls_q_ = in.cls & 3u;
    t_x_q_ = pix.x;
    t_y_q_ = pix.y;
    t_x2_q_ = x2;
    t_xy_q_ = xy;
    t_y2_q_ = y2;
    if (pix.sof) {
      win_q_ = port_window(win);
    }
    row_start_q_ = pix.eol;
    frame_open_q_ = !pix.eof;
  } else if (pix.abort) {
    frame_open_q_ = false;  // the partial sums are never shown
  }
}

void ClassMoments::accumulate_row(ClassMomentResults& sums, uint32_t y, const uint8_t* cls,
                                  uint32_t width, const ClassWindow& window) {
  const ClassWindow win = port_window(window);
  if (y < win.y0 || y >= win.y1) return;
  const uint32_t x_begin = win.x0;
  const uint32_t x_end = std::min<uint32_t>(win.x1, width);
  std::array<uint32_t, kClassCount> s0{};  // count   <= 2048
  std::array<uint32_t, kClassCount> s1{};  // sum x   <= 2047 * 2048 / 2
  std::array<uint64_t, kClassCount> s2{};  // sum x^2
  for (uint32_t x = x_begin; x < x_end; ++x) {
    const unsigned c = cls[x] & 3u;
    ++s0[c];
    s1[c] += x;
    s2[c] += uint64_t{x} * x;
  }
  const uint64_t yy = uint64_t{y} * y;
  for (int c = 1; c <= kMomentClasses; ++c) {
    const auto i = static_cast<size_t>(c);
    auto& m = sums.cls[i - 1];
    m[kM00] += s0[i];
    m[kM10] += s1[i];
    m[kM01] += uint64_t{s0[i]} * y;
    m[kM20] += s2[i];
    m[kM11] += uint64_t{s1[i]} * y;
    m[kM02] += s0[i] * yy;
  }
}

ClassMomentResults ClassMoments::frame(const uint8_t* cls, uint32_t width, uint32_t height,
                                       size_t stride_bytes, const ClassWindow& win) {
  ClassMomentResults sums;
  for (uint32_t y = 0; y < height; ++y) {
    accumulate_row(sums, y, cls + size_t{y} * stride_bytes, width, win);
  }
  return sums;
}

}  // namespace ceilnav::stream
