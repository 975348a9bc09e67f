// histogram: 256 bins per frame of the camera grey or the LUT remap, in a
// read-modify-write BRAM. Three banks rotate: one accumulates the open frame,
// one holds the published result, the third is cleared by a sweep (one bin
// per cycle) after it stops being the result, so that every frame starts in a
// bank of zeros and no per-bin valid bits are needed. See
// docs/blocks/histogram.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "common/limits.hpp"
#include "common/results.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream {

class Histogram {
 public:
  static constexpr size_t kBins = 256;
  static constexpr unsigned kBanks = 3;
  // A bin counts at most every pixel of the largest frame (fixedpoint/datapath.hpp).
  static constexpr int kBinBits = fp::datapath::histogram::kBinBits;
  // EOF pixel sampled on edge e -> done() high and results() switched on edge e+1.
  static constexpr int kDoneLatencyCycles = 1;
  // A dirty bank is cleared in this many edges (one bin per edge on its own
  // write port), starting the edge after it became dirty: it is clean again
  // kClearCycles + 1 edges after the edge that made it dirty. Every bank has
  // its own sweep, so two dirty banks clear at the same time.
  static constexpr int kClearCycles = static_cast<int>(kBins);

  // Power-on (configuration) state: every bank holds zeros, bank 0 is the
  // result bank, nothing published yet.
  Histogram() { reset(); }

  // Reset: no frame open, nothing published (reads give 0), done low, the
  // clear sweep restarts. The banks, like the BRAM they model, keep their
  // contents and their clean/dirty state, except that the bank of the last
  // frame becomes dirty (it may hold a partial count): a frame may start
  // right after a reset.
  void reset();

  // Mealy output for the beat on the input: the histogram counts the frame
  // this beat belongs to (for an SOF beat: a cleared bank is free for it).
  // The pipeline drops an EOF the histogram does not count (moment_gen's
  // eof_drop), so that every published frame has its histogram.
  bool counts(const LutBeat& s_lut) const;

  // One rising edge. source_remap is the configuration input (false = camera
  // grey, true = LUT remap); it is latched on the SOF beat. keep (RTL keep_i)
  // is sampled with the EOF beat: high = the pipeline publishes this frame
  // (the bank becomes the result bank on the next edge), low = the frame is
  // dropped (its bank is cleared).
  void clock(const LutBeat& s_lut, bool source_remap, bool keep = true);

  // One rising edge with the results read port (RTL hist_rd_en_i,
  // hist_rd_bin_i) sampled too. BRAM-style synchronous read: a read sampled on
  // edge t returns, after edge t, read_bin(rd_bin) as it was before edge t;
  // after an edge without a read, hist_rd_data() is 0.
  void clock(const LutBeat& s_lut, bool source_remap, bool keep, bool rd_en, uint8_t rd_bin);

  // Fast path: one complete frame of 8-bit values (grey or remap already
  // chosen by the caller), row stride in bytes. Leaves the block as clock()-ing
  // the frame followed by enough gap cycles to finish every clear sweep would
  // (done() low again).
  void process_frame(const uint8_t* values, int width, int height, size_t stride_bytes);
  // Fast path, when the caller has counted the bins itself.
  void publish_frame(const std::array<uint32_t, kBins>& bins);

  // Registered outputs. done() is a one-cycle pulse; results() are the bins of
  // the last published frame (0 before the first one), stable until the next
  // done().
  bool done() const { return done_q_; }
  HistogramResults results() const;
  // One bin of results() (what the register file reads through the port).
  uint32_t read_bin(uint8_t bin) const;
  // Registered output of the read port (hist_rd_data_o).
  uint32_t hist_rd_data() const { return rd_data_q_; }
  // Bank state, for tests: bank b needs clearing / is being cleared.
  bool dirty(unsigned b) const { return dirty_q_[b]; }

 private:
  // The lowest-numbered clean bank that is neither the result bank nor the
  // bank of the frame before (kBanks if none).
  unsigned free_bank() const;
  void clear_step();

  // BRAM contents and the state that describes them: not reset (they are
  // initialised with the configuration, as the BRAM is).
  std::array<std::array<uint32_t, kBins>, kBanks> count_{};
  std::array<bool, kBanks> dirty_q_{};
  unsigned disp_bank_q_ = 0;  // result bank (read port)
  unsigned acc_bank_q_ = 0;   // bank of the open or last frame

  bool counting_q_ = false;  // the open frame is counted in acc_bank_q_
  bool frame_open_q_ = false;
  bool source_remap_q_ = false;
  bool eof_q_ = false;  // a kept EOF pixel sampled on the previous edge
  bool done_q_ = false;
  bool res_valid_q_ = false;  // a frame has been published since reset
  std::array<bool, kBanks> clr_busy_q_{};
  std::array<unsigned, kBanks> clr_ptr_q_{};
  uint32_t rd_data_q_ = 0;
};

}  // namespace ceilnav::stream
