// run_scanner: per row, runs of mask = 1 with intensity sums for a sub-pixel
// centre, through a FIFO onto an AXI4-Stream master with a per-frame trailer.
// See docs/blocks/run_scanner.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/limits.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream {

// The widths live in fixedpoint/datapath.hpp (with their proofs).
namespace run_scanner_widths {
using namespace fp::datapath::run_scanner;  // NOLINT(google-build-using-namespace)
}  // namespace run_scanner_widths

// m_axis_runs_tdata: the RunRecord packed into 112 bits, no field crossing a
// 32-bit word, as the RTL port (rtl_model/run_scanner.sv) and the register
// file carry it. words[i] = tdata[32 i + 31 : 32 i]; bits 127:112 are 0.
//   [15:0] row (trailer: runs emitted)   [31:16] x_start (trailer: flags)
//   [63:32] sum_w   [95:64] sum_xw   [111:96] x_end
inline constexpr int kRunBeatBits = 112;
using RunBeatWords = std::array<uint32_t, 4>;

// Exact for every record the run scanner makes (sum_xw < 2^29, sum_w < 2^19);
// wider sums are cut to 32 bits, which unpack_run_beat() would expose.
constexpr RunBeatWords pack_run_beat(const RunRecord& r) {
  return {static_cast<uint32_t>(r.row) | (static_cast<uint32_t>(r.x_start) << 16), r.sum_w,
          static_cast<uint32_t>(r.sum_xw), static_cast<uint32_t>(r.x_end)};
}

constexpr RunRecord unpack_run_beat(const RunBeatWords& w) {
  RunRecord r;
  r.row = static_cast<uint16_t>(w[0] & 0xFFFFu);
  r.x_start = static_cast<uint16_t>(w[0] >> 16);
  r.sum_w = w[1];
  r.sum_xw = w[2];
  r.x_end = static_cast<uint16_t>(w[3] & 0xFFFFu);
  return r;
}

// The configuration fields the run scanner uses (latched at the SOF pixel).
struct RunScanConfig {
  uint8_t background_level = 0;
  uint16_t min_run_length = 1;
  uint16_t max_runs_per_row = 8;

  static RunScanConfig from(const PipelineConfig& c) {
    return {c.background_level, c.min_run_length, c.max_runs_per_row};
  }
  friend bool operator==(const RunScanConfig&, const RunScanConfig&) = default;
};

class RunScanner {
 public:
  static constexpr uint32_t kDefaultFifoDepth = 1024;

  // fifo_depth: entries of the run FIFO memory (>= 2; one entry is kept free
  // for the frame's trailer).
  explicit RunScanner(uint32_t fifo_depth = kDefaultFifoDepth);

  // Synchronous active-low reset: FIFO empty, output idle, counters zero.
  void reset();

  // Configuration input port (the pipeline's active config). Its value at the
  // clock edge of the SOF pixel is latched and used for the whole frame.
  void set_active_config(const RunScanConfig& cfg) { cfg_in_ = cfg; }
  void set_active_config(const PipelineConfig& cfg) { cfg_in_ = RunScanConfig::from(cfg); }

  // One rising clock edge: samples the LutBeat port and m_axis_runs_tready.
  void clock(const LutBeat& in, bool m_axis_runs_tready);

  // Registered outputs.
  RunBeat m_axis_runs() const { return out_q_; }
  bool done() const { return done_q_; }  // one-cycle pulse: last_frame_stats() just updated
  const RunStats& last_frame_stats() const { return stats_q_; }  // last completed frame
  uint32_t fifo_occupancy() const { return fifo_count_q_; }      // memory entries in use
  uint32_t fifo_depth() const { return static_cast<uint32_t>(fifo_.size()); }
  // Trailers lost because the FIFO was completely full at frame end (the
  // consumer read nothing since the previous trailer took the last entry).
  // Cumulative since reset, saturating. The next trailer that is stored
  // carries kTrailerFifoOverflow.
  uint32_t trailers_lost() const { return trailers_lost_q_; }

  // Fast path: the runs of one row in emission order (no FIFO: infinite),
  // as the clocked path finds them. mask bytes: nonzero = 1. Runs beyond
  // max_runs_per_row are counted in dropped_row_limit.
  static void scan_row(const RunScanConfig& cfg, uint16_t y, const uint8_t* remap,
                       const uint8_t* mask, uint32_t width, std::vector<RunRecord>& runs,
                       uint32_t& dropped_row_limit);

 private:
  struct Entry {
    bool last = false;
    RunRecord data{};
  };
  void push(const Entry& e);

  RunScanConfig cfg_in_{};  // input port
  RunScanConfig cfg_q_{};   // latched at SOF

  bool frame_open_q_ = false;
  uint16_t x_q_ = 0;  // column of the next pixel (kCoordBits)
  uint16_t y_q_ = 0;
  uint8_t prev_w_q_ = 0;  // w of the previous pixel on the row (left margin)
  bool in_run_q_ = false;
  uint16_t run_start_q_ = 0;
  uint32_t run_sum_w_q_ = 0;   // kSumWBits
  uint32_t run_sum_xw_q_ = 0;  // kSumXwBits
  uint16_t row_runs_q_ = 0;    // runs of this row past min_run_length (kRowRunCountBits)

  RunStats frame_q_{};  // counters of the open frame
  RunStats stats_q_{};  // latched at the EOF of the last completed frame
  bool done_q_ = false;
  bool overflow_sticky_q_ = false;  // a trailer was lost: flag the next stored one
  uint32_t trailers_lost_q_ = 0;

  std::vector<Entry> fifo_;  // BRAM, four banks (address mod 4): up to 3 writes per edge
  uint32_t fifo_head_q_ = 0;
  uint32_t fifo_count_q_ = 0;
  RunBeat out_q_{};  // output register of the FIFO
};

}  // namespace ceilnav::stream
