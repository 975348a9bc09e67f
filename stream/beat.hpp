// Stream beats on the ports of the blocks. One struct per port bundle; the
// field names are the AXI4-Stream signal names the RTL ports will carry.
#pragma once

#include <cstdint>

namespace ceilnav::stream {

// s_axis_video_*: AXI4-Stream video from the camera (8-bit grey).
// tuser = start of frame (on the first pixel), tlast = end of line.
// The device keeps tready high: the camera cannot be stalled.
struct VideoBeat {
  uint8_t tdata = 0;
  bool tvalid = false;
  bool tuser = false;  // SOF
  bool tlast = false;  // EOL
};

// Internal pixel stream after frame_check: geometry is known to be right for
// every beat with valid = true. x, y are the pixel's column and row.
struct PixelBeat {
  bool valid = false;
  uint8_t grey = 0;    // camera pixel
  uint16_t x = 0;      // column, 0 .. width-1
  uint16_t y = 0;      // row, 0 .. height-1
  bool sof = false;    // x == 0 && y == 0
  bool eol = false;    // x == width-1
  bool eof = false;    // last pixel of the frame: eol && y == height-1
  bool abort = false;  // frame aborted by frame_check. With valid = false: no pixel.
                       // With valid and sof: an early SOF, the old frame is
                       // aborted and this pixel starts the new one (same beat).
                       // Downstream discards the partial frame
};

// m_axis_edges of the edge block = s_axis_edges of the hough block: tdata as
// pack_edge_beat() / pack_edge_trailer() (common/edge_record.hpp) make it:
// word0 = x | y << 16, word1 = magnitude | polarity << 12 | kind << 13;
// the trailer (tlast) word0 = edges, word1 = flags.
struct EdgeBeat {
  bool tvalid = false;
  bool tlast = false;  // the frame's trailer
  uint64_t tdata = 0;

  friend bool operator==(const EdgeBeat&, const EdgeBeat&) = default;
};

// After thresh_lut: the pixel beat plus the LUT outputs, one cycle later.
struct LutBeat {
  PixelBeat pix;      // delayed copy of the pixel beat (grey = camera pixel)
  uint8_t remap = 0;  // LUT[grey] bits 7:0
  bool mask = false;  // LUT[grey] bit 8
  uint8_t cls = 0;    // LUT[grey] bits 10:9: PixelClass (common/pipeline_config.hpp)
};

}  // namespace ceilnav::stream
