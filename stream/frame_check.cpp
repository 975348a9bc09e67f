#include "stream/frame_check.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "common/limits.hpp"

namespace ceilnav::stream {
namespace {

void saturating_increment(uint32_t& counter) {
  if (counter != std::numeric_limits<uint32_t>::max()) {
    ++counter;
  }
}

uint16_t clamp_geometry(uint16_t value, uint32_t max_value) {
  return static_cast<uint16_t>(std::clamp<uint32_t>(value, 1u, max_value));
}

}  // namespace

void FrameCheck::reset() {
  state_q_ = State::kIdle;
  width_q_ = 1;
  height_q_ = 1;
  x_q_ = 0;
  y_q_ = 0;
  pix_q_ = PixelBeat{};
  counters_q_ = FrameErrorCounters{};
}

void FrameCheck::clock(const VideoBeat& s_axis_video, uint16_t cfg_width, uint16_t cfg_height) {
  pix_q_ = PixelBeat{};
  if (!s_axis_video.tvalid) {
    return;
  }
  if (s_axis_video.tuser) {
    open_frame(s_axis_video, cfg_width, cfg_height);
    return;
  }
  switch (state_q_) {
    case State::kIdle:
      // A pixel outside any frame (also: an extra line after a complete frame).
      saturating_increment(counters_q_.missing_sof);
      state_q_ = State::kDiscard;
      break;
    case State::kDiscard:
      break;
    case State::kInFrame:
      check_pixel(s_axis_video);
      break;
  }
}

void FrameCheck::open_frame(const VideoBeat& in, uint16_t cfg_width, uint16_t cfg_height) {
  if (state_q_ == State::kInFrame) {
    // Early SOF: abort the open frame; the SOF pixel starts the next one.
    saturating_increment(counters_q_.early_sof);
    saturating_increment(counters_q_.frames_aborted);
    pix_q_.abort = true;
  }
  width_q_ = clamp_geometry(cfg_width, kMaxWidth);
  height_q_ = clamp_geometry(cfg_height, kMaxHeight);
  x_q_ = 0;
  y_q_ = 0;
  state_q_ = State::kInFrame;
  check_pixel(in);
}

void FrameCheck::check_pixel(const VideoBeat& in) {
  const bool at_eol = x_q_ == width_q_ - 1;
  const bool first_pixel = x_q_ == 0 && y_q_ == 0;
  if (in.tlast != at_eol) {
    saturating_increment(in.tlast ? counters_q_.early_eol : counters_q_.late_eol);
    // A frame whose SOF pixel is itself malformed was never opened downstream:
    // it is counted under its error class only and needs no abort.
    if (!first_pixel) {
      saturating_increment(counters_q_.frames_aborted);
      pix_q_.abort = true;
    }
    state_q_ = State::kDiscard;
    return;
  }
  const bool at_eof = at_eol && y_q_ == height_q_ - 1;
  pix_q_.valid = true;
  pix_q_.grey = in.tdata;
  pix_q_.x = x_q_;
  pix_q_.y = y_q_;
  pix_q_.sof = first_pixel;
  pix_q_.eol = at_eol;
  pix_q_.eof = at_eof;
  if (at_eof) {
    saturating_increment(counters_q_.frames_ok);
    state_q_ = State::kIdle;
  } else if (at_eol) {
    x_q_ = 0;
    ++y_q_;
  } else {
    ++x_q_;
  }
}

void FrameCheck::process_frame(uint16_t cfg_width, uint16_t cfg_height) {
  if (state_q_ == State::kInFrame) {
    saturating_increment(counters_q_.early_sof);
    saturating_increment(counters_q_.frames_aborted);
  }
  width_q_ = clamp_geometry(cfg_width, kMaxWidth);
  height_q_ = clamp_geometry(cfg_height, kMaxHeight);
  saturating_increment(counters_q_.frames_ok);
  state_q_ = State::kIdle;
  x_q_ = static_cast<uint16_t>(width_q_ - 1);
  y_q_ = static_cast<uint16_t>(height_q_ - 1);
  pix_q_ = PixelBeat{};
}

}  // namespace ceilnav::stream
