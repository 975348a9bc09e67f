// class_moments: m00 m10 m01 m20 m11 m02 of the binary mask of each pixel
// class 1..3 (LUT bits 10:9: pattern, shadow, bar) inside a programmable
// window, all classes at once. Counters and adders only (seed 003, eq. 20-28):
// the terms 1, x, y, x^2, x y, y^2 of each pixel are formed by increments from
// the previous pixel's terms and added into the accumulators of its class.
// See docs/blocks/class_moments.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "common/limits.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "stream/beat.hpp"
#include "stream/moment_gen.hpp"

namespace ceilnav::stream {

// The widths live in fixedpoint/datapath.hpp (with their proofs).
namespace class_moments_widths {
using namespace fp::datapath::class_moments;  // NOLINT(google-build-using-namespace)
}  // namespace class_moments_widths

class ClassMoments {
 public:
  // Edges from the edge that takes the EOF pixel (e) to the edge that raises
  // done() (e + 2): terms at e, accumulators at e + 1, results at e + 2.
  static constexpr int kLatencyCycles = 2;

  ClassMoments() { reset(); }

  // Synchronous active-low reset: every register to zero, no frame open.
  void reset();

  // One rising edge. Samples the LutBeat port (pix.*, cls), the window ports
  // (latched with the SOF pixel: the window of a frame is the one on the
  // ports at its SOF pixel's edge) and eof_keep (sampled with the EOF pixel:
  // false discards the frame: no done, results unchanged). Throws
  // std::logic_error if a pixel position does not follow the previous one
  // (x + 1 in a row, (0, y + 1) after a row end, (0, 0) at SOF): frame_check
  // rules that out.
  void clock(const LutBeat& in, const ClassWindow& win, bool eof_keep = true);

  // Registered outputs.
  bool done() const { return done_q_; }  // one-cycle pulse: results() just updated
  const ClassMomentResults& results() const { return results_q_; }

  // Fast frame-at-a-time path, equal to clock()-ing the frame: per row the
  // sums of 1, x, x^2 per class inside the window, weighted by 1, y, y^2.
  // Rows may come in any order; cls holds PixelClass codes (0..3).
  static void accumulate_row(ClassMomentResults& sums, uint32_t y, const uint8_t* cls,
                             uint32_t width, const ClassWindow& win);
  // A whole frame (rows stride_bytes apart).
  static ClassMomentResults frame(const uint8_t* cls, uint32_t width, uint32_t height,
                                  size_t stride_bytes, const ClassWindow& win);

 private:
  // Stage 0: frame tracking and the window latched at SOF.
  bool frame_open_q_ = false;
  bool row_start_q_ = false;  // the previous taken pixel ended a row
  ClassWindow win_q_{};

  // Stage 1: the terms of the last taken pixel (they stay until the next one:
  // the next pixel's terms are increments of them).
  bool t_valid_q_ = false;  // a pixel was taken on the last edge
  bool t_start_q_ = false;  // ... and it was the frame's first (SOF)
  bool t_end_q_ = false;    // ... and it was a kept EOF
  uint8_t t_cls_q_ = 0;
  uint32_t t_x_q_ = 0;
  uint32_t t_y_q_ = 0;
  uint32_t t_x2_q_ = 0;
  uint32_t t_xy_q_ = 0;
  uint32_t t_y2_q_ = 0;

  // Stage 2: one accumulator per class and moment, kept to its RTL width.
  std::array<std::array<uint64_t, kMomentCount>, kMomentClasses> acc_q_{};
  bool end_q_ = false;  // the accumulators hold a finished frame

  ClassMomentResults results_q_{};
  bool done_q_ = false;
};

}  // namespace ceilnav::stream
