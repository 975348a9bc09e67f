// What the host reads back of the corridor blocks for one frame
// (docs/blocks/ceilnav_top.md, "Corridor readout"): the hough block's
// published accumulator with its shape and configuration, and the edge /
// hough counters. Filled by host::Driver::read_corridor through the
// registers, and by drivers::Device's fast backend from the pipeline model.
#pragma once

#include <cstdint>
#include <vector>

#include "common/edge_record.hpp"
#include "common/hough_params.hpp"

namespace ceilnav::stream {

struct CorridorReadout {
  bool valid = false;        // HOUGH_STATUS.RESULTS_VALID: a frame is published
  HoughShape shape;          // HOUGH_SHAPE (the device's compile-time shape)
  EdgeConfig edge;           // EDGE_CONTROL as the host programmed it for the frame
  HoughConfig config;        // HOUGH_CONTROL / HOUGH_GEOMETRY as programmed for the frame
  uint32_t frame_count = 0;  // HOUGH_FRAME_COUNT: hough publications since reset
  // The accumulator, j-major: shape.n_theta() x shape.rho_bins() cells,
  // cell (j, rho) at j * rho_bins + rho (golden::hough_ref's order, saturated
  // at shape.acc_max()); j counts theta cells from config.theta_first.
  std::vector<uint32_t> cells;
  HoughCounters counters;  // HOUGH_EDGES .. HOUGH_TRAILER_FLAGS of the frame
  // Of the frame as the edge block's trailer reports it: edges emitted and
  // dropped (HOUGH_TRAILER_EDGES, bits 31:16 of HOUGH_TRAILER_FLAGS).
  uint32_t edges_emitted() const { return counters.trailer_edges; }
  uint32_t edges_dropped() const { return counters.trailer_flags >> 16; }
  bool edge_overflow() const { return (counters.trailer_flags & kEdgeTrailerOverflow) != 0; }
  // Live, since reset: EDGE_TRAILERS_LOST and HOUGH_STALLS (cycle-dependent:
  // 0 on the fast backend, which has no clock).
  uint32_t edge_trailers_lost = 0;
  uint32_t hough_stalls = 0;
  bool consistent = true;  // HOUGH_FRAME_COUNT unchanged across the readout

  uint32_t cell(int j, uint32_t rho) const {
    return cells[static_cast<size_t>(j) * shape.rho_bins() + rho];
  }
};

}  // namespace ceilnav::stream
