#include "stream/hough.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "fixedpoint/hough_trig.hpp"

namespace ceilnav::stream {

namespace {

constexpr uint32_t kCoordLimit = fp::datapath::kMaxWidth;  // x, y < 2048
constexpr int kFrac = fp::hough::kTrigFrac;
static_assert(kFrac == fp::datapath::hough::kTrigFrac);

}  // namespace

uint32_t hough_weight(const HoughConfig& cfg, uint32_t y) {
  return cfg.unit_weight ? 1u : ((y + 1u) >> (cfg.weight_shift & 15u));
}

bool hough_rho_index(const HoughShape& shape, const HoughConfig& cfg, uint32_t x, uint32_t y,
                     int k_deg, uint32_t& index) {
  const auto& t = fp::hough::trig_table();
  const auto k = static_cast<size_t>(k_deg);
  // Round to the nearest bin: + half a bin before the floor.
  const int64_t sum = int64_t{x} * t.cos[k] + int64_t{y} * t.sin[k] +
                      (int64_t{cfg.width & 0xFFFu} << kFrac) +
                      (int64_t{1} << (kFrac - 1 + (cfg.rho_shift & 7u)));
  if (sum < 0) {
    return false;
  }
  const uint64_t idx = static_cast<uint64_t>(sum) >> (kFrac + (cfg.rho_shift & 7u));
  if (idx >= shape.rho_bins()) {
    return false;
  }
  index = static_cast<uint32_t>(idx);
  return true;
}

Hough::Hough(const HoughShape& shape) : shape_(shape) {
  if (shape_.lanes < 1 || (shape_.lanes & (shape_.lanes - 1)) != 0 || shape_.theta_step < 1 ||
      180 % shape_.theta_step != 0 || shape_.rho_bits < 1 || shape_.rho_bits > 12 ||
      shape_.acc_bits < 1 || shape_.acc_bits > 32) {
    throw std::invalid_argument("Hough: bad shape");
  }
  mem_.assign(static_cast<size_t>(2 * shape_.lanes) * shape_.lane_words(), 0u);
  reset();
}

void Hough::reset() {
  state_q_ = State::kClear;
  acc_q_ = 0;
  disp_q_ = 1;
  res_valid_q_ = false;
  done_q_ = false;
  clr_ptr_q_ = 0;
  frame_open_q_ = false;
  frame_en_q_ = false;
  cfg_q_ = HoughConfig{};
  first_q_ = 0;
  count_q_ = 1;
  last_slot_q_ = 0;
  x_q_ = 0;
  y_q_ = 0;
  slot_q_ = 0;
  w_sat_q_ = 0;
  for (Slot* st : {&t_, &m_, &r_, &b_}) {
    *st = Slot{};
    st->lanes.assign(static_cast<size_t>(shape_.lanes), LaneVote{});
  }
  cnt_ = {};
  pub_ = {};
  rd_data_q_ = 0;
}

bool Hough::tready() const {
  return state_q_ == State::kIdle || (state_q_ == State::kVote && slot_q_ == last_slot_q_);
}

int Hough::cycles_per_edge(const HoughConfig& cfg) const {
  const ThetaRange r = theta_range(shape_, cfg);
  return (r.count + shape_.lanes - 1) / shape_.lanes;
}

void Hough::bump(uint32_t& c, uint32_t n) {
  const uint64_t s = uint64_t{c} + n;
  c = s > 0xFFFFFFFFu ? 0xFFFFFFFFu : static_cast<uint32_t>(s);
}

uint32_t Hough::read_port(uint32_t rd_index) const {
  const uint32_t index = rd_index & ((1u << shape_.index_bits()) - 1u);
  const uint32_t j = index >> shape_.rho_bits;
  const uint32_t rho = index & (shape_.rho_bins() - 1u);
  if (!res_valid_q_ || j >= static_cast<uint32_t>(shape_.n_theta())) {
    return 0;
  }
  return cell(j, rho);
}

uint32_t Hough::cell(uint32_t j, uint32_t rho) const {
  const auto lane = static_cast<int>(j & static_cast<uint32_t>(shape_.lanes - 1));
  const uint32_t slot = j >> shape_.lane_bits();
  return word(disp_q_, lane, slot * shape_.rho_bins() + rho);
}

std::vector<uint32_t> Hough::results() const {
  std::vector<uint32_t> out(static_cast<size_t>(shape_.n_theta()) * shape_.rho_bins(), 0u);
  if (!res_valid_q_) {
    return out;
  }
  for (uint32_t j = 0; j < static_cast<uint32_t>(shape_.n_theta()); ++j) {
    for (uint32_t r = 0; r < shape_.rho_bins(); ++r) {
      out[j * shape_.rho_bins() + r] = cell(j, r);
    }
  }
  return out;
}

bool Hough::vote_into(int lane, uint32_t addr, uint32_t weight) {
  uint32_t& c = word(acc_q_, lane, addr);
  const uint64_t sum = uint64_t{c} + weight;
  bump(cnt_.votes, 1);
  if (sum > shape_.acc_max()) {
    c = shape_.acc_max();
    return true;
  }
  c = static_cast<uint32_t>(sum);
  return false;
}

void Hough::clear_bank(int bank) {
  for (int l = 0; l < shape_.lanes; ++l) {
    for (uint32_t a = 0; a < shape_.lane_words(); ++a) {
      word(bank, l, a) = 0;
    }
  }
}

void Hough::clock(const EdgeBeat& in, const HoughConfig& cfg, bool rd_en, uint32_t rd_index) {
  // Everything below samples the state before this edge.
  const uint32_t rd = rd_en ? read_port(rd_index) : 0u;
  const bool ready = tready();
  const State state = state_q_;
  const auto lanes = static_cast<size_t>(shape_.lanes);

  // Stage W: the votes read in stage B on the previous edge are written
  // (their clipping counted on the next edge); the clips of the previous
  // edge and the drops leaving stage R are counted.
  bump(cnt_.saturated, w_sat_q_);
  uint32_t w_sat_next = 0;
  if (b_.valid) {
    for (size_t l = 0; l < lanes; ++l) {
      if (b_.lanes[l].vote && vote_into(static_cast<int>(l), b_.lanes[l].addr, b_.weight)) {
        ++w_sat_next;
      }
    }
  }
  if (r_.valid) {
    bump(cnt_.dropped,
         static_cast<uint32_t>(std::count_if(r_.lanes.begin(), r_.lanes.end(),
                                             [](const LaneVote& v) { return v.drop; })));
  }
  const bool pipe_busy = busy();

  // Stage T: in kVote, slot slot_q_ of the held edge issues one vote per lane.
  Slot t_next;
  t_next.lanes.assign(lanes, LaneVote{});
  t_next.weight = hough_weight(cfg_q_, y_q_);
  if (state == State::kVote) {
    t_next.valid = true;
    for (size_t l = 0; l < lanes; ++l) {
      const int j = slot_q_ * shape_.lanes + static_cast<int>(l);
      if (j >= count_q_) {
        continue;
      }
      uint32_t idx = 0;
      LaneVote& v = t_next.lanes[l];
      if (hough_rho_index(shape_, cfg_q_, x_q_, y_q_, (first_q_ + j) * shape_.theta_step, idx)) {
        v.vote = true;
        v.addr = static_cast<uint32_t>(slot_q_) * shape_.rho_bins() + idx;
      } else {
        v.drop = true;
      }
    }
  }

  done_q_ = false;
  State next = state;
  switch (state) {
    case State::kClear:
      for (int l = 0; l < shape_.lanes; ++l) {
        word(acc_q_, l, clr_ptr_q_) = 0;
      }
      if (clr_ptr_q_ == shape_.lane_words() - 1) {
        next = State::kIdle;
        clr_ptr_q_ = 0;
      } else {
        ++clr_ptr_q_;
      }
      break;
    case State::kSwap:
      // Held until the last vote of the frame is written on this edge
      // (stage W above).
      if (pipe_busy) {
        break;
      }
      pub_ = cnt_;
      cnt_ = {};
      disp_q_ = acc_q_;
      acc_q_ = 1 - acc_q_;
      res_valid_q_ = true;
      done_q_ = true;
      next = State::kClear;
      clr_ptr_q_ = 0;
      break;
    case State::kVote:
      if (slot_q_ == last_slot_q_) {
        next = State::kIdle;
      } else {
        ++slot_q_;
      }
      break;
    case State::kIdle:
      break;
  }

  if (ready && in.tvalid) {
    if (!frame_open_q_) {
      cfg_q_ = cfg;
      const ThetaRange r = theta_range(shape_, cfg);
      first_q_ = r.first;
      count_q_ = r.count;
      last_slot_q_ = (r.count + shape_.lanes - 1) / shape_.lanes - 1;
      frame_en_q_ = cfg.enable;
      frame_open_q_ = true;
    }
    const bool en = frame_en_q_;
    const auto word0 = static_cast<uint32_t>(in.tdata);
    const auto word1 = static_cast<uint32_t>(in.tdata >> 32);
    next = State::kIdle;
    if (in.tlast) {
      frame_open_q_ = false;
      if (en) {
        cnt_.trailer_edges = word0;
        cnt_.trailer_flags = word1;
        next = State::kSwap;
      }
    } else if (en) {
      const uint32_t x = word0 & 0xFFFFu;
      const uint32_t y = word0 >> 16;
      if (x >= kCoordLimit || y >= kCoordLimit) {
        bump(cnt_.bad_edges, 1);
      } else {
        bump(cnt_.edges, 1);
        x_q_ = x;
        y_q_ = y;
        slot_q_ = 0;
        next = State::kVote;
      }
    }
  }
  state_q_ = next;
  std::swap(b_, r_);  // b_ = r_, r_ = m_, m_ = t_, t_ = t_next
  std::swap(r_, m_);
  std::swap(m_, t_);
  std::swap(t_, t_next);
  w_sat_q_ = w_sat_next;
  rd_data_q_ = rd;
}

void Hough::process_frame(const std::vector<uint64_t>& edges, uint64_t trailer,
                          const HoughConfig& cfg) {
  if (state_q_ == State::kVote || state_q_ == State::kSwap || busy() || w_sat_q_ != 0) {
    throw std::logic_error("Hough::process_frame: the block is busy");
  }
  if (state_q_ == State::kClear) {  // as the rest of the sweep would
    clear_bank(acc_q_);
    clr_ptr_q_ = 0;
    state_q_ = State::kIdle;
  }
  done_q_ = false;
  rd_data_q_ = 0;
  cfg_q_ = cfg;
  const ThetaRange r = theta_range(shape_, cfg);
  first_q_ = r.first;
  count_q_ = r.count;
  last_slot_q_ = (r.count + shape_.lanes - 1) / shape_.lanes - 1;
  frame_en_q_ = cfg.enable;
  frame_open_q_ = false;
  if (!cfg.enable) {
    return;
  }
  for (const uint64_t e : edges) {
    const auto word0 = static_cast<uint32_t>(e);
    const uint32_t x = word0 & 0xFFFFu;
    const uint32_t y = word0 >> 16;
    if (x >= kCoordLimit || y >= kCoordLimit) {
      bump(cnt_.bad_edges, 1);
      continue;
    }
    bump(cnt_.edges, 1);
    x_q_ = x;
    y_q_ = y;
    slot_q_ = last_slot_q_;
    const uint32_t w = hough_weight(cfg, y);
    for (int j = 0; j < r.count; ++j) {
      uint32_t idx = 0;
      if (!hough_rho_index(shape_, cfg, x, y, (r.first + j) * shape_.theta_step, idx)) {
        bump(cnt_.dropped, 1);
        continue;
      }
      const int lane = j & (shape_.lanes - 1);
      const auto slot = static_cast<uint32_t>(j >> shape_.lane_bits());
      if (vote_into(lane, slot * shape_.rho_bins() + idx, w)) {
        bump(cnt_.saturated, 1);
      }
    }
  }
  // The trailer, the swap and the clear sweep of the new voting bank.
  cnt_.trailer_edges = static_cast<uint32_t>(trailer);
  cnt_.trailer_flags = static_cast<uint32_t>(trailer >> 32);
  pub_ = cnt_;
  cnt_ = {};
  disp_q_ = acc_q_;
  acc_q_ = 1 - acc_q_;
  res_valid_q_ = true;
  clear_bank(acc_q_);
  state_q_ = State::kIdle;
  clr_ptr_q_ = 0;
  for (Slot* st : {&t_, &m_, &r_, &b_}) {
    st->valid = false;  // drained
  }
}

}  // namespace ceilnav::stream
