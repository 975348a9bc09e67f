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

#include "common/limits.hpp"
#include "common/results.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream {

// The widths live in fixedpoint/datapath.hpp (with their proofs).
namespace moment_gen_widths {
using namespace fp::datapath::moment_gen;  // NOLINT(google-build-using-namespace)
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

  // Synchronous active-low reset: all registers to zero, no frame open.
  void reset();

  // One rising clock edge; samples the LutBeat port (remap, mask, pix.*) and
  // eof_drop (RTL eof_drop_i): an EOF beat sampled with eof_drop high is not
  // accepted (no combine, no done) and counts as an overrun, as if the combine
  // were busy; the pipeline drops a frame the histogram could not count.
  // Throws std::logic_error if pix.x / pix.y differ from the block's counters
  // or the frame is not rectangular (frame_check rules both out).
  void clock(const LutBeat& in, bool eof_drop = false);

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
  // fewer than kCombineCycles pixels plus blanking can do that) or with
  // eof_drop high. Saturating.
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
