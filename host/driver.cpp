#include "host/driver.hpp"

#include <stdexcept>

#include "ceilnav/regs.hpp"
#include "common/version.hpp"

namespace ceilnav::host {

namespace r = regs;

Driver::Driver(Bus& bus, const DriverOptions& options) : bus_(bus), options_(options) {}

uint32_t Driver::identify() {
  const uint32_t id = bus_.read32(r::id::kOffset);
  if (id != kDeviceId) throw std::runtime_error("ceilnav driver: not a ceilnav device (ID)");
  const uint32_t version = bus_.read32(r::version::kOffset);
  if (r::version::kMajor.get(version) != r::version::kMajor.get(version_word())) {
    throw std::runtime_error("ceilnav driver: unsupported major version");
  }
  return version;
}

void Driver::configure(const stream::PipelineConfig& cfg) {
  has_class_moments_ = r::features::kClassMoments.get(bus_.read32(r::features::kOffset)) != 0;
  bus_.write32(r::width::kOffset, r::width::kValue.put(cfg.width));
  bus_.write32(r::height::kOffset, r::height::kValue.put(cfg.height));
  bus_.write32(r::background_level::kOffset, r::background_level::kValue.put(cfg.background_level));
  bus_.write32(r::min_run_length::kOffset, r::min_run_length::kValue.put(cfg.min_run_length));
  bus_.write32(r::max_runs_per_row::kOffset, r::max_runs_per_row::kValue.put(cfg.max_runs_per_row));
  bus_.write32(r::hist_source::kOffset,
               r::hist_source::kRemap.put(cfg.hist_source_remap ? 1u : 0u));
  if (has_class_moments_) {
    bus_.write32(r::class_win_x::kOffset, r::class_win_x::kX0.put(cfg.class_window.x0) |
                                              r::class_win_x::kX1.put(cfg.class_window.x1));
    bus_.write32(r::class_win_y::kOffset, r::class_win_y::kY0.put(cfg.class_window.y0) |
                                              r::class_win_y::kY1.put(cfg.class_window.y1));
  }
  // All 256 entries: after a bank swap the shadow bank holds the older table.
  bus_.write32(r::lut_index::kOffset, 0);
  for (stream::LutEntry e : cfg.lut) {
    bus_.write32(r::lut_data::kOffset,
                 r::lut_data::kRemap.put(e & stream::kLutRemapMask) |
                     r::lut_data::kMask.put((e & stream::kLutMaskBit) != 0 ? 1u : 0u) |
                     r::lut_data::kClass.put(stream::lut_class(e)));
  }
  bus_.write32(r::intr_state::kOffset, r::intr_state::kFrameDone.mask() |
                                           r::intr_state::kRunOverflow.mask() |
                                           r::intr_state::kFrameError.mask());
  bus_.write32(r::intr_enable::kOffset, r::intr_enable::kFrameDone.mask());
  bus_.write32(r::control::kOffset,
               r::control::kEnable.put(1) |
                   r::control::kRunSink.put(options_.run_sink == RunSink::kRegisters ? 1u : 0u));
}

stream::FrameResults Driver::read_results() {
  stream::FrameResults f;
  f.frame_index = bus_.read32(r::res_frame_index::kOffset);
  f.valid = r::status::kResultsValid.get(bus_.read32(r::status::kOffset)) != 0;
  bus_.write32(r::hist_index::kOffset, 0);
  for (uint32_t& bin : f.histogram.bins) {
    bin = r::hist_data::kCount.get(bus_.read32(r::hist_data::kOffset));
  }
  for (uint32_t i = 0; i < static_cast<uint32_t>(stream::kMomentCount); ++i) {
    f.moments.grey[i] = bus_.read32(r::mom_grey_lo::kArray.at(i)) |
                        uint64_t{bus_.read32(r::mom_grey_hi::kArray.at(i))} << 32;
    f.moments.mask[i] = bus_.read32(r::mom_mask_lo::kArray.at(i)) |
                        uint64_t{bus_.read32(r::mom_mask_hi::kArray.at(i))} << 32;
  }
  // CLASS_MOM_*[6 (c - 1) + k]: pixel class c = 1..3, moment k.
  for (uint32_t i = 0; has_class_moments_ && i < r::class_mom_lo::kCount; ++i) {
    f.class_moments.cls[i / stream::kMomentCount][i % stream::kMomentCount] =
        bus_.read32(r::class_mom_lo::kArray.at(i)) |
        uint64_t{bus_.read32(r::class_mom_hi::kArray.at(i))} << 32;
  }
  f.run_stats.runs_emitted = bus_.read32(r::runs_emitted::kOffset);
  f.run_stats.runs_dropped_row_limit = bus_.read32(r::runs_dropped_row_limit::kOffset);
  f.run_stats.runs_dropped_overflow = bus_.read32(r::runs_dropped_overflow::kOffset);
  f.run_stats.fifo_high_water = bus_.read32(r::run_fifo_high_water::kOffset);
  f.errors.early_eol = bus_.read32(r::res_early_eol::kOffset);
  f.errors.late_eol = bus_.read32(r::res_late_eol::kOffset);
  f.errors.early_sof = bus_.read32(r::res_early_sof::kOffset);
  f.errors.missing_sof = bus_.read32(r::res_missing_sof::kOffset);
  f.errors.frames_ok = bus_.read32(r::res_frames_ok::kOffset);
  f.errors.frames_aborted = bus_.read32(r::res_frames_aborted::kOffset);
  f.cycles_in_frame = bus_.read32(r::cycles_per_frame::kOffset);
  return f;
}

bool Driver::next_run_entry(stream::RunBeat& beat) {
  if (options_.run_sink == RunSink::kStream) {
    if (stream_backlog_.empty()) {
      for (const stream::RunBeat& b : bus_.take_run_stream()) stream_backlog_.push_back(b);
    }
    if (stream_backlog_.empty()) return false;
    beat = stream_backlog_.front();
    stream_backlog_.pop_front();
    return true;
  }
  const uint32_t w0 = bus_.read32(r::run_word0::kOffset);
  if (r::run_word0::kValid.get(w0) == 0) return false;
  beat.tvalid = true;
  beat.tlast = r::run_word0::kLast.get(w0) != 0;
  beat.tdata.row = static_cast<uint16_t>(r::run_word0::kRow.get(w0));
  const uint32_t w1 = bus_.read32(r::run_word1::kOffset);
  beat.tdata.x_start = static_cast<uint16_t>(r::run_word1::kXStart.get(w1));
  beat.tdata.x_end = static_cast<uint16_t>(r::run_word1::kXEnd.get(w1));
  beat.tdata.sum_w = r::run_word2::kSumW.get(bus_.read32(r::run_word2::kOffset));
  beat.tdata.sum_xw = r::run_word3::kSumXw.get(bus_.read32(r::run_word3::kOffset));  // pops
  return true;
}

void Driver::read_runs(FrameReadout& out) {
  // The runs of aborted frames end with a trailer flagged kTrailerFrameAborted:
  // they precede the published frame's runs and are skipped.
  const uint64_t start = bus_.cycles();
  stream::RunBeat beat;
  while (bus_.cycles() - start < options_.run_timeout_cycles) {
    if (!next_run_entry(beat)) {
      bus_.idle(16);
      continue;
    }
    if (!beat.tlast) {
      out.runs.push_back(beat.tdata);
      continue;
    }
    if ((beat.tdata.x_start & stream::kTrailerFrameAborted) != 0) {
      out.runs.clear();
      continue;
    }
    out.trailer_seen = true;
    out.trailer_flags = beat.tdata.x_start;
    out.trailer_run_count = beat.tdata.row;
    return;
  }
}

FrameReadout Driver::read_frame() {
  FrameReadout out;
  for (;;) {
    if (!bus_.wait_irq(options_.irq_timeout_cycles)) {
      throw std::runtime_error("ceilnav driver: no interrupt");
    }
    const uint32_t state = bus_.read32(r::intr_state::kOffset);
    bus_.write32(r::intr_state::kOffset, state);  // W1C what was seen
    out.intr_state |= state;
    if ((state & r::intr_state::kFrameDone.mask()) != 0) break;
  }
  out.results = read_results();
  out.frame_count = bus_.read32(r::frame_count::kOffset);
  out.eof_to_irq_cycles = bus_.read32(r::eof_to_irq_cycles::kOffset);
  read_runs(out);
  out.consistent = bus_.read32(r::res_frame_index::kOffset) == out.results.frame_index;
  if (!out.trailer_seen) throw std::runtime_error("ceilnav driver: the frame's trailer is missing");
  return out;
}

}  // namespace ceilnav::host
