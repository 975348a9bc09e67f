// The edge -> hough fast path for software: the edge points of a whole frame
// (seed 002 eq. 17, as EdgeDetector::scan_frame) and their weighted Hough
// accumulator (eq. 18, as golden::hough_ref: unsaturated 64-bit cells), at
// frame rate on one core. Bit exact with golden::find_edges_ref and
// golden::hough_ref on its output (stream/tests/edge_hough_fast_test.cpp);
// the cycle models stay the reference of the hardware's timing, FIFO and
// saturating cells. How it is fast (docs/blocks/edge.md, docs/blocks/hough.md,
// "Fast path"): the edges row by row without per-pixel branches (a
// difference / magnitude row, a 0/1 row of magnitude > t, compaction eight
// pixels per 64-bit word); the votes theta-major from per-theta integer
// cos/sin (the s1.14 table of fixedpoint/hough_trig.hpp, the same rounding)
// over the frame's edge coordinates, into four interleaved copies of one rho
// row (no store-to-load chain when consecutive edges hit one cell). Buffers
// grow with the largest frame seen and are reused: no allocation per frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "stream/edge.hpp"

namespace ceilnav::stream {

class EdgeHoughFast {
 public:
  // shape: as stream::Hough's (theta_step dividing 180, rho_bits 1 .. 12);
  // throws std::invalid_argument otherwise.
  explicit EdgeHoughFast(const HoughShape& shape = HoughShape{});

  // The edge points of `remap` (row-major, `stride` bytes between rows,
  // 1 <= width, height <= 2048) under cfg.mode and cfg.threshold (cfg.enable
  // is not looked at, as in scan_frame), in raster order. Returns edges().
  std::span<const EdgeRecord> find_edges(const EdgeConfig& cfg, const uint8_t* remap,
                                         uint32_t width, uint32_t height, size_t stride);

  // Votes the edges of the last find_edges() under cfg. An enabled cfg must be
  // in the register ranges: weight_shift <= 15, rho_shift <= 7, width <= 4095
  // (throws std::invalid_argument otherwise); a disabled one votes nothing.
  // Returns accumulator().
  std::span<const uint64_t> vote(const HoughConfig& cfg);

  // find_edges then vote: pixels in, accumulator out.
  std::span<const uint64_t> run(const EdgeConfig& edge_cfg, const HoughConfig& hough_cfg,
                                const uint8_t* remap, uint32_t width, uint32_t height,
                                size_t stride) {
    find_edges(edge_cfg, remap, width, height, stride);
    return vote(hough_cfg);
  }

  std::span<const EdgeRecord> edges() const { return {records_.data(), n_edges_}; }
  // golden::hough_ref's layout: j-major n_theta x rho_bins, row j the range's
  // j-th theta, rows past the range (and every row of a disabled cfg) 0.
  std::span<const uint64_t> accumulator() const { return acc_; }
  uint64_t votes() const { return votes_; }      // votes that landed in a cell
  uint64_t dropped() const { return dropped_; }  // votes with a rho index outside the bins
  const HoughShape& shape() const { return shape_; }

 private:
  void reserve(uint32_t width, uint32_t height);

  HoughShape shape_;
  // Per edge: record (the edge list), coordinates and weight (the voter's input).
  std::vector<EdgeRecord> records_;
  std::vector<int32_t> xs_;
  std::vector<int32_t> ys_;
  size_t n_edges_ = 0;
  // Row buffers (padded to whole 64-bit words): magnitude, rises, magnitude > t.
  std::vector<int16_t> mag_;
  std::vector<uint8_t> rises_;
  std::vector<uint8_t> hit_;
  std::vector<int16_t> tmp_;  // Sobel: the smoothed column sums of a row
  std::vector<int16_t> tmp2_;
  // Voter scratch: one block of edges' rho indices (one theta) and weights.
  std::vector<uint32_t> idx_;
  std::vector<uint64_t> w_;
  // Per theta of the range, kCopies copies of its rho row, each bins + 1 cells.
  std::vector<uint64_t> rows_;
  std::vector<uint64_t> acc_;
  uint64_t votes_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace ceilnav::stream
