#include "stream/orientation.hpp"

#include <algorithm>
#include <stdexcept>

namespace ceilnav::stream {

namespace {

namespace fo = fp::orientation;

// The vote of pixel (x, y)'s window, centred at (x-1, y-1). Only centres with
// x, y >= 2 (interior) vote.
fo::Vote window_vote(const Window3x3& w, uint32_t x, uint32_t y, uint32_t threshold,
                     uint32_t bins) {
  if (x < 2 || y < 2) return {};
  return fo::vote(sobel_gx(w), sobel_gy(w), threshold, bins);
}

uint32_t saturating_inc(uint32_t v) {
  return v == UINT32_MAX ? v : v + 1;
}

}  // namespace

Orientation::Orientation(uint32_t bins) : bins_(bins) {
  if (bins < 2 || bins > static_cast<uint32_t>(fo::kMaxBins)) {
    throw std::invalid_argument("Orientation: bins must be 2 .. 256");
  }
  for (auto& b : bank_) b.assign(bins, 0u);
  reset();
}

void Orientation::reset() {
  cfg_q_ = {};
  window_.reset();
  pipe_ = {};
  w_q_ = {};
  acc_q_ = 0;
  res_valid_q_ = false;
  sweep_busy_q_ = true;  // the accumulating bank may hold a partial frame
  sweep_ptr_q_ = 0;
  votes_q_ = 0;
  dropped_q_ = false;
  stat_votes_q_ = 0;
  frames_q_ = 0;
  skipped_q_ = 0;
  done_q_ = false;
  rd_data_q_ = 0;
}

uint32_t Orientation::read_bin(uint32_t bin) const {
  if (!res_valid_q_ || bin >= bins_) return 0;
  return bank_[1 - acc_q_][bin];
}

std::vector<uint32_t> Orientation::results() const {
  std::vector<uint32_t> r(bins_);
  for (uint32_t k = 0; k < bins_; ++k) r[k] = read_bin(k);
  return r;
}

void Orientation::clock(const LutBeat& in, bool rd_en, uint16_t rd_bin) {
  // ---- Read port: the result bank before this edge.
  const uint32_t rd_d = rd_en ? read_bin(rd_bin) : 0u;

  // ---- Write stage: the frame events of the entry that left the read stage
  // on the last edge (its vote is written on this edge).
  const Entry& w = w_q_;
  bool sweep_start = false;
  bool done_d = false;
  unsigned acc_d = acc_q_;
  if (w.abort) sweep_start = true;
  if (w.eof) {
    if (!w.abort && !sweep_busy_q_ && !dropped_q_) {
      acc_d = 1 - acc_q_;
      res_valid_q_ = true;
      stat_votes_q_ = votes_q_;
      frames_q_ = saturating_inc(frames_q_);
      done_d = true;
    } else {
      skipped_q_ = saturating_inc(skipped_q_);
    }
    sweep_start = true;  // the new accumulating bank, or the skipped frame's
  }

  // ---- Read stage: the entry's vote is read (and counted) or dropped if the
  // sweep is clearing the bank.
  const Entry& p = pipe_[kPipeStages - 1];
  uint32_t votes_d = p.sof ? 0u : votes_q_;
  bool dropped_d = p.sof ? false : dropped_q_;
  if (p.vote) {
    if (sweep_busy_q_) {
      dropped_d = true;
    } else {
      uint32_t& b = bank_[acc_q_][p.bin];
      b = fo::add_saturating(b, p.weight);
      ++votes_d;
    }
  }
  if (p.vote && !sweep_busy_q_ && (sweep_start || done_d)) {
    throw std::logic_error("Orientation: a vote on the edge its bank changes role");
  }

  // ---- The sweep: one bin of the accumulating bank per edge.
  if (sweep_busy_q_) {
    bank_[acc_q_][sweep_ptr_q_] = 0;
    ++sweep_ptr_q_;
    if (sweep_ptr_q_ == bins_) sweep_busy_q_ = false;
  }
  if (sweep_start) {
    sweep_busy_q_ = true;
    sweep_ptr_q_ = 0;
  }
  acc_q_ = acc_d;
  votes_q_ = votes_d;
  dropped_q_ = dropped_d;
  done_q_ = done_d;
  rd_data_q_ = rd_d;

  // ---- The pixel: its window's vote enters the pipeline.
  const PixelBeat& pix = in.pix;
  Entry e{};
  const LineWindow::Pixel px = window_.clock(pix, in.remap, cfg_in_.enable, "Orientation");
  e.abort = px.abort;
  if (px.take) {
    if (pix.sof) cfg_q_ = cfg_in_;
    const fo::Vote v = window_vote(px.w, px.x, px.y, cfg_q_.threshold, bins_);
    e.vote = v.valid;
    e.bin = v.bin;
    e.weight = v.weight;
    e.sof = pix.sof;
    e.eof = pix.eof;
  }
  w_q_ = pipe_[kPipeStages - 1];
  for (size_t k = kPipeStages - 1; k > 0; --k) pipe_[k] = pipe_[k - 1];
  pipe_[0] = e;
}

bool Orientation::idle() const {
  const auto busy = [](const Entry& e) { return e.vote || e.sof || e.eof || e.abort; };
  return !window_.frame_open() && !busy(w_q_) && std::none_of(pipe_.begin(), pipe_.end(), busy);
}

void Orientation::publish_frame(const OrientationConfig& cfg, const uint8_t* remap, uint32_t width,
                                uint32_t height) {
  if (width < 1 || height < 1) throw std::invalid_argument("Orientation: empty frame");
  if (!idle()) {
    throw std::logic_error("Orientation::publish_frame: the clocked block is not idle");
  }
  done_q_ = false;
  rd_data_q_ = 0;
  if (!cfg.enable) return;
  cfg_q_ = cfg;
  // The sweep of the blanking has cleared the accumulating bank.
  std::vector<uint32_t>& acc = bank_[acc_q_];
  std::fill(acc.begin(), acc.end(), 0u);
  uint32_t votes = 0;
  for (uint32_t y = 2; y < height; ++y) {
    for (uint32_t x = 2; x < width; ++x) {
      const fo::Vote v = window_vote(frame_window(remap, width, x, y), x, y, cfg.threshold, bins_);
      if (!v.valid) continue;
      acc[v.bin] = fo::add_saturating(acc[v.bin], v.weight);
      ++votes;
    }
  }
  acc_q_ = 1 - acc_q_;
  res_valid_q_ = true;
  stat_votes_q_ = votes;
  votes_q_ = votes;
  dropped_q_ = false;
  frames_q_ = saturating_inc(frames_q_);
  std::fill(bank_[acc_q_].begin(), bank_[acc_q_].end(), 0u);
  sweep_busy_q_ = false;
  sweep_ptr_q_ = 0;
}

std::vector<uint32_t> Orientation::scan_frame(const OrientationConfig& cfg, uint32_t bins,
                                              const uint8_t* remap, uint32_t width,
                                              uint32_t height) {
  std::vector<uint32_t> h(bins, 0u);
  for (uint32_t y = 2; y < height; ++y) {
    for (uint32_t x = 2; x < width; ++x) {
      const fo::Vote v = window_vote(frame_window(remap, width, x, y), x, y, cfg.threshold, bins);
      if (v.valid) h[v.bin] = fo::add_saturating(h[v.bin], v.weight);
    }
  }
  return h;
}

}  // namespace ceilnav::stream
