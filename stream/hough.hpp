// hough: weighted Hough voter (seed 002 step 3, eq. 18). Every edge point
// (x, y) of a frame votes, for each theta of the configured range, into the
// cell (theta, rho index) of a theta x rho accumulator with the weight
// w = (y + 1) >> weight_shift (eq. 18 with r counted from the bottom), or 1.
// theta is split over `lanes` parallel lanes (cell j of the range goes to lane
// j mod lanes, slot j / lanes), each lane its own BRAM per bank, so one edge
// takes ceil(theta_count / lanes) cycles; s_axis_edges_tready throttles the
// input meanwhile. Two banks: the frame votes in one while the other holds
// the published frame for the host read port; the trailer beat publishes
// the frame (swap) and the bank that stops being the result is cleared by a
// sweep before the next frame votes into it. Cycle-exact twin of
// rtl_model/hough.sv; see docs/blocks/hough.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/hough_params.hpp"
#include "fixedpoint/datapath.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream {

// s_axis_edges: one stream::EdgeBeat (stream/beat.hpp) per cycle.

// Edge beat words (docs/blocks/hough.md): word0 = x | y << 16,
// word1 = magnitude | polarity << 12 | kind << 13; trailer word0 = edges,
// word1 = flags.
inline uint64_t edge_word(uint16_t x, uint16_t y, uint32_t word1 = 0) {
  return uint64_t{x} | (uint64_t{y} << 16) | (uint64_t{word1} << 32);
}
inline uint64_t trailer_word(uint32_t edges, uint32_t flags) {
  return uint64_t{edges} | (uint64_t{flags} << 32);
}

// Weight of an edge at row y (from the top) under cfg.
uint32_t hough_weight(const HoughConfig& cfg, uint32_t y);

// rho index of (x, y) at table theta k (degrees); false if outside
// [0, rho_bins). Integer arithmetic of the RTL.
bool hough_rho_index(const HoughShape& shape, const HoughConfig& cfg, uint32_t x, uint32_t y,
                     int k_deg, uint32_t& index);

class Hough {
 public:
  enum class State : uint8_t { kIdle = 0, kVote = 1, kSwap = 2, kClear = 3 };

  // Edges in kSwap when the trailer is accepted on the edge that issues the
  // frame's last slot: that slot's votes pass stages T, M, R and B, are
  // written on the fourth edge and their clipping counted on the fifth, which
  // publishes (a trailer g idle cycles later: max(1, kSwapEdges - g)).
  static constexpr int kSwapEdges = 5;

  explicit Hough(const HoughShape& shape = HoughShape{});

  // Reset: results invalid, counters 0, bank 0 votes and is cleared first
  // (state kClear). Bank contents are kept (the sweep clears bank 0).
  void reset();

  // Registered output: the block accepts a beat on this edge.
  bool tready() const;

  // One rising edge. cfg is sampled with the first beat of a frame; the read
  // port (rd_en, rd_index = j << rho_bits | rho) samples the result bank
  // before the edge and returns it in rd_data() after the edge (0 without a
  // read, for j >= n_theta, or with no frame published).
  void clock(const EdgeBeat& in, const HoughConfig& cfg, bool rd_en = false, uint32_t rd_index = 0);

  // Fast path: one complete frame (edge beats then its trailer) with no
  // gaps and no reads, the block idle on entry. Leaves the block as clock()
  // would after the frame plus the idle cycles until tready rises (the clear
  // sweep done), except for the read port output (0).
  void process_frame(const std::vector<uint64_t>& edges, uint64_t trailer, const HoughConfig& cfg);

  // Registered outputs.
  bool done() const { return done_q_; }  // one-cycle pulse after a publication
  uint32_t rd_data() const { return rd_data_q_; }
  bool results_valid() const { return res_valid_q_; }
  State state() const { return state_q_; }
  const HoughCounters& counters() const { return pub_; }  // the published frame's

  // Cell (j, rho) of the published frame (what the read port returns).
  uint32_t cell(uint32_t j, uint32_t rho) const;
  // The published accumulator, j-major: n_theta * rho_bins cells.
  std::vector<uint32_t> results() const;
  const HoughShape& shape() const { return shape_; }
  // Clear sweep length in cycles (words per lane).
  uint32_t clear_cycles() const { return shape_.lane_words(); }
  // Cycles per edge of cfg: ceil(count / lanes).
  int cycles_per_edge(const HoughConfig& cfg) const;

 private:
  uint32_t& word(int bank, int lane, uint32_t addr) {
    return mem_[static_cast<size_t>((bank * shape_.lanes + lane)) * shape_.lane_words() + addr];
  }
  uint32_t word(int bank, int lane, uint32_t addr) const {
    return mem_[static_cast<size_t>((bank * shape_.lanes + lane)) * shape_.lane_words() + addr];
  }
  uint32_t read_port(uint32_t rd_index) const;
  // Stage W of one vote: the cell += weight, saturating; counts it. Returns
  // whether it clipped (counted by the caller).
  bool vote_into(int lane, uint32_t addr, uint32_t weight);
  void clear_bank(int bank);
  static void bump(uint32_t& c, uint32_t n);

  HoughShape shape_;
  std::vector<uint32_t> mem_;  // [bank][lane][slot * rho_bins + rho], not reset

  State state_q_ = State::kClear;
  int acc_q_ = 0;   // voting bank
  int disp_q_ = 1;  // result bank
  bool res_valid_q_ = false;
  bool done_q_ = false;
  uint32_t clr_ptr_q_ = 0;
  // The open frame
  bool frame_open_q_ = false;
  bool frame_en_q_ = false;
  HoughConfig cfg_q_;
  int first_q_ = 0;
  int count_q_ = 1;
  int last_slot_q_ = 0;
  // The edge being voted
  uint32_t x_q_ = 0;
  uint32_t y_q_ = 0;
  int slot_q_ = 0;
  // The vote pipeline of the RTL: a slot issued in stage T (the slot cycle)
  // passes the registers of T (table words), M (products) and R (rho index,
  // range check), then stage B reads its cells and stage W writes them. The
  // model computes each lane's vote when the slot issues (the frame's
  // configuration does not change while votes are in flight) and carries it
  // through t_, m_, r_ (the registers after T, M, R) and b_ (after B); it
  // counts the drops when they leave R and writes the votes when they leave
  // B, reading the memory as it is after the previous edge's write (the RTL
  // forwards that write to its read of the same cell); the clipped votes of
  // W are counted on the next edge (w_sat_q_, the RTL's registered flags).
  struct LaneVote {
    bool vote = false;
    bool drop = false;
    uint32_t addr = 0;
  };
  struct Slot {
    bool valid = false;  // the stage holds a slot
    uint32_t weight = 0;
    std::vector<LaneVote> lanes;
  };
  Slot t_, m_, r_, b_;
  uint32_t w_sat_q_ = 0;  // votes stage W clipped on the previous edge
  // The pipeline holds a slot whose write or clip count is still to come
  // after this edge.
  bool busy() const { return t_.valid || m_.valid || r_.valid || b_.valid; }
  // Counters of the open frame, and the published ones
  HoughCounters cnt_;
  HoughCounters pub_;
  uint32_t rd_data_q_ = 0;
};

}  // namespace ceilnav::stream
