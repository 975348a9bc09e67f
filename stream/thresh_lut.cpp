#include "stream/thresh_lut.hpp"

#include "common/limits.hpp"

namespace ceilnav::stream {

static_assert(ThreshLut::kEntries == (size_t{1} << kPixelBits), "one entry per grey level");
static_assert(kLutEntryMask == (1u << ThreshLut::kEntryBits) - 1u, "entry bits");

void ThreshLut::reset() {
  active_q_ = 0;
  pending_q_ = false;
  out_q_ = LutBeat{};
}

void ThreshLut::write(uint8_t index, LutEntry entry) {
  bank_[active_q_ ^ 1u][index] = static_cast<LutEntry>(entry & kLutEntryMask);
  pending_q_ = true;
}

void ThreshLut::clock(const PixelBeat& s_pix, bool frame_start) {
  const LutEntry entry = s_pix.valid ? bank_[active_q_][s_pix.grey] : LutEntry{0};
  out_q_.pix = s_pix;
  out_q_.remap = static_cast<uint8_t>(entry & kLutRemapMask);
  out_q_.mask = (entry & kLutMaskBit) != 0;
  out_q_.cls = lut_class(entry);
  if (frame_start) {
    commit_at_frame_start();
  }
}

void ThreshLut::clock(const PixelBeat& s_pix, bool frame_start, const LutWrite& wr) {
  if (wr.en) {
    write(wr.index, wr.data);
  }
  clock(s_pix, frame_start);
}

void ThreshLut::commit_at_frame_start() {
  if (pending_q_) {
    active_q_ ^= 1u;
    pending_q_ = false;
  }
}

}  // namespace ceilnav::stream
