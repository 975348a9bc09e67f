// The LutBeat stream generator of the co-simulations of the blocks behind
// thresh_lut (moment_gen, class_moments, run_scanner, edge): random legal streams as
// thresh_lut delivers them after frame_check. Frames of random size (mostly
// small, now and then up to 640 x 480), tvalid gaps (valid low) per frame,
// zero-blanking back-to-back frames, aborts (an abort beat alone, or combined
// with the next frame's SOF as frame_check's early SOF does), resets in
// mid-frame, and stray beats between frames (a lone abort, pixels without an
// SOF) that a closed frame must ignore.
//
// Block is the derived generator (CRTP); it adds the block's side inputs:
//   Stim make(const LutBeat&)               a frame beat with its side inputs
//   Stim make_blank()                       a blanking cycle (from blank_beat())
//   void begin_frame(const LutFrame&)       per-frame side inputs
//   LutFrame frame(uint16_t w, uint16_t h)  a random frame of that size
//   void drain(std::vector<Stim>&)          the cycles after the last frame
// Stim has `LutBeat beat` and `bool reset_before`.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "stream/beat.hpp"
#include "stream/tests/beat_source.hpp"
#include "testbench/cosim_common.hpp"

namespace ceilnav::testbench {

// How a block's stream is shaped where the blocks differ.
struct LutStreamShape {
  bool thin_frames = false;  // 0.3 % long thin frames up to the 2048 limit
  // Blanking after a frame: kind = uniform(0, 9); none below none_below, then
  // short (below 8) or long, each a uniform count.
  int64_t none_below = 4;
  int64_t short_lo = 1;
  int64_t short_hi = 10;
  int64_t long_lo = 10;
  int64_t long_hi = 60;
  bool stray_class = false;  // stray pixels carry a class (else remap and mask)
};

template <class Block, class Stim>
class LutStreamGen {
 public:
  LutStreamGen(uint64_t seed, const LutStreamShape& shape)
      : rng_(seed), mt_(static_cast<uint32_t>(seed)), shape_(shape) {}

  Rng& rng() { return rng_; }
  std::mt19937& mt() { return mt_; }

  // Mostly small frames; now and then a large one.
  void random_size(uint16_t& w, uint16_t& h) {
    const int64_t kind = rng_.uniform(0, 999);
    if (kind < 600) {
      w = rng_.uniform_as<uint16_t>(1, 12);
      h = rng_.uniform_as<uint16_t>(1, 12);
    } else if (kind < 900) {
      w = rng_.uniform_as<uint16_t>(1, 64);
      h = rng_.uniform_as<uint16_t>(1, 48);
    } else if (kind < (shape_.thin_frames ? 995 : 998)) {
      w = rng_.uniform_as<uint16_t>(1, 200);
      h = rng_.uniform_as<uint16_t>(1, 150);
    } else if (shape_.thin_frames && kind < 998) {  // long thin frames up to the limit
      w = rng_.chance(0.5) ? rng_.uniform_as<uint16_t>(1000, 2048) : 1;
      h = w == 1 ? rng_.uniform_as<uint16_t>(1000, 2048) : rng_.uniform_as<uint16_t>(1, 3);
    } else {
      w = rng_.uniform_as<uint16_t>(320, 640);
      h = rng_.uniform_as<uint16_t>(200, 480);
    }
  }

  // Appends one frame (possibly cut short or reset) and the blanking after it.
  void append_frame(std::vector<Stim>& out, const stream::test::LutFrame& f) {
    static constexpr double kGapChoices[] = {0.0, 0.0, 0.0, 0.05, 0.2, 0.6};
    const double gap = kGapChoices[rng_.uniform(0, 5)];
    const int64_t mode = rng_.uniform(0, 199);
    const auto pixels = static_cast<int64_t>(f.pixels());
    block().begin_frame(f);
    std::vector<stream::LutBeat> beats;
    bool combine_abort_with_next_sof = false;
    size_t reset_at = SIZE_MAX;
    if (mode < 140) {
      stream::test::append_frame(beats, f, mt_, gap);
    } else if (mode < 165) {  // abort beat (valid = 0) after some pixels
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
    } else if (mode < 196) {  // early SOF: the next frame's SOF beat carries the abort
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
      beats.pop_back();
      combine_abort_with_next_sof = true;
    } else {  // reset somewhere in the frame
      stream::test::append_frame(beats, f, mt_, gap);
      reset_at = static_cast<size_t>(rng_.uniform(0, static_cast<int64_t>(beats.size()) - 1));
    }
    for (size_t i = 0; i < beats.size(); ++i) {
      Stim s = block().make(beats[i]);
      if (pending_abort_ && s.beat.pix.valid) {
        s.beat.pix.abort = true;  // combined abort + SOF beat (frame_check's early SOF)
        pending_abort_ = false;
      }
      s.reset_before = i == reset_at;
      out.push_back(s);
    }
    pending_abort_ = combine_abort_with_next_sof;
    if (pending_abort_) return;  // zero blanking: the next frame's SOF aborts this one
    const int64_t blank_kind = rng_.uniform(0, 9);
    const int64_t blank = blank_kind < shape_.none_below ? 0
                          : blank_kind < 8 ? rng_.uniform(shape_.short_lo, shape_.short_hi)
                                           : rng_.uniform(shape_.long_lo, shape_.long_hi);
    for (int64_t i = 0; i < blank; ++i) out.push_back(block().make_blank());
  }

  // A beat of blanking: idle, a lone abort, or a pixel outside any frame.
  stream::LutBeat blank_beat() {
    stream::LutBeat b;
    if (rng_.chance(0.1)) {
      b.pix.abort = true;  // abort with no frame open
    } else if (rng_.chance(0.1)) {
      b.pix.valid = true;  // pixel outside a frame, no SOF: ignored
      b.pix.x = rng_.uniform_as<uint16_t>(0, 2047);
      b.pix.y = rng_.uniform_as<uint16_t>(0, 2047);
      b.pix.eol = rng_.chance(0.5);
      b.pix.eof = b.pix.eol && rng_.chance(0.5);
      if (shape_.stray_class) {
        b.cls = rng_.uniform_as<uint8_t>(0, 3);
      } else {
        b.remap = rng_.byte();
        b.mask = rng_.chance(0.5);
      }
    }
    return b;
  }

  // Random frames until at least `cycles` records, then finish().
  std::vector<Stim> random_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      uint16_t w = 0;
      uint16_t h = 0;
      random_size(w, h);
      append_frame(out, block().frame(w, h));
    }
    finish(out);
    return out;
  }

  // A closing frame, so that a pending combined abort has its SOF; then the
  // block's drain.
  void finish(std::vector<Stim>& out) {
    if (pending_abort_) append_frame(out, block().frame(3, 2));
    block().drain(out);
  }

 protected:
  Rng rng_;
  std::mt19937 mt_;

 private:
  Block& block() { return static_cast<Block&>(*this); }

  LutStreamShape shape_;
  bool pending_abort_ = false;
};

// The generator of a block with a configuration port and an m_axis output
// behind a FIFO (run_scanner, edge): LutStreamGen's hooks plus the config
// port (a new random configuration at any cycle, P = 0.003) and the
// consumer's tready in phases of random length, each with its own P(tready),
// some of them full stalls of up to max_stall cycles. Block adds
//   Config random_config()                 a random configuration
//   void append_burst(std::vector<Stim>&)  frames that overflow the FIFO (using stall_)
// Stim has `LutBeat beat`, `Config cfg`, `bool tready`, `bool reset_before`.
template <class Block, class Stim, class Config>
class FifoStreamGen : public LutStreamGen<Block, Stim> {
 public:
  FifoStreamGen(uint64_t seed, const LutStreamShape& shape, uint32_t max_stall_cycles)
      : LutStreamGen<Block, Stim>(seed, shape), max_stall_(max_stall_cycles) {}

  bool next_tready() {
    Rng& rng = this->rng_;
    if (phase_left_ == 0) {
      static constexpr double kP[] = {1.0, 1.0, 0.95, 0.7, 0.3, 0.05, 0.0};
      p_ready_ = kP[rng.uniform(0, 6)];
      phase_left_ = static_cast<uint32_t>(
          rng.uniform(1, p_ready_ == 0.0 ? max_stall_ : std::max<uint32_t>(64, max_stall_ / 4)));
    }
    --phase_left_;
    return p_ready_ >= 1.0 || (p_ready_ > 0.0 && rng.chance(p_ready_));
  }

  Stim make(const stream::LutBeat& b) {
    if (this->rng_.chance(0.003)) cfg_ = block().random_config();  // the port may change any time
    Stim s;
    s.beat = b;
    s.cfg = cfg_;
    s.tready = next_tready() && !stall_;
    return s;
  }

  // LutStreamGen's hooks.
  void begin_frame(const stream::test::LutFrame& /*f*/) {}
  Stim make_blank() { return make(this->blank_beat()); }
  stream::test::LutFrame frame(uint16_t w, uint16_t h) {
    return stream::test::random_frame(this->mt_, w, h);
  }
  // Drain: tready high until a FIFO of up to 1024 entries must be empty.
  void drain(std::vector<Stim>& out) {
    for (int i = 0; i < 1100; ++i) {
      Stim s = make(stream::LutBeat{});
      s.tready = true;
      out.push_back(s);
    }
  }

  // Random frames, and with burst_probability per frame the block's burst.
  std::vector<Stim> random_stream(uint64_t cycles, double burst_probability) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      if (this->rng_.chance(burst_probability)) {
        block().append_burst(out);
        continue;
      }
      uint16_t w = 0;
      uint16_t h = 0;
      this->random_size(w, h);
      this->append_frame(out, frame(w, h));
    }
    this->finish(out);
    return out;
  }

 protected:
  Config cfg_{};
  bool stall_ = false;  // tready low whatever the phase

 private:
  Block& block() { return static_cast<Block&>(*this); }

  uint32_t max_stall_;
  uint32_t phase_left_ = 0;
  double p_ready_ = 1.0;
};

// A grey image (a photo) through a LUT, as the LutFrame thresh_lut makes of it.
inline stream::test::LutFrame lut_frame(const cv::Mat& grey,
                                        const std::array<stream::LutEntry, 256>& lut) {
  std::vector<uint8_t> pixels;
  pixels.reserve(grey.total());
  for (int y = 0; y < grey.rows; ++y) {
    const auto* row = grey.ptr<uint8_t>(y);
    pixels.insert(pixels.end(), row, row + grey.cols);
  }
  return stream::test::LutFrame::from_grey(pixels, static_cast<uint16_t>(grey.cols),
                                           static_cast<uint16_t>(grey.rows), lut);
}

}  // namespace ceilnav::testbench
