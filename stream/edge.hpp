// edge: the edge detector of seed 002 eq. 17. An edge point is a pixel whose
// difference to its neighbour (horizontal, vertical or a 3x3 Sobel gradient)
// exceeds a threshold; every edge point becomes one beat of an AXI4-Stream
// master through a FIFO, with a per-frame trailer. See docs/blocks/edge.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/edge_record.hpp"
#include "fixedpoint/datapath.hpp"
#include "stream/beat.hpp"
#include "stream/line_window.hpp"

namespace ceilnav::stream {

// The widths live in fixedpoint/datapath.hpp (with their proofs).
namespace edge_widths {
using namespace fp::datapath::edge;  // NOLINT(google-build-using-namespace)
}  // namespace edge_widths

// m_axis_edges: stream::EdgeBeat (stream/beat.hpp), tdata as pack_edge_beat()
// / pack_edge_trailer() make it.

// The configuration port: EdgeConfig (common/edge_record.hpp), latched at
// the SOF pixel.

// Counters of one frame (published at its EOF pixel).
struct EdgeStats {
  uint32_t edges_emitted = 0;  // pushed into the FIFO (kFrameEdgeCountBits)
  uint32_t edges_dropped = 0;  // lost because the FIFO was full

  friend bool operator==(const EdgeStats&, const EdgeStats&) = default;
};

class EdgeDetector {
 public:
  static constexpr uint32_t kDefaultFifoDepth = 1024;

  // fifo_depth: entries of the edge FIFO memory, a power of two >= 8 (as the
  // RTL's FifoDepth); one entry is kept free for the frame's trailer.
  explicit EdgeDetector(uint32_t fifo_depth = kDefaultFifoDepth);

  // Synchronous active-low reset: FIFO empty, output idle, counters zero. The
  // line buffer keeps its contents (a frame reads only rows it wrote).
  void reset();

  // Configuration input port; its value at the SOF pixel's edge is latched.
  void set_config(const EdgeConfig& cfg) { cfg_in_ = cfg; }

  // One rising clock edge: samples the LutBeat port and m_axis_edges_tready.
  void clock(const LutBeat& in, bool m_axis_edges_tready);

  // Registered outputs.
  EdgeBeat m_axis_edges() const { return out_q_; }
  bool done() const { return done_q_; }  // one-cycle pulse: last_frame_stats() just updated
  // The event stage holds an edge point or a trailer that the next edge
  // admits to the FIFO (pending_o).
  bool pending() const { return stage_q_.abort || stage_q_.hit || stage_q_.eof; }
  const EdgeStats& last_frame_stats() const { return stats_q_; }
  uint32_t fifo_occupancy() const { return fifo_count_q_; }  // memory entries in use
  uint32_t fifo_depth() const { return static_cast<uint32_t>(fifo_.size()); }
  // Trailers lost because the FIFO was full at a frame's end or abort;
  // cumulative since reset, saturating. The next stored trailer carries
  // kEdgeTrailerOverflow.
  uint32_t trailers_lost() const { return trailers_lost_q_; }

  // Fast path: the edge points of a whole frame (row-major remap bytes) in
  // emission order, as the clocked path finds them with an infinite FIFO.
  static void scan_frame(const EdgeConfig& cfg, const uint8_t* remap, uint32_t width,
                         uint32_t height, std::vector<EdgeRecord>& edges);

 private:
  struct Entry {
    bool last = false;
    uint64_t tdata = 0;
  };
  // The events of one edge's input, admitted to the FIFO on the next edge.
  struct Stage {
    bool abort = false;  // the open frame was aborted: its trailer
    bool sof = false;    // a frame was taken: its counters restart
    bool hit = false;    // the pixel is an edge point: `edge`
    EdgeRecord edge{};
    bool eof = false;  // the frame's last pixel: its trailer and counters
  };
  EdgeConfig cfg_in_{};  // input port
  EdgeConfig cfg_q_{};   // latched at SOF

  LineWindow window_;  // the taken frame, the line buffer and the 3x3 window

  Stage stage_q_{};      // the event stage: the last edge's input, admitted on this one
  EdgeStats frame_q_{};  // counters of the open frame
  EdgeStats stats_q_{};  // latched at the last completed frame's EOF
  bool done_q_ = false;
  bool overflow_sticky_q_ = false;  // a trailer was lost: flag the next stored one
  uint32_t trailers_lost_q_ = 0;

  std::vector<Entry> fifo_;
  uint32_t fifo_head_q_ = 0;
  uint32_t fifo_count_q_ = 0;
  EdgeBeat out_q_{};  // output register of the FIFO
};

}  // namespace ceilnav::stream
