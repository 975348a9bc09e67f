// histogram: 256 bins per frame of the camera grey or the LUT remap, in a
// read-modify-write BRAM, ping-pong banked with a flash-cleared valid bit per
// bin so that frames may follow with zero blanking. See docs/blocks/histogram.md.
#pragma once

#include <array>
#include <bitset>
#include <cstddef>
#include <cstdint>

#include "stream/beat.hpp"
#include "stream/limits.hpp"
#include "stream/results.hpp"

namespace ceilnav::stream {

class Histogram {
 public:
  static constexpr size_t kBins = 256;
  // A bin counts at most every pixel of the largest frame (fixedpoint/datapath.hpp).
  static constexpr int kBinBits = fp::datapath::histogram::kBinBits;
  // EOF pixel sampled on edge e -> done() high and results() switched on edge e+1.
  static constexpr int kDoneLatencyCycles = 1;

  Histogram() { reset(); }

  // Asynchronous active-low reset: no frame open, both banks invalid, done low.
  void reset();

  // One rising edge. source_remap is the configuration input (false = camera
  // grey, true = LUT remap); it is latched on the SOF beat.
  void clock(const LutBeat& s_lut, bool source_remap);

  // One rising edge with the results read port (RTL hist_rd_en_i,
  // hist_rd_bin_i) sampled too. BRAM-style synchronous read: a read sampled on
  // edge t returns, after edge t, read_bin(rd_bin) as it was before edge t;
  // after an edge without a read, hist_rd_data() is 0.
  void clock(const LutBeat& s_lut, bool source_remap, bool rd_en, uint8_t rd_bin);

  // Fast path: one complete frame of 8-bit values (grey or remap already
  // chosen by the caller), row stride in bytes. Leaves the block as clock()-ing
  // the frame followed by two gap cycles would (done() low again).
  void process_frame(const uint8_t* values, int width, int height, size_t stride_bytes);
  // Fast path, when the caller has counted the bins itself.
  void publish_frame(const std::array<uint32_t, kBins>& bins);

  // Registered outputs. done() is a one-cycle pulse; results() are the bins of
  // the last complete (non-aborted) frame, stable until the next done().
  bool done() const { return done_q_; }
  HistogramResults results() const;
  // One bin of results() (what the register file reads through the port).
  uint32_t read_bin(uint8_t bin) const;
  // Registered output of the read port (hist_rd_data_o).
  uint32_t hist_rd_data() const { return rd_data_q_; }

 private:
  struct Bank {
    std::array<uint32_t, kBins> count{};  // BRAM, 23 bits used
    std::bitset<kBins> valid;             // flip-flops, flash-cleared at SOF
  };

  void start_frame(unsigned bank);

  std::array<Bank, 2> bank_{};
  unsigned acc_bank_q_ = 0;   // bank the open frame accumulates into
  unsigned disp_bank_q_ = 1;  // bank results() reads
  unsigned fin_bank_q_ = 0;   // bank that completed on the previous edge
  bool frame_open_q_ = false;
  bool source_remap_q_ = false;
  bool eof_q_ = false;  // EOF pixel sampled on the previous edge
  bool done_q_ = false;
  uint32_t rd_data_q_ = 0;
};

}  // namespace ceilnav::stream
