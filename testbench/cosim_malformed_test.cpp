// Malformed video streams at device level: for each class a good
// frame, the malformed frame, then a good frame, with random tvalid gaps and
// m_axis_runs back-pressure. Vceilnav_top and stream::CeilnavTop get the same
// stimulus and every output port is compared after every edge; the registers
// (read over AXI4-Lite) show the counters, INTR_STATE.FRAME_ERROR and that the
// next good frame's results equal Pipeline::process_frame exactly.
// See docs/malformed_streams.md.
#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "ceilnav/regs.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/pipeline.hpp"
#include "testbench/cosim_common.hpp"
#include "testbench/top_cosim.hpp"
#include "testbench/video_stream.hpp"

namespace ceilnav::testbench {
namespace {

namespace r = regs;
using stream::FrameErrorCounters;
using stream::RunRecord;
using stream::VideoBeat;

constexpr int kWidth = 32;
constexpr int kHeight = 24;

// The bench (run back-pressure set per test), plus the counter registers.
class Bench : public DeviceBench {
 public:
  explicit Bench(uint64_t seed) : DeviceBench(seed, "ceilnav_top_malformed", 1.0) {}

  FrameErrorCounters counters() {
    FrameErrorCounters c;
    c.early_eol = read(r::cnt_early_eol::kOffset);
    c.late_eol = read(r::cnt_late_eol::kOffset);
    c.early_sof = read(r::cnt_early_sof::kOffset);
    c.missing_sof = read(r::cnt_missing_sof::kOffset);
    c.frames_ok = read(r::cnt_frames_ok::kOffset);
    c.frames_aborted = read(r::cnt_frames_aborted::kOffset);
    return c;
  }
  FrameErrorCounters res_counters() {
    FrameErrorCounters c;
    c.early_eol = read(r::res_early_eol::kOffset);
    c.late_eol = read(r::res_late_eol::kOffset);
    c.early_sof = read(r::res_early_sof::kOffset);
    c.missing_sof = read(r::res_missing_sof::kOffset);
    c.frames_ok = read(r::res_frames_ok::kOffset);
    c.frames_aborted = read(r::res_frames_aborted::kOffset);
    return c;
  }
};

// Dark noise with bright rectangles (runs for the scanner, a spread histogram).
std::vector<uint8_t> frame_pixels(Rng& rng, int w, int h) {
  return blob_pixels(rng, w, h, BlobStyle{10, 80, 2, 6, 1, 120});
}

// Blanking (up to 40 idle beats) if `blanking`, then the beats with random
// tvalid gaps between them.
void enqueue(Bench& b, const std::vector<VideoBeat>& beats, double gap_p, bool blanking) {
  b.queue(beats, gap_p, blanking ? 40 : -1, b.rng());
}

enum class Malform : uint8_t {
  kEarlyEol,
  kLateEol,
  kEarlySof,
  kMissingSof,
  kExtraLines,
  kZeroLengthLine,
  kSoftReset,
  kHardReset,
  kMalformedSofPixel,
};

struct Config {
  stream::PipelineConfig cfg;
  double gap_p = 0.0;
};

void configure(Bench& b, Config& c) {
  Rng& rng = b.rng();
  c.cfg.width = kWidth;
  c.cfg.height = kHeight;
  c.cfg.background_level = rng.uniform_as<uint8_t>(0, 40);
  c.cfg.min_run_length = rng.uniform_as<uint16_t>(1, 3);
  c.cfg.max_runs_per_row = rng.uniform_as<uint16_t>(1, 8);
  c.cfg.lut = stream::threshold_lut(rng.uniform_as<uint8_t>(90, 200));
  // Pixel classes in grey bands, and a class window (class_moments).
  const auto band = rng.uniform_as<unsigned>(20, 90);
  for (unsigned g = 0; g < 256; ++g) {
    c.cfg.lut[g] |= stream::lut_entry(0, false, static_cast<uint8_t>((g / band) % 4));
  }
  c.cfg.class_window = {rng.uniform_as<uint16_t>(0, 8), rng.uniform_as<uint16_t>(20, 40),
                        rng.uniform_as<uint16_t>(0, 6), rng.uniform_as<uint16_t>(12, 30)};
  c.gap_p = std::array<double, 3>{0.05, 0.2, 0.5}[rng.index(3)];
  b.set_tready_p(std::array<double, 4>{1.0, 0.7, 0.3, 0.1}[rng.index(4)]);
  b.write(r::intr_enable::kOffset, 0x7);
  b.write(r::width::kOffset, c.cfg.width);
  b.write(r::height::kOffset, c.cfg.height);
  b.write(r::background_level::kOffset, c.cfg.background_level);
  b.write(r::min_run_length::kOffset, c.cfg.min_run_length);
  b.write(r::max_runs_per_row::kOffset, c.cfg.max_runs_per_row);
  b.write(r::hist_source::kOffset, 0);
  if (kTopConfig.has_class_moments) {
    const stream::ClassWindow& w = c.cfg.class_window;
    b.write(r::class_win_x::kOffset, r::class_win_x::kX0.put(w.x0) | r::class_win_x::kX1.put(w.x1));
    b.write(r::class_win_y::kOffset, r::class_win_y::kY0.put(w.y0) | r::class_win_y::kY1.put(w.y1));
  }
}

// The whole table into the shadow bank: active from the next SOF.
void program_lut(Bench& b, const stream::PipelineConfig& cfg) {
  b.write(r::lut_index::kOffset, 0);
  for (unsigned g = 0; g < 256; ++g) {
    const unsigned e = cfg.lut[g];
    b.write(r::lut_data::kOffset,
            r::lut_data::kRemap.put(e & stream::kLutRemapMask) |
                r::lut_data::kMask.put((e & stream::kLutMaskBit) != 0 ? 1u : 0u) |
                r::lut_data::kClass.put(stream::lut_class(static_cast<stream::LutEntry>(e))));
  }
}

// The published result registers against the fast path of the same pixels,
// and the last frame's run stream (the beats after the previous trailer).
void check_published(Bench& b, const stream::PipelineConfig& cfg, const std::vector<uint8_t>& px) {
  stream::Pipeline fast(stream::RunScanner::kDefaultFifoDepth, kTopConfig.has_class_moments);
  fast.set_config(cfg);
  std::vector<RunRecord> want_runs;
  const stream::FrameResults want = fast.process_frame(px.data(), cfg.width, cfg.height,
                                                       static_cast<size_t>(cfg.width), &want_runs);
  for (uint32_t i = 0; i < stream::kMomentCount; ++i) {
    EXPECT_EQ(b.read64(r::mom_grey_lo::kOffset + 8 * i), want.moments.grey[i]) << "grey m" << i;
    EXPECT_EQ(b.read64(r::mom_mask_lo::kOffset + 8 * i), want.moments.mask[i]) << "mask m" << i;
  }
  for (uint32_t i = 0; kTopConfig.has_class_moments && i < r::class_mom_lo::kCount; ++i) {
    EXPECT_EQ(b.read64(r::class_mom_lo::kArray.at(i)),
              want.class_moments.cls[i / stream::kMomentCount][i % stream::kMomentCount])
        << "class moment " << i;
  }
  EXPECT_EQ(b.read(r::runs_emitted::kOffset), want.run_stats.runs_emitted);
  EXPECT_EQ(b.read(r::runs_dropped_row_limit::kOffset), want.run_stats.runs_dropped_row_limit);
  EXPECT_EQ(b.read(r::runs_dropped_overflow::kOffset), want.run_stats.runs_dropped_overflow);
  // Back-pressure only ever raises the occupancy seen (the fast path drains at once).
  EXPECT_GE(b.read(r::run_fifo_high_water::kOffset), want.run_stats.fifo_high_water);
  b.write(r::hist_index::kOffset, 0);
  for (size_t bin = 0; bin < 256; ++bin) {
    EXPECT_EQ(r::hist_data::kCount.get(b.read(r::hist_data::kOffset)), want.histogram.bins[bin])
        << "bin " << bin;
  }
  // The run stream: the last trailer closes this frame; its runs follow the
  // trailer before it (or start the log).
  b.drain_runs();
  const std::vector<stream::RunBeat>& log = b.runs_log();
  ASSERT_FALSE(log.empty());
  ASSERT_TRUE(log.back().tlast);
  size_t first = log.size() - 1;
  while (first > 0 && !log[first - 1].tlast) --first;
  std::vector<RunRecord> got_runs;
  for (size_t i = first; i + 1 < log.size(); ++i) got_runs.push_back(log[i].tdata);
  EXPECT_EQ(got_runs, want_runs);
  EXPECT_EQ(log.back().tdata.row, want_runs.size());
  // Trailer flags: never kTrailerFrameAborted on a good frame.
  const uint32_t flags =
      (want.run_stats.runs_dropped_row_limit != 0 ? uint32_t{stream::kTrailerRowLimitHit} : 0u) |
      (want.run_stats.runs_dropped_overflow != 0 ? uint32_t{stream::kTrailerFifoOverflow} : 0u);
  EXPECT_EQ(log.back().tdata.x_start, flags) << "trailer flags of a good frame";
  EXPECT_GT(want.run_stats.runs_emitted + want.histogram.bins[0], 0u);
}

// Counter moves a class must cause (relative to after the first good frame).
struct Expect {
  FrameErrorCounters delta;
  uint32_t published = 0;  // frames published by the malformed one
};

void run_class(Malform m, uint64_t seed) {
  Bench b(seed);
  Rng& rng = b.rng();
  Config c;
  configure(b, c);
  program_lut(b, c.cfg);
  b.write(r::control::kOffset, r::control::kEnable.mask());

  const int total = kWidth * kHeight;
  // ---- Frame 1, good.
  const std::vector<uint8_t> px1 = frame_pixels(rng, kWidth, kHeight);
  enqueue(b, video_beats(px1, kWidth), c.gap_p, true);
  b.drain_video();
  {
    const uint32_t intr = b.read(r::intr_state::kOffset);
    EXPECT_NE(r::intr_state::kFrameDone.get(intr), 0u);
    EXPECT_EQ(r::intr_state::kFrameError.get(intr), 0u) << "a good frame raised FRAME_ERROR";
    b.write(r::intr_state::kOffset, 0x7);
  }
  const FrameErrorCounters base = b.counters();
  EXPECT_EQ(base, (FrameErrorCounters{0, 0, 0, 0, 1, 0}));
  EXPECT_EQ(b.read(r::error_cause::kOffset), 0u) << "a good frame set ERROR_CAUSE";
  EXPECT_EQ(b.read(r::frame_count::kOffset), 1u);
  EXPECT_EQ(b.read(r::res_frame_index::kOffset), 0u);
  b.drain_runs();
  b.runs_log().clear();

  // ---- Frame 2, malformed; frame 3, good.
  std::vector<uint8_t> px2 = frame_pixels(rng, kWidth, kHeight);
  std::vector<VideoBeat> bad = video_beats(px2, kWidth);
  const std::vector<uint8_t> px3 = frame_pixels(rng, kWidth, kHeight);
  Expect e;
  bool back_to_back = false;
  switch (m) {
    case Malform::kEarlyEol: {
      // tlast inside a line, not on the SOF pixel (that one never opens a frame).
      int64_t i = 0;
      do {
        i = rng.uniform(1, total - 1);
      } while (i % kWidth == kWidth - 1);
      bad[static_cast<size_t>(i)].tlast = true;
      e.delta.early_eol = 1;
      e.delta.frames_aborted = 1;
      break;
    }
    case Malform::kLateEol: {
      const int64_t y = rng.uniform(0, kHeight - 1);
      bad[static_cast<size_t>(y * kWidth + kWidth - 1)].tlast = false;
      e.delta.late_eol = 1;
      e.delta.frames_aborted = 1;
      break;
    }
    case Malform::kEarlySof:
      // Cut after at least kClearCycles + 2 beats, so that the histogram has
      // cleared a bank for frame 3 (a shorter cut drops frame 3 as an overrun:
      // docs/blocks/histogram.md).
      bad.resize(static_cast<size_t>(rng.uniform(stream::Histogram::kClearCycles + 2, total - 1)));
      back_to_back = true;  // the next SOF arrives inside this frame
      e.delta.early_sof = 1;
      e.delta.frames_aborted = 1;
      break;
    case Malform::kMissingSof:
      bad[0].tuser = false;
      e.delta.missing_sof = 1;
      break;
    case Malform::kExtraLines: {
      // The first HEIGHT lines are a complete frame; the rest has no SOF.
      const auto extra = static_cast<size_t>(rng.uniform(1, 3));
      std::vector<uint8_t> more = frame_pixels(rng, kWidth, kHeight);
      more.resize(extra * kWidth);
      std::vector<VideoBeat> tail = video_beats(more, kWidth);
      tail[0].tuser = false;
      bad.insert(bad.end(), tail.begin(), tail.end());
      e.delta.frames_ok = 1;
      e.delta.missing_sof = 1;
      e.published = 1;
      break;
    }
    case Malform::kZeroLengthLine: {
      const int64_t y = rng.uniform(1, kHeight - 1);
      bad[static_cast<size_t>(y * kWidth)].tlast = true;
      e.delta.early_eol = 1;
      e.delta.frames_aborted = 1;
      break;
    }
    case Malform::kSoftReset:
    case Malform::kHardReset:
      break;
    case Malform::kMalformedSofPixel:
      // tlast on the SOF pixel of a 32-wide frame: the frame is never opened,
      // the rest of it is discarded silently.
      bad[0].tlast = true;
      e.delta.early_eol = 1;
      break;
  }
  enqueue(b, bad, c.gap_p, true);

  if (m == Malform::kSoftReset) {
    // CONTROL.SOFT_RESET while the frame streams: every counter restarts at 0
    // and the rest of the frame is pixels without an SOF.
    const auto until = static_cast<size_t>(rng.uniform(total / 4, total / 2));
    while (b.video().size() > until && !b.sim().failed()) b.step();
    b.write(r::control::kOffset, r::control::kEnable.mask() | r::control::kSoftReset.mask());
    const size_t valid_left = static_cast<size_t>(std::count_if(
        b.video().begin(), b.video().end(), [](const VideoBeat& v) { return v.tvalid; }));
    ASSERT_GT(valid_left, 2u) << "the soft reset must land inside the frame";
    b.runs_log().clear();  // the FIFO was reset with the datapath
    e.delta.missing_sof = 1;
  }
  if (m == Malform::kHardReset) {
    // rst_ni while the frame streams: the whole device restarts (registers at
    // their reset values, CONTROL.ENABLE = 0), so the rest of the frame is
    // dropped by the closed input gate without counting; the host then brings
    // the device up again (configuration, LUT, enable) before frame 3.
    const auto until = static_cast<size_t>(rng.uniform(total / 4, total / 2));
    while (b.video().size() > until && !b.sim().failed()) b.step();
    b.hard_reset();
    EXPECT_EQ(b.read(r::control::kOffset), 0u);
    EXPECT_EQ(b.read(r::width::kOffset), r::width::kValue.reset);
    EXPECT_EQ(b.read(r::intr_state::kOffset), 0u);
    EXPECT_EQ(b.counters(), FrameErrorCounters{});
    const size_t valid_left = static_cast<size_t>(std::count_if(
        b.video().begin(), b.video().end(), [](const VideoBeat& v) { return v.tvalid; }));
    ASSERT_GT(valid_left, 2u) << "the reset must land inside the frame";
    b.runs_log().clear();
    configure(b, c);
    program_lut(b, c.cfg);
    b.write(r::control::kOffset, r::control::kEnable.mask());
  }
  const bool reset = m == Malform::kSoftReset || m == Malform::kHardReset;
  if (!back_to_back) {
    b.drain_video();
    const uint32_t intr = b.read(r::intr_state::kOffset);
    // A hard reset clears INTR_STATE, and the gate drops the rest silently.
    EXPECT_EQ(r::intr_state::kFrameError.get(intr), m == Malform::kHardReset ? 0u : 1u)
        << "FRAME_ERROR";
    b.write(r::intr_state::kOffset, 0x7);
    const uint32_t published = reset ? 0u : 1u + e.published;
    EXPECT_EQ(b.read(r::frame_count::kOffset), published);
    EXPECT_EQ(b.read(r::status::kOffset) & r::status::kInFrame.mask(), 0u);
    if (m == Malform::kHardReset) {
      EXPECT_EQ(b.read(r::status::kOffset) & r::status::kResultsValid.mask(), 0u);
    } else if (m == Malform::kSoftReset) {
      // LUT contents are kept but bank 0 is active again: a full reprogram.
      EXPECT_EQ(b.read(r::status::kOffset) & r::status::kResultsValid.mask(), 0u);
      program_lut(b, c.cfg);
    } else if (m == Malform::kExtraLines) {
      EXPECT_EQ(b.read(r::res_frame_index::kOffset), 1u);
    } else {
      EXPECT_EQ(b.read(r::res_frame_index::kOffset), 0u) << "the malformed frame was published";
    }
  }
  enqueue(b, video_beats(px3, kWidth), c.gap_p, !back_to_back);
  b.drain_video();

  // ---- After frame 3.
  const uint32_t intr = b.read(r::intr_state::kOffset);
  EXPECT_NE(r::intr_state::kFrameDone.get(intr), 0u);
  if (back_to_back) {
    EXPECT_NE(r::intr_state::kFrameError.get(intr), 0u) << "FRAME_ERROR not raised";
  } else {
    EXPECT_EQ(r::intr_state::kFrameError.get(intr), 0u) << "the good frame raised FRAME_ERROR";
  }
  FrameErrorCounters want = reset ? FrameErrorCounters{} : base;
  want.early_eol += e.delta.early_eol;
  want.late_eol += e.delta.late_eol;
  want.early_sof += e.delta.early_sof;
  want.missing_sof += e.delta.missing_sof;
  want.frames_ok += e.delta.frames_ok + 1;
  want.frames_aborted += e.delta.frames_aborted;
  const FrameErrorCounters got = b.counters();
  EXPECT_EQ(got.early_eol, want.early_eol);
  EXPECT_EQ(got.late_eol, want.late_eol);
  EXPECT_EQ(got.early_sof, want.early_sof);
  EXPECT_EQ(got.missing_sof, want.missing_sof);
  EXPECT_EQ(got.frames_ok, want.frames_ok);
  EXPECT_EQ(got.frames_aborted, want.frames_aborted);
  EXPECT_EQ(b.res_counters(), got) << "RES_* of the last frame = the live counters";
  // ERROR_CAUSE: one sticky bit per class that occurred (kept by a soft
  // reset, cleared by a hardware reset), then W1C.
  const uint32_t cause = r::error_cause::kEarlyEol.put(e.delta.early_eol != 0 ? 1u : 0u) |
                         r::error_cause::kLateEol.put(e.delta.late_eol != 0 ? 1u : 0u) |
                         r::error_cause::kEarlySof.put(e.delta.early_sof != 0 ? 1u : 0u) |
                         r::error_cause::kMissingSof.put(e.delta.missing_sof != 0 ? 1u : 0u);
  EXPECT_EQ(b.read(r::error_cause::kOffset), cause) << "ERROR_CAUSE";
  b.write(r::error_cause::kOffset, 0xF);
  EXPECT_EQ(b.read(r::error_cause::kOffset), 0u) << "ERROR_CAUSE after W1C";
  const uint32_t frames = reset ? 1u : 2u + e.published;
  EXPECT_EQ(b.read(r::frame_count::kOffset), frames);
  EXPECT_EQ(b.read(r::res_frame_index::kOffset), want.frames_ok - 1);
  const uint32_t status = b.read(r::status::kOffset);
  EXPECT_NE(status & r::status::kResultsValid.mask(), 0u);
  EXPECT_EQ(status & r::status::kInFrame.mask(), 0u);
  check_published(b, c.cfg, px3);
  // The run stream marks each aborted frame (its runs are partial) with a
  // trailer flag; published frames end with a trailer without it.
  size_t trailers = 0;
  size_t aborted = 0;
  for (const stream::RunBeat& beat : b.runs_log()) {
    if (!beat.tlast) continue;
    ++trailers;
    if ((beat.tdata.x_start & stream::kTrailerFrameAborted) != 0) ++aborted;
  }
  EXPECT_EQ(aborted, e.delta.frames_aborted);
  EXPECT_EQ(trailers, e.delta.frames_aborted + e.published + 1u);

  b.sim().report();
  EXPECT_FALSE(b.sim().failed());
}

TEST(MalformedCosim, EarlyEol) {
  run_class(Malform::kEarlyEol, cosim_seed(501));
}
TEST(MalformedCosim, LateEol) {
  run_class(Malform::kLateEol, cosim_seed(502));
}
TEST(MalformedCosim, EarlySof) {
  run_class(Malform::kEarlySof, cosim_seed(503));
}
TEST(MalformedCosim, MissingSof) {
  run_class(Malform::kMissingSof, cosim_seed(504));
}
TEST(MalformedCosim, ExtraLines) {
  run_class(Malform::kExtraLines, cosim_seed(505));
}
TEST(MalformedCosim, ZeroLengthLine) {
  run_class(Malform::kZeroLengthLine, cosim_seed(506));
}
TEST(MalformedCosim, SoftResetMidFrame) {
  run_class(Malform::kSoftReset, cosim_seed(507));
}
TEST(MalformedCosim, HardResetMidFrame) {
  run_class(Malform::kHardReset, cosim_seed(508));
}
TEST(MalformedCosim, MalformedSofPixel) {
  run_class(Malform::kMalformedSofPixel, cosim_seed(509));
}

}  // namespace
}  // namespace ceilnav::testbench
