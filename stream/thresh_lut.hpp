// thresh_lut: the programmable 256 x 11-bit threshold LUT (bits 7:0 remap,
// bit 8 mask, bits 10:9 class) with a synchronous read, double-banked so that a frame never
// sees a half-written table. See docs/blocks/thresh_lut.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "common/pipeline_config.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream {

// Host write port of the LUT as RTL ports (lut_wr_en_i, lut_wr_index_i,
// lut_wr_data_i), sampled on a clock edge.
struct LutWrite {
  bool en = false;
  uint8_t index = 0;
  LutEntry data = 0;  // bits above bit 10 are ignored
};

class ThreshLut {
 public:
  static constexpr int kEntryBits = 11;
  static constexpr size_t kEntries = 256;
  static constexpr int kLatencyCycles = 1;

  ThreshLut() { reset(); }

  // Synchronous active-low reset of the registers: bank select, pending flag
  // and output. The BRAM contents are not reset (as in hardware); the model
  // zeroes them only at construction.
  void reset();

  // Host write port: writes the shadow (inactive) bank and marks a commit
  // pending. Bits above bit 10 of entry are ignored.
  void write(uint8_t index, LutEntry entry);

  // One rising edge. Samples s_pix, reads the ACTIVE bank at s_pix.grey (the
  // read happens before the bank flip of the same edge). frame_start is the
  // frame-start strobe: asserted on the edge at which frame_check accepts an
  // SOF beat, i.e. one edge BEFORE that SOF pixel reaches this block; if a
  // commit is pending, the banks swap on that edge, so the SOF pixel is the
  // first one looked up in the new table.
  void clock(const PixelBeat& s_pix, bool frame_start);

  // One rising edge with the write port sampled on the same edge (the RTL's
  // port timing): the write lands in the shadow bank first, so a write on the
  // commit edge is part of the table that this edge commits.
  void clock(const PixelBeat& s_pix, bool frame_start, const LutWrite& wr);

  // Fast path: what the pipeline does at a frame start (swap if pending).
  void commit_at_frame_start();

  // Fast path lookup in the active bank.
  LutEntry active_entry(uint8_t grey) const { return bank_[active_q_][grey]; }
  const std::array<LutEntry, kEntries>& active_table() const { return bank_[active_q_]; }
  const std::array<LutEntry, kEntries>& shadow_table() const { return bank_[active_q_ ^ 1u]; }
  bool commit_pending() const { return pending_q_; }

  // Registered output: the input beat delayed by one cycle with the LUT
  // outputs; remap, mask and cls are 0 on beats with pix.valid = 0.
  const LutBeat& m_lut() const { return out_q_; }

 private:
  std::array<std::array<LutEntry, kEntries>, 2> bank_{};  // two BRAM banks
  unsigned active_q_ = 0;                                 // bank select
  bool pending_q_ = false;                                // shadow bank written since the last swap
  LutBeat out_q_{};
};

}  // namespace ceilnav::stream
