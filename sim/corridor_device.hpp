// The device's corridor blocks (edge -> hough, seed 002 eq. 17-18) on one
// frame as the host reads them, frame after frame: the host's edge
// threshold rule (corridor::edge_threshold), the rho bins sized to the frame,
// the Hough weight shift carried from frame to frame
// (CorridorGuide::next_weight_shift) and the published accumulator with the
// hardware's saturating cells. It runs stream::EdgeHoughFast, bit exact with
// the blocks' golden references (and so with their cycle models and the RTL
// on the cells they publish). Used by `ceilnav corridor` and the closed-loop
// corridor drive (corridor_drive.hpp). docs/corridor.md, "ceilnav corridor".
#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "common/hough_params.hpp"
#include "host/corridor/hough_lines.hpp"
#include "stream/edge_hough_fast.hpp"

namespace ceilnav::sim {

// The hough shape the pan and shift goals need (docs/corridor.md, "Lines,
// vanishing points and pan"): 1-deg thetas, 512 rho bins, 12-bit cells, 8
// lanes.
stream::HoughShape corridor_hough_shape();

// The first frame's weight shift: one edge per row on a line can give a
// cell at most sum (y + 1) = H (H + 1) / 2 (eq. 18), which must fit the cell.
uint8_t initial_weight_shift(int image_height, const stream::HoughShape& shape);

struct CorridorDeviceFrame {
  host::corridor::Accumulator acc;  // as published: cells clipped at acc_max
  uint32_t edges = 0;
  uint16_t threshold = 0;      // the eq. 17 threshold this frame was scanned with
  uint32_t clipped_cells = 0;  // cells the votes drove past acc_max (0 iff HOUGH_SATURATED is 0)
};

class CorridorDevice {
 public:
  CorridorDevice(const stream::HoughShape& shape, int image_width, int image_height);
  // One 8-bit frame of the configured size (throws std::invalid_argument
  // otherwise); the next frame's weight shift follows from this one's cells.
  const CorridorDeviceFrame& process(const cv::Mat& grey);
  uint8_t weight_shift() const { return weight_shift_; }

 private:
  stream::HoughShape shape_;
  int width_, height_;
  stream::EdgeHoughFast fast_;
  uint8_t weight_shift_;
  uint8_t rho_shift_ = 0;
  CorridorDeviceFrame frame_;
};

}  // namespace ceilnav::sim
