// Video stimulus for the device-level co-simulations: frames of dark noise
// with bright rectangles (runs for the scanner, a spread histogram), their
// AXI4-Stream beats, and a queue of beats with blanking and random tvalid
// gaps (valid low) in front of the device. The m_axis_runs back-pressure
// (tready low) is DeviceBench's (testbench/top_cosim.hpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "stream/beat.hpp"
#include "testbench/cosim_common.hpp"

namespace ceilnav::testbench {

// How blob_pixels draws a frame.
struct BlobStyle {
  int64_t dark_lo = 0;   // the noise ceiling, from [dark_lo, dark_hi]
  int64_t dark_hi = 80;  // (dark_lo == dark_hi: fixed, nothing drawn)
  int64_t blobs_lo = 0;  // rectangles per frame
  int64_t blobs_hi = 6;
  int64_t min_width = 1;   // rectangle widths from [min(min_width, w), max(min_width, w / 3)]
  int64_t level_lo = 120;  // rectangle level from [level_lo, 255], minus up to 30 per pixel
};

// Row-major grey pixels of a w x h frame: dark noise with bright rectangles.
inline std::vector<uint8_t> blob_pixels(Rng& rng, int w, int h, const BlobStyle& style) {
  std::vector<uint8_t> px(static_cast<size_t>(w) * static_cast<size_t>(h));
  const int64_t dark =
      style.dark_lo == style.dark_hi ? style.dark_lo : rng.uniform(style.dark_lo, style.dark_hi);
  for (auto& p : px) p = rng.uniform_as<uint8_t>(0, dark);
  const int64_t blobs = rng.uniform(style.blobs_lo, style.blobs_hi);
  for (int64_t b = 0; b < blobs; ++b) {
    const auto x0 = static_cast<int>(rng.uniform(0, w - 1));
    const auto y0 = static_cast<int>(rng.uniform(0, h - 1));
    const auto bw = static_cast<int>(rng.uniform(std::min<int64_t>(style.min_width, w),
                                                 std::max<int64_t>(style.min_width, w / 3)));
    const auto bh = static_cast<int>(rng.uniform(1, std::max(1, h / 3)));
    const auto level = static_cast<int>(rng.uniform(style.level_lo, 255));
    for (int y = y0; y < std::min(h, y0 + bh); ++y) {
      for (int x = x0; x < std::min(w, x0 + bw); ++x) {
        const int v = level - static_cast<int>(rng.uniform(0, 30));
        px[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] =
            static_cast<uint8_t>(std::max(0, v));
      }
    }
  }
  return px;
}

// The pixel beats of a well-formed frame of width w (no gaps).
inline std::vector<stream::VideoBeat> video_beats(const std::vector<uint8_t>& px, int w) {
  std::vector<stream::VideoBeat> beats(px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    beats[i].tvalid = true;
    beats[i].tdata = px[i];
    beats[i].tuser = i == 0;
    beats[i].tlast = static_cast<int>(i % static_cast<size_t>(w)) == w - 1;
  }
  return beats;
}

// A frame size of the pixel-stream block tests (thresh_lut, histogram), from
// a pick the caller drew: below small_below up to 8 x 8, below medium_below
// up to 80 x 60, else up to 640 x 480 with at most 40 000 pixels.
inline void pixel_frame_size(Rng& rng, int64_t pick, int64_t small_below, int64_t medium_below,
                             int& width, int& height) {
  if (pick < small_below) {
    width = static_cast<int>(rng.uniform(1, 8));
    height = static_cast<int>(rng.uniform(1, 8));
  } else if (pick < medium_below) {
    width = static_cast<int>(rng.uniform(1, 80));
    height = static_cast<int>(rng.uniform(1, 60));
  } else {
    width = static_cast<int>(rng.uniform(1, 640));
    height = static_cast<int>(rng.uniform(1, std::min<int64_t>(480, 40000 / width)));
  }
}

// Appends to `queue`: blanking of uniform(0, max_blanking) idle beats (none,
// and nothing drawn, if max_blanking < 0), then the beats, each after tvalid
// gaps while a coin with P(gap) = gap_p comes up.
inline void queue_video(std::deque<stream::VideoBeat>& queue, Rng& rng,
                        const std::vector<stream::VideoBeat>& beats, double gap_p,
                        int64_t max_blanking) {
  const int64_t idle = max_blanking >= 0 ? rng.uniform(0, max_blanking) : 0;
  for (int64_t k = 0; k < idle; ++k) queue.push_back(stream::VideoBeat{});
  for (const stream::VideoBeat& beat : beats) {
    while (gap_p > 0.0 && rng.chance(gap_p)) queue.push_back(stream::VideoBeat{});
    queue.push_back(beat);
  }
}

}  // namespace ceilnav::testbench
