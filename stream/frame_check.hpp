// frame_check: checks the camera's AXI4-Stream video against the configured
// geometry and realigns after errors. See docs/blocks/frame_check.md.
#pragma once

#include <cstdint>

#include "common/results.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream {

class FrameCheck {
 public:
  enum class State : uint8_t {
    kIdle,     // no frame open, the last one ended cleanly (or reset): expecting SOF
    kInFrame,  // a frame is open; x_q/y_q is the position of the next pixel
    kDiscard,  // after an error: drop pixels silently until the next SOF
  };

  FrameCheck() { reset(); }

  // Synchronous active-low reset: counters to zero, state kIdle, output idle.
  void reset();

  // One rising edge. cfg_width/cfg_height are the configuration inputs; they
  // are latched only on an SOF beat (s_axis_video.tvalid && tuser) and clamped
  // to 1 .. kMaxWidth / kMaxHeight. s_axis_tready is always 1.
  void clock(const VideoBeat& s_axis_video, uint16_t cfg_width, uint16_t cfg_height);

  // Fast path: the same state as clock()-ing one complete, well-formed frame
  // of cfg_width x cfg_height followed by one gap cycle.
  void process_frame(uint16_t cfg_width, uint16_t cfg_height);

  // Registered outputs.
  const PixelBeat& m_pix() const { return pix_q_; }
  const FrameErrorCounters& counters() const { return counters_q_; }

  // Observability (not ports).
  State state() const { return state_q_; }
  uint16_t width() const { return width_q_; }
  uint16_t height() const { return height_q_; }

 private:
  void open_frame(const VideoBeat& in, uint16_t cfg_width, uint16_t cfg_height);
  void check_pixel(const VideoBeat& in);

  State state_q_ = State::kIdle;
  uint16_t width_q_ = 1;  // latched geometry of the open frame
  uint16_t height_q_ = 1;
  uint16_t x_q_ = 0;  // position of the next expected pixel
  uint16_t y_q_ = 0;
  PixelBeat pix_q_{};
  FrameErrorCounters counters_q_{};
};

}  // namespace ceilnav::stream
