// orientation: the major-orientation histogram of seed 004's FindOrientation.
// Every interior pixel's 3 x 3 Sobel gradient of the LUT remap stream (the
// edge block's window) votes its weight into the bin of its angle folded
// modulo 90 degrees (fp::orientation::vote, fixedpoint/orientation.hpp).
// Two BRAM banks: one accumulates the open frame, the other holds the
// published histogram for the read port; a published frame swaps them and
// the new accumulating bank is cleared by a sweep of one bin per clock.
// See docs/blocks/orientation.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "fixedpoint/orientation.hpp"
#include "stream/beat.hpp"
#include "stream/line_window.hpp"

namespace ceilnav::stream {

// The configuration port, latched at the SOF pixel.
struct OrientationConfig {
  bool enable = false;
  uint16_t threshold = 16;  // 12 bits: a gradient votes if its weight > threshold

  friend bool operator==(const OrientationConfig&, const OrientationConfig&) = default;
};

class Orientation {
 public:
  static constexpr uint32_t kDefaultBins = 90;
  // Pipeline registers from the pixel to the histogram's read stage: the
  // gradient, the fold, the weight, three divider stages, the table read,
  // the bin (docs/blocks/orientation.md, "Hardware scheme").
  static constexpr int kPipeStages = 8;
  // EOF pixel sampled on edge e -> done() and the swapped banks after edge
  // e + kDoneLatencyCycles.
  static constexpr int kDoneLatencyCycles = kPipeStages + 1;

  // bins: 2 .. 256 (RTL parameter Bins).
  explicit Orientation(uint32_t bins = kDefaultBins);

  // Synchronous active-low reset: no frame open, the pipeline empty, nothing
  // published (reads give 0), counters zero; the accumulating bank is swept.
  // The BRAM banks and the line buffer keep their contents.
  void reset();

  // Configuration input port; its value at the SOF pixel's edge is latched.
  void set_config(const OrientationConfig& cfg) { cfg_in_ = cfg; }

  // One rising clock edge: samples the LutBeat port and the read port
  // (RTL hist_rd_en_i, hist_rd_bin_i). BRAM-style synchronous read: a read
  // sampled on edge t returns, after edge t, read_bin(rd_bin) as it was
  // before edge t; after an edge without a read, hist_rd_data() is 0.
  void clock(const LutBeat& in, bool rd_en = false, uint16_t rd_bin = 0);

  // Registered outputs.
  bool done() const { return done_q_; }  // one-cycle pulse: a frame was published
  uint32_t hist_rd_data() const { return rd_data_q_; }
  bool results_valid() const { return res_valid_q_; }     // a frame was published since reset
  bool clearing() const { return sweep_busy_q_; }         // the accumulating bank is being swept
  uint32_t frame_votes() const { return stat_votes_q_; }  // votes of the last published frame
  uint32_t frames() const { return frames_q_; }           // published since reset, saturating
  // Frames that ended without being published because some of their votes
  // met the sweep (or the frame ended during it), since reset, saturating.
  uint32_t frames_skipped() const { return skipped_q_; }

  // The published histogram's bin (0 before the first publication, and for
  // bin >= bins()).
  uint32_t read_bin(uint32_t bin) const;
  std::vector<uint32_t> results() const;
  uint32_t bins() const { return bins_; }
  // No frame open and no vote or frame event in the pipeline (the sweep may
  // still run).
  bool idle() const;

  // Fast path: the histogram of a whole frame (row-major remap bytes) as the
  // clocked path publishes it.
  static std::vector<uint32_t> scan_frame(const OrientationConfig& cfg, uint32_t bins,
                                          const uint8_t* remap, uint32_t width, uint32_t height);
  // Fast path of the block: a whole frame (row-major remap bytes, at least
  // one pixel) published as the clocked path publishes it when the frame
  // arrives with the block idle and the sweep done (blanking >= bins()
  // cycles): the histogram and the frame's votes in the result bank,
  // results_valid(), frames() + 1, the accumulating bank clear. `cfg` is the
  // configuration latched at the frame's SOF; a disabled block ignores the
  // frame. std::logic_error if a frame is open or votes are in flight.
  void publish_frame(const OrientationConfig& cfg, const uint8_t* remap, uint32_t width,
                     uint32_t height);

 private:
  // One pipeline entry: a pixel's vote and the frame events it carries.
  struct Entry {
    bool vote = false;  // an interior pixel whose weight > threshold
    uint32_t bin = 0;
    uint32_t weight = 0;
    bool sof = false;    // the frame's counters restart
    bool eof = false;    // the frame ends: publish (or skip) it
    bool abort = false;  // the open frame was aborted: sweep its bank
  };

  uint32_t bins_;
  OrientationConfig cfg_in_{};
  OrientationConfig cfg_q_{};

  LineWindow window_;  // the taken frame, the line buffer and the 3x3 window

  std::array<Entry, kPipeStages> pipe_{};  // pipe_[k]: after k + 1 edges
  Entry w_q_{};                            // the write stage

  // The two banks (BRAM: not reset).
  std::array<std::vector<uint32_t>, 2> bank_;
  unsigned acc_q_ = 0;  // accumulating bank; the other is the result bank
  bool res_valid_q_ = false;
  bool sweep_busy_q_ = false;
  uint32_t sweep_ptr_q_ = 0;

  uint32_t votes_q_ = 0;    // accepted votes of the open frame
  bool dropped_q_ = false;  // a vote of the open frame met the sweep
  uint32_t stat_votes_q_ = 0;
  uint32_t frames_q_ = 0;
  uint32_t skipped_q_ = 0;
  bool done_q_ = false;
  uint32_t rd_data_q_ = 0;
};

}  // namespace ceilnav::stream
