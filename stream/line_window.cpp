#include "stream/line_window.hpp"

#include <stdexcept>
#include <string>

#include "fixedpoint/datapath.hpp"

namespace ceilnav::stream {

Window3x3 frame_window(const uint8_t* remap, uint32_t width, uint32_t x, uint32_t y) {
  auto at = [&](uint32_t u, uint32_t v) { return remap[size_t{v} * width + u]; };
  auto col = [&](uint32_t u, uint8_t& t, uint8_t& m, uint8_t& b) {
    t = y >= 2 ? at(u, y - 2) : uint8_t{0};
    m = y >= 1 ? at(u, y - 1) : uint8_t{0};
    b = at(u, y);
  };
  Window3x3 w{};
  if (x >= 2) col(x - 2, w.t0, w.m0, w.b0);
  if (x >= 1) col(x - 1, w.t1, w.m1, w.b1);
  col(x, w.t2, w.m2, w.b2);
  return w;
}

LineWindow::LineWindow() : line1_(fp::datapath::kMaxWidth), line2_(fp::datapath::kMaxWidth) {}

void LineWindow::reset() {
  frame_open_q_ = false;
  x_q_ = 0;
  y_q_ = 0;
  win1_q_ = {};
  win2_q_ = {};
}

LineWindow::Pixel LineWindow::clock(const PixelBeat& pix, uint8_t remap, bool enable,
                                    const char* block) {
  Pixel out;
  out.abort = pix.abort && frame_open_q_;
  out.take = pix.valid && (pix.sof ? enable : frame_open_q_);
  if (out.take) {
    const uint32_t x = pix.sof ? 0u : x_q_;
    const uint32_t y = pix.sof ? 0u : y_q_;
    if (x != pix.x || y != pix.y) {
      throw std::logic_error(std::string(block) + ": pixel position differs from the counters");
    }
    const Column cur{line2_[x], line1_[x], remap};
    out.x = x;
    out.y = y;
    out.w = {win2_q_.top, win2_q_.mid, win2_q_.bot, win1_q_.top, win1_q_.mid,
             win1_q_.bot, cur.top,     cur.mid,     cur.bot};
    line2_[x] = cur.mid;
    line1_[x] = cur.bot;
    win2_q_ = win1_q_;
    win1_q_ = cur;
    x_q_ = static_cast<uint16_t>(pix.eol ? 0u : x + 1);
    y_q_ = static_cast<uint16_t>(pix.eol ? y + 1 : y);
  }
  if (pix.valid && pix.sof) {
    frame_open_q_ = out.take && !pix.eof;  // a disabled frame is not opened
  } else if (out.take) {
    frame_open_q_ = !pix.eof;
  } else if (pix.abort) {
    frame_open_q_ = false;
  }
  return out;
}

}  // namespace ceilnav::stream
