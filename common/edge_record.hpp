// One edge point as the edge detector emits it, and the 64-bit beat of its
// m_axis_edges stream (docs/blocks/edge.md). The `hough` block reads this
// format: keep it.
#pragma once

#include <algorithm>
#include <cstdint>

namespace ceilnav::stream {

// The difference an edge point was found with (beat field kind[1:0]).
enum class EdgeKind : uint8_t { kHorizontal = 0, kVertical = 1, kSobel = 2 };

// EDGE_CONTROL.MODE: which difference the detector uses for a frame.
enum class EdgeMode : uint8_t { kHorizontal = 0, kVertical = 1, kSobel = 2, kReserved = 3 };

// The edge block's configuration (register EDGE_CONTROL), latched at the SOF pixel.
struct EdgeConfig {
  bool enable = false;
  EdgeMode mode = EdgeMode::kHorizontal;
  uint16_t threshold = 32;  // 12 bits: an edge point has magnitude > threshold

  friend bool operator==(const EdgeConfig&, const EdgeConfig&) = default;
};
struct EdgeRecord {
  uint16_t x = 0;          // column of the right pixel of the pair / the 3x3 window's centre
  uint16_t y = 0;          // row of the lower pixel of the pair / the window's centre
  uint16_t magnitude = 0;  // |d| (0..255) or Sobel |gx| + |gy| (0..2040), 12-bit field
  bool polarity = false;   // intensity rises with x (vertical: with y; Sobel: gx > 0)
  EdgeKind kind = EdgeKind::kHorizontal;

  friend bool operator==(const EdgeRecord&, const EdgeRecord&) = default;
};

// Trailer flags (tdata[33:32], word1 bits 1:0).
inline constexpr uint32_t kEdgeTrailerOverflow = 1u << 0;  // edges dropped / a trailer lost
inline constexpr uint32_t kEdgeTrailerAborted = 1u << 1;   // frame cut short by frame_check

// tdata = word0 | word1 << 32.
//   edge:    word0 = x | y << 16;  word1 = magnitude[11:0] | polarity << 12 | kind << 13
//   trailer: word0 = edges emitted (saturating); word1 = flags | min(dropped, 0xFFFF) << 16
constexpr uint64_t pack_edge_beat(const EdgeRecord& e) {
  const uint32_t w0 = uint32_t{e.x} | (uint32_t{e.y} << 16);
  const uint32_t w1 = (uint32_t{e.magnitude} & 0xFFFu) | (uint32_t{e.polarity} << 12) |
                      (static_cast<uint32_t>(e.kind) << 13);
  return uint64_t{w0} | (uint64_t{w1} << 32);
}

constexpr EdgeRecord unpack_edge_beat(uint64_t tdata) {
  EdgeRecord e;
  e.x = static_cast<uint16_t>(tdata & 0xFFFFu);
  e.y = static_cast<uint16_t>((tdata >> 16) & 0xFFFFu);
  e.magnitude = static_cast<uint16_t>((tdata >> 32) & 0xFFFu);
  e.polarity = ((tdata >> 44) & 1u) != 0;
  e.kind = static_cast<EdgeKind>((tdata >> 45) & 3u);
  return e;
}

constexpr uint64_t pack_edge_trailer(uint64_t emitted, uint32_t flags, uint64_t dropped) {
  const uint64_t w0 = std::min<uint64_t>(emitted, 0xFFFFFFFFu);
  const uint64_t w1 = (flags & 3u) | (std::min<uint64_t>(dropped, 0xFFFFu) << 16);
  return w0 | (w1 << 32);
}

}  // namespace ceilnav::stream
