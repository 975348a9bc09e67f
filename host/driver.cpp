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
  const uint32_t features = bus_.read32(r::features::kOffset);
  has_class_moments_ = r::features::kClassMoments.get(features) != 0;
  has_corridor_ = r::features::kCorridor.get(features) != 0;
  has_orientation_ = r::features::kOrientation.get(features) != 0;
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

void Driver::configure_corridor(const stream::EdgeConfig& edge, const stream::HoughConfig& hough) {
  if (r::features::kCorridor.get(bus_.read32(r::features::kOffset)) == 0) {
    throw std::runtime_error("ceilnav driver: the device has no corridor blocks (FEATURES)");
  }
  has_corridor_ = true;
  bus_.write32(r::edge_control::kOffset,
               r::edge_control::kEnable.put(edge.enable ? 1u : 0u) |
                   r::edge_control::kMode.put(static_cast<uint32_t>(edge.mode)) |
                   r::edge_control::kThreshold.put(edge.threshold));
  bus_.write32(r::hough_control::kOffset,
               r::hough_control::kEnable.put(hough.enable ? 1u : 0u) |
                   r::hough_control::kUnitWeight.put(hough.unit_weight ? 1u : 0u) |
                   r::hough_control::kWeightShift.put(hough.weight_shift) |
                   r::hough_control::kRhoShift.put(hough.rho_shift) |
                   r::hough_control::kThetaFirst.put(hough.theta_first) |
                   r::hough_control::kThetaCount.put(hough.theta_count));
  bus_.write32(r::hough_geometry::kOffset, r::hough_geometry::kWidth.put(hough.width));
  edge_cfg_ = edge;
  hough_cfg_ = hough;
}

stream::CorridorReadout Driver::read_corridor() {
  if (!has_corridor_) {
    throw std::runtime_error("ceilnav driver: the device has no corridor blocks (FEATURES)");
  }
  // The frame's trailer is in the edge FIFO once FRAME_DONE was seen: the
  // hough block has published the frame when nothing is pending.
  const uint64_t start = bus_.cycles();
  while (r::status::kHoughPending.get(bus_.read32(r::status::kOffset)) != 0) {
    if (bus_.cycles() - start > options_.hough_timeout_cycles) {
      throw std::runtime_error("ceilnav driver: the hough block did not publish the frame");
    }
    bus_.idle(64);
  }
  bus_.write32(r::intr_state::kOffset, r::intr_state::kHoughDone.mask());
  stream::CorridorReadout out;
  out.edge = edge_cfg_;
  out.config = hough_cfg_;
  const uint32_t shape = bus_.read32(r::hough_shape::kOffset);
  out.shape.lanes = static_cast<int>(r::hough_shape::kLanes.get(shape));
  out.shape.theta_step = static_cast<int>(r::hough_shape::kThetaStep.get(shape));
  out.shape.rho_bits = static_cast<int>(r::hough_shape::kRhoBits.get(shape));
  out.shape.acc_bits = static_cast<int>(r::hough_shape::kAccBits.get(shape));
  out.frame_count = bus_.read32(r::hough_frame_count::kOffset);
  out.valid = r::hough_status::kResultsValid.get(bus_.read32(r::hough_status::kOffset)) != 0;
  stream::HoughCounters& c = out.counters;
  c.edges = bus_.read32(r::hough_edges::kOffset);
  c.bad_edges = bus_.read32(r::hough_bad_edges::kOffset);
  c.votes = bus_.read32(r::hough_votes::kOffset);
  c.dropped = bus_.read32(r::hough_dropped::kOffset);
  c.saturated = bus_.read32(r::hough_saturated::kOffset);
  c.trailer_edges = bus_.read32(r::hough_trailer_edges::kOffset);
  c.trailer_flags = bus_.read32(r::hough_trailer_flags::kOffset);
  out.edge_trailers_lost = bus_.read32(r::edge_trailers_lost::kOffset);
  out.hough_stalls = bus_.read32(r::hough_stalls::kOffset);
  // The cells, j-major: HOUGH_INDEX = j << RHO_BITS | rho counts up by itself.
  const auto n = static_cast<uint32_t>(out.shape.n_theta()) * out.shape.rho_bins();
  out.cells.resize(n);
  bus_.write32(r::hough_index::kOffset, 0);
  for (uint32_t i = 0; i < n; ++i) {
    out.cells[i] = r::hough_data::kCount.get(bus_.read32(r::hough_data::kOffset));
  }
  out.consistent = bus_.read32(r::hough_frame_count::kOffset) == out.frame_count;
  return out;
}

void Driver::configure_orientation(const OrientationControl& ori) {
  if (r::features::kOrientation.get(bus_.read32(r::features::kOffset)) == 0) {
    throw std::runtime_error("ceilnav driver: the device has no orientation block (FEATURES)");
  }
  has_orientation_ = true;
  bus_.write32(r::ori_control::kOffset, r::ori_control::kEnable.put(ori.enable ? 1u : 0u) |
                                            r::ori_control::kThreshold.put(ori.threshold));
}

OrientationReadout Driver::read_orientation() {
  if (!has_orientation_) {
    throw std::runtime_error("ceilnav driver: the device has no orientation block (FEATURES)");
  }
  OrientationReadout out;
  out.frames = bus_.read32(r::ori_frames::kOffset);
  const uint32_t status = bus_.read32(r::ori_status::kOffset);
  out.valid = r::ori_status::kResultsValid.get(status) != 0;
  out.skipped = bus_.read32(r::ori_skipped::kOffset);
  out.votes = bus_.read32(r::ori_votes::kOffset);
  // The bins: ORI_INDEX counts up by itself with every ORI_DATA read.
  out.bins.resize(r::ori_status::kNumBins.get(status));
  bus_.write32(r::ori_index::kOffset, 0);
  for (uint32_t& b : out.bins) b = r::ori_data::kCount.get(bus_.read32(r::ori_data::kOffset));
  out.consistent = bus_.read32(r::ori_frames::kOffset) == out.frames;
  return out;
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
