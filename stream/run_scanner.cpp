#include "stream/run_scanner.hpp"

#include <algorithm>
#include <stdexcept>

namespace ceilnav::stream {

namespace {

// w = max(0, remap - background_level), 8 bits.
inline uint32_t weight(uint8_t remap, uint8_t background_level) {
  return remap > background_level ? uint32_t{remap} - background_level : 0u;
}

inline uint32_t wrap(uint64_t v, int bits) {
  return static_cast<uint32_t>(v & ((uint64_t{1} << bits) - 1));
}

}  // namespace

RunScanner::RunScanner(uint32_t fifo_depth) {
  if (fifo_depth < 2) {
    throw std::invalid_argument("RunScanner: fifo_depth must be >= 2");
  }
  fifo_.resize(fifo_depth);
  reset();
}

void RunScanner::reset() {
  cfg_q_ = {};
  frame_open_q_ = false;
  x_q_ = 0;
  y_q_ = 0;
  prev_w_q_ = 0;
  in_run_q_ = false;
  run_start_q_ = 0;
  run_sum_w_q_ = 0;
  run_sum_xw_q_ = 0;
  row_runs_q_ = 0;
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

void RunScanner::clock(const LutBeat& in, bool m_axis_runs_tready) {
  using namespace run_scanner_widths;
  const uint32_t depth = fifo_depth();

  // ---- FIFO read side: the output register takes the head entry when it is
  // empty or being transferred. Admission below uses the pre-edge count only.
  bool pop = false;
  RunBeat out_d = out_q_;
  if (!out_q_.tvalid || m_axis_runs_tready) {
    if (fifo_count_q_ > 0) {
      const Entry& e = fifo_[fifo_head_q_];
      out_d = {true, e.last, e.data};
      pop = true;
    } else {
      out_d = {};
    }
  }

  Entry writes[3];  // aborted-frame trailer, run, trailer
  uint32_t n_writes = 0;
  bool done_d = false;
  RunStats frame_d = frame_q_;
  bool sticky_d = overflow_sticky_q_;

  auto push_trailer = [&](uint16_t flags) {
    if (sticky_d) flags = static_cast<uint16_t>(flags | kTrailerFifoOverflow);
    if (fifo_count_q_ + n_writes < depth) {
      Entry t;
      t.last = true;
      t.data.row = static_cast<uint16_t>(std::min<uint32_t>(frame_d.runs_emitted, 0xFFFF));
      t.data.x_start = flags;
      writes[n_writes++] = t;
      sticky_d = false;
    } else {
      if (trailers_lost_q_ != UINT32_MAX) ++trailers_lost_q_;
      sticky_d = true;
    }
  };
  auto frame_flags = [&]() {
    uint16_t flags = 0;
    if (frame_d.runs_dropped_row_limit != 0) flags |= kTrailerRowLimitHit;
    if (frame_d.runs_dropped_overflow != 0) flags |= kTrailerFifoOverflow;
    return flags;
  };

  const PixelBeat& pix = in.pix;
  const bool take = pix.valid && (pix.sof || frame_open_q_);
  if (take) {
    // frame_check cuts a frame short with an early SOF in one beat (abort,
    // valid and sof together): close the aborted frame before the new one.
    if (pix.abort && frame_open_q_) {
      push_trailer(static_cast<uint16_t>(frame_flags() | kTrailerFrameAborted));
    }
    if (pix.sof) {
      cfg_q_ = cfg_in_;
      frame_d = {};
    }
    const RunScanConfig& cfg = cfg_q_;
    const uint32_t x = pix.sof ? 0u : x_q_;
    const uint32_t y = pix.sof ? 0u : y_q_;
    if (x != pix.x || y != pix.y) {
      throw std::logic_error("RunScanner: pixel position differs from the counters");
    }
    const bool row_start = x == 0;
    const bool in_run = !row_start && in_run_q_;  // SOF/EOL leave no run open
    const uint32_t row_runs = row_start ? 0u : row_runs_q_;
    const uint32_t w = weight(in.remap, cfg.background_level);
    const uint32_t prev_w = row_start ? 0u : prev_w_q_;  // left margin clipped at x = 0

    // Run sums including this pixel (as run pixel or as right margin).
    uint32_t start = run_start_q_;
    uint64_t sum_w = run_sum_w_q_ + w;
    uint64_t sum_xw = run_sum_xw_q_ + uint64_t{x} * w;
    if (in.mask && !in_run) {  // run starts here; the previous pixel is its left margin
      start = x;
      sum_w = prev_w + w;
      sum_xw = (row_start ? 0u : uint64_t{x - 1} * prev_w) + uint64_t{x} * w;
    }
    bool end_run = false;
    uint32_t end = 0;
    if (in.mask && pix.eol) {  // the run reaches the end of the line: no right margin
      end_run = true;
      end = x;
    } else if (!in.mask && in_run) {  // this mask-0 pixel is the right margin
      end_run = true;
      end = x - 1;
    }

    uint32_t row_runs_d = row_runs;
    if (end_run && end - start + 1 >= cfg.min_run_length) {
      if (row_runs < cfg.max_runs_per_row) {
        ++row_runs_d;
        if (fifo_count_q_ + n_writes + 1 < depth) {  // one entry stays free for the trailer
          Entry r;
          r.data.row = static_cast<uint16_t>(y);
          r.data.x_start = static_cast<uint16_t>(start);
          r.data.x_end = static_cast<uint16_t>(end);
          r.data.sum_w = wrap(sum_w, kSumWBits);
          r.data.sum_xw = wrap(sum_xw, kSumXwBits);
          writes[n_writes++] = r;
          ++frame_d.runs_emitted;
        } else {
          ++frame_d.runs_dropped_overflow;
        }
      } else {
        ++frame_d.runs_dropped_row_limit;
      }
    }

    in_run_q_ = in.mask && !pix.eol;
    run_start_q_ = static_cast<uint16_t>(start);
    run_sum_w_q_ = wrap(sum_w, kSumWBits);
    run_sum_xw_q_ = wrap(sum_xw, kSumXwBits);
    prev_w_q_ = static_cast<uint8_t>(w);
    row_runs_q_ = static_cast<uint16_t>(row_runs_d);
    x_q_ = static_cast<uint16_t>(pix.eol ? 0u : wrap(x + 1, kCoordBits));
    y_q_ = static_cast<uint16_t>(pix.eol ? wrap(y + 1, kCoordBits) : y);

    if (pix.eof) {
      push_trailer(frame_flags());
    }
  } else if (pix.abort && frame_open_q_) {
    push_trailer(static_cast<uint16_t>(frame_flags() | kTrailerFrameAborted));
  }

  // ---- Commit the FIFO: writes at the tail (pre-edge), read at the head.
  for (uint32_t i = 0; i < n_writes; ++i) {
    fifo_[(fifo_head_q_ + fifo_count_q_ + i) % depth] = writes[i];
  }
  if (pop) fifo_head_q_ = (fifo_head_q_ + 1) % depth;
  fifo_count_q_ = fifo_count_q_ - (pop ? 1u : 0u) + n_writes;

  if (take) {
    frame_d.fifo_high_water =
        pix.sof ? fifo_count_q_ : std::max(frame_d.fifo_high_water, fifo_count_q_);
    if (pix.eof) {
      stats_q_ = frame_d;
      done_d = true;
    }
    frame_open_q_ = !pix.eof;
  } else if (pix.abort) {
    frame_open_q_ = false;
  }
  frame_q_ = frame_d;
  overflow_sticky_q_ = sticky_d;
  out_q_ = out_d;
  done_q_ = done_d;
}

void RunScanner::scan_row(const RunScanConfig& cfg, uint16_t y, const uint8_t* remap,
                          const uint8_t* mask, uint32_t width, std::vector<RunRecord>& runs,
                          uint32_t& dropped_row_limit) {
  const uint8_t bg = cfg.background_level;
  uint32_t row_runs = 0;
  uint32_t x = 0;
  while (x < width) {
    if (mask[x] == 0) {
      ++x;
      continue;
    }
    const uint32_t start = x;
    uint32_t sum_w = 0;
    uint32_t sum_xw = 0;
    if (start > 0) {
      const uint32_t wl = weight(remap[start - 1], bg);
      sum_w = wl;
      sum_xw = (start - 1) * wl;
    }
    while (x < width && mask[x] != 0) {
      const uint32_t w = weight(remap[x], bg);
      sum_w += w;
      sum_xw += x * w;
      ++x;
    }
    const uint32_t end = x - 1;
    if (x < width) {  // right margin: the first mask-0 pixel
      const uint32_t wr = weight(remap[x], bg);
      sum_w += wr;
      sum_xw += x * wr;
    }
    if (end - start + 1 < cfg.min_run_length) continue;
    if (row_runs >= cfg.max_runs_per_row) {
      ++dropped_row_limit;
      continue;
    }
    ++row_runs;
    runs.push_back({y, static_cast<uint16_t>(start), static_cast<uint16_t>(end), sum_w, sum_xw});
  }
}

}  // namespace ceilnav::stream
