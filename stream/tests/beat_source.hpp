// Test driver: turns a frame (camera grey + LUT, or remap/mask planes) into
// the LutBeat sequence that thresh_lut would deliver, with random tvalid gaps
// and optional abort. No OpenCV, so any stream test can use it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "common/pipeline_config.hpp"
#include "stream/beat.hpp"

namespace ceilnav::stream::test {

// One frame after the LUT, row-major.
struct LutFrame {
  uint16_t width = 0;
  uint16_t height = 0;
  std::vector<uint8_t> grey;   // camera pixel (carried in pix.grey)
  std::vector<uint8_t> remap;  // LUT bits 7:0
  std::vector<uint8_t> mask;   // LUT bit 8, 0/1
  std::vector<uint8_t> cls{};  // LUT bits 10:9 (PixelClass); empty = all 0

  size_t pixels() const { return size_t{width} * height; }
  const uint8_t* remap_row(uint32_t y) const { return remap.data() + size_t{y} * width; }
  const uint8_t* mask_row(uint32_t y) const { return mask.data() + size_t{y} * width; }
  const uint8_t* cls_row(uint32_t y) const { return cls.data() + size_t{y} * width; }

  static LutFrame from_grey(const std::vector<uint8_t>& grey, uint16_t width, uint16_t height,
                            const std::array<LutEntry, 256>& lut) {
    LutFrame f{width,
               height,
               grey,
               std::vector<uint8_t>(grey.size()),
               std::vector<uint8_t>(grey.size()),
               std::vector<uint8_t>(grey.size())};
    for (size_t i = 0; i < grey.size(); ++i) {
      f.remap[i] = static_cast<uint8_t>(lut[grey[i]] & kLutRemapMask);
      f.mask[i] = (lut[grey[i]] & kLutMaskBit) != 0 ? 1 : 0;
      f.cls[i] = lut_class(lut[grey[i]]);
    }
    return f;
  }
};

// Appends the beats of `f`. Before every pixel, idle beats (valid = 0) are
// inserted while a coin with P(gap) = gap_probability comes up. If
// abort_after_pixels >= 0, only that many pixels are sent, then one abort beat
// (valid = 0, abort = 1) ends the frame.
inline void append_frame(std::vector<LutBeat>& out, const LutFrame& f, std::mt19937& rng,
                         double gap_probability, int64_t abort_after_pixels = -1) {
  std::bernoulli_distribution gap(gap_probability);
  int64_t sent = 0;
  for (uint32_t y = 0; y < f.height; ++y) {
    for (uint32_t x = 0; x < f.width; ++x) {
      if (sent == abort_after_pixels) {
        LutBeat a;
        a.pix.abort = true;
        out.push_back(a);
        return;
      }
      while (gap_probability > 0.0 && gap(rng)) out.push_back(LutBeat{});
      const size_t i = size_t{y} * f.width + x;
      LutBeat b;
      b.pix.valid = true;
      b.pix.grey = f.grey.empty() ? 0 : f.grey[i];
      b.pix.x = static_cast<uint16_t>(x);
      b.pix.y = static_cast<uint16_t>(y);
      b.pix.sof = x == 0 && y == 0;
      b.pix.eol = x + 1u == f.width;
      b.pix.eof = b.pix.eol && y + 1u == f.height;
      b.remap = f.remap[i];
      b.mask = f.mask[i] != 0;
      b.cls = f.cls.empty() ? uint8_t{0} : f.cls[i];
      out.push_back(b);
      ++sent;
    }
  }
}

inline void append_idle(std::vector<LutBeat>& out, size_t cycles) {
  out.insert(out.end(), cycles, LutBeat{});
}

// Random frame: remap uniform, mask from a random threshold on remap with some
// salt so that both long and single-pixel runs occur.
inline LutFrame random_frame(std::mt19937& rng, uint16_t width, uint16_t height) {
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<uint8_t> grey(size_t{width} * height);
  // Smooth-ish rows (random walk) so thresholds give runs of many lengths.
  int v = byte(rng);
  for (auto& g : grey) {
    v = std::clamp(v + byte(rng) / 16 - 8, 0, 255);
    if (byte(rng) < 4) v = byte(rng);
    g = static_cast<uint8_t>(v);
  }
  std::array<LutEntry, 256> lut{};
  const int threshold = byte(rng);
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = lut_entry(static_cast<uint8_t>(byte(rng)), g >= threshold);
  }
  return LutFrame::from_grey(grey, width, height, lut);
}

}  // namespace ceilnav::stream::test
