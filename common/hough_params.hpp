// The parameters of the hough block (docs/blocks/hough.md), shared by the
// C++ cycle model (stream/hough.hpp) and the golden reference
// (golden/hough_ref.hpp) without linking the stream models, in the
// namespace ceilnav::stream of the model: the compile-time shape (the RTL's
// parameters), the run-time configuration (HOUGH_CONTROL, HOUGH_GEOMETRY) and
// the theta range a configuration selects.
#pragma once

#include <algorithm>
#include <cstdint>

#include "fixedpoint/datapath.hpp"

namespace ceilnav::stream {

// Compile-time shape (the RTL's parameters).
struct HoughShape {
  int lanes = 4;       // Lanes: a power of two
  int theta_step = 4;  // ThetaStep: degrees between thetas (divides 180)
  int rho_bits = 6;    // RhoBits: 2^rho_bits rho bins
  int acc_bits = 16;   // AccBits: cell width (saturating)

  int n_theta() const { return 180 / theta_step; }
  int lane_bits() const { return fp::datapath::bits_for(static_cast<uint64_t>(lanes)) - 1; }
  int slots() const { return (n_theta() + lanes - 1) / lanes; }  // words of theta per lane
  uint32_t rho_bins() const { return 1u << rho_bits; }
  uint32_t lane_words() const { return static_cast<uint32_t>(slots()) * rho_bins(); }
  uint32_t acc_max() const { return static_cast<uint32_t>((uint64_t{1} << acc_bits) - 1); }
  // Bits of the read index {j, rho}: j in [0, 2^bits_for(n_theta - 1)).
  int index_bits() const {
    return fp::datapath::bits_for(static_cast<uint64_t>(n_theta() - 1)) + rho_bits;
  }
};

// Run-time configuration (register HOUGH_CONTROL, HOUGH_GEOMETRY), latched
// with the first beat of each frame.
struct HoughConfig {
  bool enable = true;
  bool unit_weight = false;  // 1: every vote weighs 1
  uint8_t weight_shift = 0;  // w = (y + 1) >> weight_shift (0 .. 15)
  uint8_t rho_shift = 0;     // rho bin = 2^rho_shift pixels (0 .. 7)
  uint8_t theta_first = 0;   // first theta index (clamped to n_theta - 1)
  uint8_t theta_count = 0;   // thetas; 0 or past the end = up to the end
  uint16_t width = 0;        // rho bias W in pixels (image width; 0 .. 2048)
};

// Published per-frame counters of the hough block (saturating at 2^32 - 1;
// registers HOUGH_EDGES .. HOUGH_TRAILER_FLAGS).
struct HoughCounters {
  uint32_t edges = 0;          // edge beats voted
  uint32_t bad_edges = 0;      // edge beats with x or y >= 2048 (not voted)
  uint32_t votes = 0;          // votes written into cells
  uint32_t dropped = 0;        // votes whose rho index fell outside [0, rho_bins)
  uint32_t saturated = 0;      // votes that clipped a cell at acc_max
  uint32_t trailer_edges = 0;  // trailer word0
  uint32_t trailer_flags = 0;  // trailer word1
  bool operator==(const HoughCounters&) const = default;
};

// The theta range a configuration selects: first index and count.
struct ThetaRange {
  int first = 0;
  int count = 1;
};
// First clamped to n_theta - 1; count 0 or past the end = up to the end.
inline ThetaRange theta_range(const HoughShape& shape, const HoughConfig& cfg) {
  const int n = shape.n_theta();
  ThetaRange r;
  r.first = std::min<int>(cfg.theta_first, n - 1);
  const int avail = n - r.first;
  r.count = (cfg.theta_count == 0 || cfg.theta_count > avail) ? avail : cfg.theta_count;
  return r;
}

}  // namespace ceilnav::stream
