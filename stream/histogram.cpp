#include "stream/histogram.hpp"

namespace ceilnav::stream {

void Histogram::reset() {
  for (Bank& bank : bank_) {
    bank.valid.reset();
  }
  acc_bank_q_ = 0;
  disp_bank_q_ = 1;
  fin_bank_q_ = 0;
  frame_open_q_ = false;
  source_remap_q_ = false;
  eof_q_ = false;
  done_q_ = false;
  rd_data_q_ = 0;
}

void Histogram::start_frame(unsigned bank) {
  // Flash clear: the stale counts of this bank stay in the BRAM but read as 0.
  bank_[bank].valid.reset();
  frame_open_q_ = true;
}

void Histogram::clock(const LutBeat& s_lut, bool source_remap, bool rd_en, uint8_t rd_bin) {
  // The read port samples the state before this edge.
  const uint32_t rd_data = rd_en ? read_bin(rd_bin) : 0u;
  clock(s_lut, source_remap);
  rd_data_q_ = rd_data;
}

void Histogram::clock(const LutBeat& s_lut, bool source_remap) {
  rd_data_q_ = 0;
  // Stage 2: the last read-modify-write of the finished frame has been written
  // on the previous edge; switch the result bank and pulse done.
  done_q_ = eof_q_;
  if (eof_q_) {
    disp_bank_q_ = fin_bank_q_;
  }
  eof_q_ = false;

  // Stage 1: read-modify-write of the sampled pixel's bin.
  const PixelBeat& pix = s_lut.pix;
  if (pix.abort) {
    frame_open_q_ = false;  // the partial bank is cleared by the next SOF
  }
  if (!pix.valid) {
    return;
  }
  if (pix.sof) {
    source_remap_q_ = source_remap;
    start_frame(acc_bank_q_);
  }
  if (!frame_open_q_) {
    return;
  }
  Bank& bank = bank_[acc_bank_q_];
  const uint8_t bin = source_remap_q_ ? s_lut.remap : pix.grey;
  if (!bank.valid[bin]) {
    bank.valid[bin] = true;
    bank.count[bin] = 0;
  }
  ++bank.count[bin];
  if (pix.eof) {
    fin_bank_q_ = acc_bank_q_;
    acc_bank_q_ ^= 1u;
    frame_open_q_ = false;
    eof_q_ = true;
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
  Bank& bank = bank_[acc_bank_q_];
  bank.count = bins;
  for (size_t b = 0; b < kBins; ++b) {
    bank.valid[b] = bins[b] != 0;
  }
  disp_bank_q_ = acc_bank_q_;
  fin_bank_q_ = acc_bank_q_;
  acc_bank_q_ ^= 1u;
  frame_open_q_ = false;
  eof_q_ = false;
  done_q_ = false;
  rd_data_q_ = 0;
}

uint32_t Histogram::read_bin(uint8_t bin) const {
  const Bank& bank = bank_[disp_bank_q_];
  return bank.valid[bin] ? bank.count[bin] : 0u;
}

HistogramResults Histogram::results() const {
  HistogramResults out;
  const Bank& bank = bank_[disp_bank_q_];
  for (size_t b = 0; b < kBins; ++b) {
    out.bins[b] = bank.valid[b] ? bank.count[b] : 0u;
  }
  return out;
}

}  // namespace ceilnav::stream
