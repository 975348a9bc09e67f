#include "stream/edge.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace ceilnav::stream {

namespace {

// The edge test of the pixel at (x, y) with its window: true and *e filled if
// the pixel (or, for Sobel, the window centre) is an edge point.
bool detect(EdgeMode mode, uint16_t threshold, uint32_t x, uint32_t y, const Window3x3& w,
            EdgeRecord* e) {
  int d = 0;
  int mag = 0;
  bool rises = false;
  EdgeKind kind = EdgeKind::kHorizontal;
  uint32_t ex = x;
  uint32_t ey = y;
  switch (mode) {
    case EdgeMode::kHorizontal:
      if (x < 1) return false;
      d = int{w.b2} - int{w.b1};
      mag = std::abs(d);
      rises = d > 0;
      break;
    case EdgeMode::kVertical:
      if (y < 1) return false;
      d = int{w.b2} - int{w.m2};
      mag = std::abs(d);
      rises = d > 0;
      kind = EdgeKind::kVertical;
      break;
    case EdgeMode::kSobel: {
      if (x < 2 || y < 2) return false;
      const int gx = sobel_gx(w);
      const int gy = sobel_gy(w);
      mag = std::min(4095, std::abs(gx) + std::abs(gy));
      rises = gx > 0;
      kind = EdgeKind::kSobel;
      ex = x - 1;
      ey = y - 1;
      break;
    }
    case EdgeMode::kReserved:
      return false;
  }
  if (mag <= int{threshold}) return false;
  *e = {static_cast<uint16_t>(ex), static_cast<uint16_t>(ey), static_cast<uint16_t>(mag), rises,
        kind};
  return true;
}

}  // namespace

EdgeDetector::EdgeDetector(uint32_t fifo_depth) {
  if (fifo_depth < 8 || (fifo_depth & (fifo_depth - 1)) != 0) {
    throw std::invalid_argument("EdgeDetector: fifo_depth must be a power of two >= 8");
  }
  fifo_.resize(fifo_depth);
  reset();
}

void EdgeDetector::reset() {
  cfg_q_ = {};
  window_.reset();
  stage_q_ = {};
  frame_q_ = {};
  stats_q_ = {};
  done_q_ = false;
  overflow_sticky_q_ = false;
  trailers_lost_q_ = 0;
  std::fill(fifo_.begin(), fifo_.end(), Entry{});
  fifo_head_q_ = 0;
  fifo_count_q_ = 0;
  out_q_ = {};
}

void EdgeDetector::clock(const LutBeat& in, bool m_axis_edges_tready) {
  const uint32_t depth = fifo_depth();

  // ---- FIFO read side (pre-edge count), as run_scanner's.
  bool pop = false;
  EdgeBeat out_d = out_q_;
  if (!out_q_.tvalid || m_axis_edges_tready) {
    if (fifo_count_q_ > 0) {
      const Entry& e = fifo_[fifo_head_q_];
      out_d = {true, e.last, e.tdata};
      pop = true;
    } else {
      out_d = {};
    }
  }

  // ---- Admission of the events staged on the last edge, against the
  // pre-edge occupancy. At most two writes per edge: (aborted trailer |
  // edge), trailer.
  Entry writes[2];
  uint32_t n_writes = 0;
  bool done_d = false;
  EdgeStats frame_d = frame_q_;
  bool sticky_d = overflow_sticky_q_;

  auto push_trailer = [&](bool aborted) {
    uint32_t flags = aborted ? kEdgeTrailerAborted : 0u;
    if (frame_d.edges_dropped != 0 || sticky_d) flags |= kEdgeTrailerOverflow;
    if (fifo_count_q_ + n_writes < depth) {
      writes[n_writes++] = {true,
                            pack_edge_trailer(frame_d.edges_emitted, flags, frame_d.edges_dropped)};
      sticky_d = false;
    } else {
      if (trailers_lost_q_ != UINT32_MAX) ++trailers_lost_q_;
      sticky_d = true;
    }
  };

  // frame_check's early SOF (abort with the next SOF pixel) or a lone abort
  // closes the open frame first.
  if (stage_q_.abort) push_trailer(true);
  if (stage_q_.sof) frame_d = {};
  if (stage_q_.hit) {
    if (fifo_count_q_ + n_writes + 1 < depth) {  // one entry stays free for the trailer
      writes[n_writes++] = {false, pack_edge_beat(stage_q_.edge)};
      ++frame_d.edges_emitted;
    } else {
      ++frame_d.edges_dropped;
    }
  }
  if (stage_q_.eof) {
    push_trailer(false);
    stats_q_ = frame_d;
    done_d = true;
  }

  // ---- Commit the FIFO: writes at the tail (pre-edge), read at the head.
  for (uint32_t i = 0; i < n_writes; ++i) {
    fifo_[(fifo_head_q_ + fifo_count_q_ + i) % depth] = writes[i];
  }
  if (pop) fifo_head_q_ = (fifo_head_q_ + 1) % depth;
  fifo_count_q_ = fifo_count_q_ - (pop ? 1u : 0u) + n_writes;
  frame_q_ = frame_d;
  overflow_sticky_q_ = sticky_d;
  out_q_ = out_d;
  done_q_ = done_d;

  // ---- The pixel: its edge test, staged for the next edge's admission.
  const PixelBeat& pix = in.pix;
  Stage stage_d{};
  const LineWindow::Pixel px = window_.clock(pix, in.remap, cfg_in_.enable, "EdgeDetector");
  stage_d.abort = px.abort;
  if (px.take) {
    if (pix.sof) cfg_q_ = cfg_in_;
    stage_d.sof = pix.sof;
    stage_d.hit = detect(cfg_q_.mode, cfg_q_.threshold, px.x, px.y, px.w, &stage_d.edge);
    stage_d.eof = pix.eof;
  }
  stage_q_ = stage_d;
}

void EdgeDetector::scan_frame(const EdgeConfig& cfg, const uint8_t* remap, uint32_t width,
                              uint32_t height, std::vector<EdgeRecord>& edges) {
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      EdgeRecord e;
      if (detect(cfg.mode, cfg.threshold, x, y, frame_window(remap, width, x, y), &e)) {
        edges.push_back(e);
      }
    }
  }
}

}  // namespace ceilnav::stream
