// line_window: the 3x3 window on the LUT remap stream that the edge and the
// orientation blocks share: the frame a block takes (from an SOF pixel with
// its enable to the EOF pixel or an abort), the position check against the
// block's counters, the line buffer (BRAM: per column the pixels of rows
// y-1 and y-2) and the two registered window columns. docs/blocks/edge.md,
// docs/blocks/orientation.md.
#pragma once

#include <cstdint>
#include <vector>

#include "stream/beat.hpp"

namespace ceilnav::stream {

// The window of pixel (x, y): columns x-2 (0), x-1 (1), x (2) of rows y-2
// (t), y-1 (m), y (b); a Sobel window is centred on (x-1, y-1).
struct Window3x3 {
  uint8_t t0, m0, b0, t1, m1, b1, t2, m2, b2;
};

// The Sobel gradient of the window's centre (cv::Sobel's 3x3 kernels:
// right - left, bottom - top).
inline int sobel_gx(const Window3x3& w) {
  return (int{w.t2} + 2 * int{w.m2} + int{w.b2}) - (int{w.t0} + 2 * int{w.m0} + int{w.b0});
}
inline int sobel_gy(const Window3x3& w) {
  return (int{w.b0} + 2 * int{w.b1} + int{w.b2}) - (int{w.t0} + 2 * int{w.t1} + int{w.t2});
}

// The window of pixel (x, y) of a row-major frame (the fast paths); pixels
// before the frame's first row or column read 0 (the clocked window holds
// other values there, which no block uses).
Window3x3 frame_window(const uint8_t* remap, uint32_t width, uint32_t x, uint32_t y);

class LineWindow {
 public:
  LineWindow();

  // Reset: no frame open, counters and window columns zero. The line buffer
  // keeps its contents (a frame reads only rows it wrote).
  void reset();

  // What one edge took.
  struct Pixel {
    bool take = false;   // a pixel of the taken frame: x, y, w are its
    bool abort = false;  // the open frame was aborted (alone or by an early SOF)
    uint32_t x = 0;
    uint32_t y = 0;
    Window3x3 w{};
  };

  // One rising edge: the pixel beat with its remap value; enable is the
  // block's configured enable (used at an SOF pixel). Throws
  // std::logic_error (naming `block`) if a taken pixel's position differs
  // from the counters.
  Pixel clock(const PixelBeat& pix, uint8_t remap, bool enable, const char* block);
  // A taken frame is open (its SOF taken, its EOF or abort not yet).
  bool frame_open() const { return frame_open_q_; }

 private:
  // One column of the window: rows y-2, y-1, y.
  struct Column {
    uint8_t top = 0;
    uint8_t mid = 0;
    uint8_t bot = 0;
  };

  bool frame_open_q_ = false;
  uint16_t x_q_ = 0;  // position of the next pixel (checked against the beat)
  uint16_t y_q_ = 0;
  Column win1_q_{};             // window column x-1
  Column win2_q_{};             // window column x-2
  std::vector<uint8_t> line1_;  // row y-1, per column
  std::vector<uint8_t> line2_;  // row y-2
};

}  // namespace ceilnav::stream
