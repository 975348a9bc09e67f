#include "stream/histogram.hpp"

namespace ceilnav::stream {

void Histogram::reset() {
  // The bank of the last frame may hold a partial count.
  dirty_q_[acc_bank_q_] = true;
  counting_q_ = false;
  frame_open_q_ = false;
  source_remap_q_ = false;
  eof_q_ = false;
  done_q_ = false;
  res_valid_q_ = false;
  clr_busy_q_ = {};
  clr_ptr_q_ = {};
  rd_data_q_ = 0;
}

unsigned Histogram::free_bank() const {
  for (unsigned b = 0; b < kBanks; ++b) {
    if (!dirty_q_[b] && b != disp_bank_q_ && b != acc_bank_q_) {
      return b;
    }
  }
  return kBanks;
}

bool Histogram::counts(const LutBeat& s_lut) const {
  const PixelBeat& pix = s_lut.pix;
  if (!pix.valid) {
    return false;
  }
  if (pix.sof) {
    return free_bank() != kBanks;
  }
  return frame_open_q_ && !pix.abort && counting_q_;
}

void Histogram::clear_step() {
  // Per bank: one bin per edge; the bank is clean after the edge that clears
  // bin 255. A bank that becomes dirty on the same edge stays dirty (set wins).
  for (unsigned b = 0; b < kBanks; ++b) {
    if (clr_busy_q_[b]) {
      count_[b][clr_ptr_q_[b]] = 0;
      if (clr_ptr_q_[b] == kBins - 1) {
        clr_busy_q_[b] = false;
        dirty_q_[b] = false;
      }
      clr_ptr_q_[b] = (clr_ptr_q_[b] + 1) % kBins;
    } else if (dirty_q_[b]) {
      clr_busy_q_[b] = true;
      clr_ptr_q_[b] = 0;
    }
  }
}

void Histogram::clock(const LutBeat& s_lut, bool source_remap, bool keep, bool rd_en,
                      uint8_t rd_bin) {
  // The read port samples the state before this edge.
  const uint32_t rd_data = rd_en ? read_bin(rd_bin) : 0u;
  clock(s_lut, source_remap, keep);
  rd_data_q_ = rd_data;
}

void Histogram::clock(const LutBeat& s_lut, bool source_remap, bool keep) {
  // Everything below samples the state before this edge.
  const bool beat_counts = counts(s_lut);
  const unsigned picked = free_bank();
  const unsigned old_disp = disp_bank_q_;
  const bool publish = eof_q_;

  rd_data_q_ = 0;
  clear_step();

  // Stage 2 of the kept frame: its last count was written on the previous
  // edge; it becomes the result bank, the old result bank is to be cleared.
  done_q_ = publish;
  if (publish) {
    disp_bank_q_ = acc_bank_q_;
    dirty_q_[old_disp] = true;
    res_valid_q_ = true;
  }
  eof_q_ = false;

  // Stage 1: the sampled pixel.
  const PixelBeat& pix = s_lut.pix;
  if (pix.abort && frame_open_q_ && counting_q_) {
    dirty_q_[acc_bank_q_] = true;  // the partial count is never published
  }
  if (pix.abort) {
    frame_open_q_ = false;
    counting_q_ = false;
  }
  if (!pix.valid) {
    return;
  }
  if (pix.sof) {
    source_remap_q_ = source_remap;
    frame_open_q_ = true;
    if (picked != kBanks) {
      acc_bank_q_ = picked;
    }
  }
  if (!frame_open_q_) {
    return;
  }
  counting_q_ = beat_counts;
  if (beat_counts) {
    const uint8_t bin = source_remap_q_ ? s_lut.remap : pix.grey;
    ++count_[acc_bank_q_][bin];
  }
  if (pix.eof) {
    frame_open_q_ = false;
    if (beat_counts) {
      if (keep) {
        eof_q_ = true;
      } else {
        dirty_q_[acc_bank_q_] = true;
      }
    }
    counting_q_ = false;
  }
}

void Histogram::process_frame(const uint8_t* values, int width, int height, size_t stride_bytes) {
  std::array<uint32_t, kBins> bins{};
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = values + static_cast<size_t>(y) * stride_bytes;
    for (int x = 0; x < width; ++x) {
      ++bins[row[x]];
    }
  }
  publish_frame(bins);
}

void Histogram::publish_frame(const std::array<uint32_t, kBins>& bins) {
  // As after a long enough idle time: every bank but the result bank clean.
  for (unsigned b = 0; b < kBanks; ++b) {
    if (dirty_q_[b] && b != disp_bank_q_) {
      count_[b].fill(0);
      dirty_q_[b] = false;
    }
  }
  // Two banks are not the result bank and at most one of them is the last
  // frame's: a free bank always exists here.
  const unsigned bank = free_bank();
  count_[bank] = bins;
  const unsigned old_disp = disp_bank_q_;
  disp_bank_q_ = bank;
  acc_bank_q_ = bank;
  count_[old_disp].fill(0);
  dirty_q_[old_disp] = false;
  res_valid_q_ = true;
  clr_busy_q_ = {};
  clr_ptr_q_ = {};
  counting_q_ = false;
  frame_open_q_ = false;
  eof_q_ = false;
  done_q_ = false;
  rd_data_q_ = 0;
}

uint32_t Histogram::read_bin(uint8_t bin) const {
  return res_valid_q_ ? count_[disp_bank_q_][bin] : 0u;
}

HistogramResults Histogram::results() const {
  HistogramResults out;
  if (res_valid_q_) {
    for (size_t b = 0; b < kBins; ++b) {
      out.bins[b] = count_[disp_bank_q_][b];
    }
  }
  return out;
}

}  // namespace ceilnav::stream
