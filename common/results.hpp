// Per-frame results of the blocks, as latched in the double-buffered result
// registers at frame end, and the run stream bundle. These are the device's
// interface types: they live in common/ so that the host uses them without
// linking the stream models, and keep the namespace ceilnav::stream of the
// device they describe.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "common/run_record.hpp"

namespace ceilnav::stream {

// Moment order in every array: m00, m10, m01, m20, m11, m02 (x = column, y = row).
enum MomentIndex : int { kM00 = 0, kM10, kM01, kM20, kM11, kM02, kMomentCount };

struct MomentResults {
  std::array<uint64_t, kMomentCount> grey{};  // of the LUT remap value
  std::array<uint64_t, kMomentCount> mask{};  // of the mask bit (0/1)
  friend bool operator==(const MomentResults&, const MomentResults&) = default;
};

// class_moments: m00 m10 m01 m20 m11 m02 of the binary mask of each measured
// pixel class (stream::PixelClass 1 = pattern, 2 = shadow, 3 = bar) inside the
// class window, in frame coordinates. Index c - 1. The background (class 0)
// is not measured: its moments are those of the window minus the three rows.
inline constexpr int kMomentClasses = 3;

struct ClassMomentResults {
  std::array<std::array<uint64_t, kMomentCount>, kMomentClasses> cls{};
  // Moments of class c (1 .. kMomentClasses); throws std::out_of_range otherwise.
  const std::array<uint64_t, kMomentCount>& of(int pixel_class) const {
    return cls.at(static_cast<std::size_t>(pixel_class - 1));
  }
  friend bool operator==(const ClassMomentResults&, const ClassMomentResults&) = default;
};

struct HistogramResults {
  std::array<uint32_t, 256> bins{};
  friend bool operator==(const HistogramResults&, const HistogramResults&) = default;
};

// m_axis_runs_*: one run per beat; tlast = 1 marks the frame trailer, which is
// not a run: trailer.run.row = runs emitted for the frame (saturating at 0xFFFF),
// trailer.run.x_start = RunTrailerFlags. The consumer drives tready.
enum RunTrailerFlags : uint16_t {
  kTrailerRowLimitHit = 1u << 0,   // some row had more than max_runs_per_row runs
  kTrailerFifoOverflow = 1u << 1,  // a run was lost because the FIFO was full
  kTrailerFrameAborted = 1u << 2,  // frame_check aborted the frame: runs are partial
};

struct RunBeat {
  bool tvalid = false;
  bool tlast = false;
  RunRecord tdata{};
  friend bool operator==(const RunBeat&, const RunBeat&) = default;
};

struct RunStats {
  uint32_t runs_emitted = 0;  // runs pushed into the FIFO this frame
  uint32_t runs_dropped_row_limit = 0;
  uint32_t runs_dropped_overflow = 0;
  uint32_t fifo_high_water = 0;  // max FIFO occupancy seen this frame (entries)
  friend bool operator==(const RunStats&, const RunStats&) = default;
};

struct FrameErrorCounters {  // cumulative since reset, saturating
  uint32_t early_eol = 0;    // tlast before x == width-1
  uint32_t late_eol = 0;     // no tlast at x == width-1
  uint32_t early_sof = 0;    // tuser inside a frame (frame cut short)
  uint32_t missing_sof = 0;  // pixel outside a frame without tuser
  uint32_t frames_ok = 0;
  uint32_t frames_aborted = 0;
  friend bool operator==(const FrameErrorCounters&, const FrameErrorCounters&) = default;
};

// The result registers of one frame, as the host reads them after frame_done.
struct FrameResults {
  uint32_t frame_index = 0;  // frames_ok - 1 at this frame's end: 0-based count of good frames
  bool valid = false;        // false until the first frame is published after reset
  HistogramResults histogram;
  MomentResults moments;
  ClassMomentResults class_moments;  // per pixel class 1..3 inside the class window
  RunStats run_stats;
  FrameErrorCounters errors;     // frame_check's counters as of this frame's EOF pixel
  uint64_t cycles_in_frame = 0;  // clock cycles from the SOF pixel to the EOF pixel, inclusive
  friend bool operator==(const FrameResults&, const FrameResults&) = default;
};

}  // namespace ceilnav::stream
