// Fuzz target: the cycle-level device pipeline (stream::Pipeline::clock) on
// arbitrary AXI4-Stream video beat sequences (tvalid, tuser, tlast, data),
// arbitrary run-stream back-pressure (tready), configuration writes at any
// cycle, resets, and a run FIFO of 2 .. 1024 entries. Opcodes:
// docs/fuzzing.md.
//
// The fuzzer keeps its own reference of the video protocol, written from the
// AXI4-Stream rules and the class table of docs/malformed_streams.md (not from
// frame_check.cpp): which SOF opens a frame, which beats complete it, which
// error class each malformed beat is. Invariants (docs/fuzzing.md):
//  * s_axis_video_tready is 1 by construction (Pipeline::clock has no tready
//    output and consumes every beat): nothing to check at run time;
//  * the six frame_check counters equal the reference after every edge;
//    SOF beats = frames_ok + early_eol + late_eol + early_sof + (frame open);
//  * a frame that the reference says is well-formed is published, or counted
//    in frames_overrun: published + overrun = frames_ok after the drain;
//    published frame_index strictly increases and is < frames_ok;
//  * the published results of a well-formed frame equal the fast path
//    Pipeline::process_frame of the same pixels with the configuration of its
//    SOF (histogram, moments, row-limit drops; emitted runs = fast runs -
//    overflow drops); the histogram counts W x H pixels; errors = counters
//    at its EOF beat; cycles_in_frame = beats from its SOF to its EOF;
//    fifo_high_water <= FIFO depth (and >= the fast path's when >= 3);
//  * the run stream: every run lies inside its frame (row < H, x_start <=
//    x_end < W, length >= min_run_length, sums consistent with the span);
//    one trailer per frame opened downstream, in order, flagged aborted
//    exactly for the aborted frames, carrying the count of runs received;
//    a good frame's runs (trailer without overflow flag) equal the fast
//    path's runs; with the overflow flag they are a subsequence of them.
//    (Checked while run_trailers_lost() = 0: a lost trailer merges frames.)
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <numeric>
#include <optional>
#include <vector>

#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "fuzz/byte_reader.hpp"
#include "fuzz/check.hpp"
#include "stream/beat.hpp"
#include "stream/pipeline.hpp"

namespace {

using ceilnav::fuzz::ByteReader;
using namespace ceilnav::stream;

constexpr size_t kMaxBeats = 40000;  // per input, before the drain
constexpr uint16_t kMaxFuzzWidth = 32;
constexpr uint16_t kMaxFuzzHeight = 16;

// Deterministic pseudo-random numbers from the input (pixels, gaps, tready).
struct Lcg {
  uint32_t s;
  uint32_t next() {
    s = s * 1664525u + 1013904223u;
    return s >> 8;
  }
  bool chance(uint8_t p256) { return (next() & 0xFFu) < p256; }
};

PipelineConfig decode_config(ByteReader& in) {
  PipelineConfig c;
  c.width = static_cast<uint16_t>(1 + in.u8() % kMaxFuzzWidth);
  c.height = static_cast<uint16_t>(1 + in.u8() % kMaxFuzzHeight);
  const uint8_t lut_mode = in.u8();
  const uint8_t threshold = in.u8();
  if ((lut_mode & 1u) == 0) {
    c.lut = threshold_lut(threshold);
  } else {
    Lcg rng{static_cast<uint32_t>(lut_mode) << 8 | threshold};
    for (LutEntry& e : c.lut) {
      const uint32_t v = rng.next();
      e = lut_entry(static_cast<uint8_t>(v), (v >> 8 & 0xFFu) > threshold);
    }
  }
  c.background_level = in.u8();
  const uint8_t runs = in.u8();
  c.min_run_length = static_cast<uint16_t>(runs & 3u);  // 0 behaves as 1
  c.max_runs_per_row = static_cast<uint16_t>(runs >> 2 & 15u);
  c.hist_source_remap = (runs & 0x40u) != 0;
  return c;
}

// Pixel pattern of generated frames: bright bars of a random period and slope
// on a dim, noisy background (runs of many lengths).
uint8_t pattern_pixel(uint8_t seed, uint32_t x, uint32_t y, Lcg& rng) {
  const uint32_t period = 3u + seed % 7u;
  const uint32_t slope = seed >> 3 & 3u;
  const bool bar = (x + slope * y) % period < period / 2;
  const uint32_t noise = rng.next() % 24u;
  return static_cast<uint8_t>(bar ? 255u - noise : noise * 4u);
}

// The reference video protocol (docs/malformed_streams.md), independent of
// frame_check.cpp.
struct RefProtocol {
  enum class State { idle, open, discard } state = State::idle;
  uint32_t w = 1, h = 1, count = 0;  // pixels accepted in the open frame
  FrameErrorCounters counters;
  uint64_t sof_beats = 0;

  // What one valid beat did (the width/height are the shadow config at it).
  struct Effect {
    bool aborted = false;    // the open frame was aborted
    bool opened = false;     // a frame opened downstream (a well-formed SOF pixel)
    bool accepted = false;   // the beat is a pixel of the open frame
    bool completed = false;  // ... and its last one
  };
  Effect beat(const VideoBeat& b, uint32_t cfg_w, uint32_t cfg_h) {
    Effect e;
    if (b.tuser) {
      ++sof_beats;
      if (state == State::open) {  // early SOF
        ++counters.early_sof;
        ++counters.frames_aborted;
        e.aborted = true;
      }
      w = std::max(1u, cfg_w);
      h = std::max(1u, cfg_h);
      count = 0;
      if (b.tlast != (w == 1)) {  // a malformed SOF pixel: the frame never opens
        ++(b.tlast ? counters.early_eol : counters.late_eol);
        state = State::discard;
        return e;
      }
      e.opened = true;
      state = State::open;
    } else {
      switch (state) {
        case State::idle:  // a pixel outside any frame: one count per burst
          ++counters.missing_sof;
          state = State::discard;
          return e;
        case State::discard:
          return e;
        case State::open:
          break;
      }
      if (b.tlast != (count % w == w - 1)) {
        ++(b.tlast ? counters.early_eol : counters.late_eol);
        ++counters.frames_aborted;
        e.aborted = true;
        state = State::discard;
        return e;
      }
    }
    e.accepted = true;
    if (++count == w * h) {
      ++counters.frames_ok;
      state = State::idle;
      e.completed = true;
    }
    return e;
  }
};

// A frame opened downstream (its SOF pixel was well-formed).
struct Frame {
  PipelineConfig cfg;  // shadow at its SOF beat = the config it is processed with
  std::vector<uint8_t> pixels;
  uint64_t sof_cycle = 0;
  bool complete = false, aborted = false;
  FrameErrorCounters errors_at_eof;
  uint64_t cycles_in_frame = 0;
  // Fast path, computed when the frame completes.
  FrameResults fast;
  std::vector<RunRecord> fast_runs;
};

struct Harness {
  explicit Harness(uint32_t fifo_depth) : pipeline(fifo_depth), depth(fifo_depth) {}

  Pipeline pipeline;
  uint32_t depth;
  uint64_t cycle = 0;  // edges since reset
  RefProtocol ref;
  std::deque<Frame> opened;            // frames opened downstream, until their trailer
  std::vector<Frame> good;             // completed frames in order (index = frame_index)
  std::optional<size_t> current;       // index into `opened` of the open frame
  std::vector<RunRecord> stream_runs;  // received since the last trailer
  size_t published = 0;
  int64_t last_index = -1;

  void clear_tracking() {
    cycle = 0;
    ref = RefProtocol{};
    opened.clear();
    good.clear();
    current.reset();
    stream_runs.clear();
    published = 0;
    last_index = -1;
  }

  void check_run_geometry(const RunRecord& r, const Frame& f) const {
    const uint32_t w = f.cfg.width, h = f.cfg.height;
    FUZZ_CHECK(r.row < h && r.x_start <= r.x_end && r.x_end < w,
               "run (row %u, %u..%u) outside its %ux%u frame", r.row, r.x_start, r.x_end, w, h);
    const uint32_t len = r.x_end - r.x_start + 1u;
    FUZZ_CHECK(len >= std::max<uint32_t>(1u, f.cfg.min_run_length), "run of %u < min %u", len,
               f.cfg.min_run_length);
    const uint64_t lo = r.x_start > 0 ? r.x_start - 1u : 0u;
    const uint64_t hi = std::min<uint64_t>(w - 1u, r.x_end + 1u);
    FUZZ_CHECK(r.sum_w <= 255u * (hi - lo + 1u), "sum_w %u over %llu pixels", r.sum_w,
               static_cast<unsigned long long>(hi - lo + 1u));
    FUZZ_CHECK(r.sum_xw >= lo * r.sum_w && r.sum_xw <= hi * r.sum_w,
               "sum_xw %llu not within [%llu, %llu] * sum_w %u",
               static_cast<unsigned long long>(r.sum_xw), static_cast<unsigned long long>(lo),
               static_cast<unsigned long long>(hi), r.sum_w);
  }

  void on_trailer(const RunRecord& t) {
    if (pipeline.run_trailers_lost() != 0) return;  // frames merged: no mapping any more
    FUZZ_CHECK(!opened.empty(), "a trailer with no frame opened");
    const Frame& f = opened.front();
    FUZZ_CHECK(f.complete || f.aborted, "a trailer before its frame ended");
    const bool aborted_flag = (t.x_start & kTrailerFrameAborted) != 0;
    FUZZ_CHECK(aborted_flag == f.aborted, "trailer aborted flag %d, frame aborted %d",
               aborted_flag ? 1 : 0, f.aborted ? 1 : 0);
    FUZZ_CHECK(t.row == std::min<size_t>(stream_runs.size(), 0xFFFF),
               "trailer says %u runs, %zu received", t.row, stream_runs.size());
    for (const RunRecord& r : stream_runs) check_run_geometry(r, f);
    if (f.complete) {
      if ((t.x_start & kTrailerFifoOverflow) == 0) {
        FUZZ_CHECK(stream_runs == f.fast_runs, "good frame: %zu runs received, fast path %zu",
                   stream_runs.size(), f.fast_runs.size());
      } else {
        size_t k = 0;
        for (const RunRecord& r : f.fast_runs) {
          if (k < stream_runs.size() && stream_runs[k] == r) ++k;
        }
        FUZZ_CHECK(k == stream_runs.size(), "overflowed frame: runs not a subsequence");
      }
      const bool row_limit = f.fast.run_stats.runs_dropped_row_limit != 0;
      FUZZ_CHECK(((t.x_start & kTrailerRowLimitHit) != 0) == row_limit,
                 "trailer row-limit flag vs %u row-limit drops",
                 f.fast.run_stats.runs_dropped_row_limit);
    }
    stream_runs.clear();
    opened.pop_front();
    if (current) --*current;
  }

  void on_publish() {
    const FrameResults& r = pipeline.results();
    FUZZ_CHECK(r.valid, "frame_done with results not valid");
    FUZZ_CHECK(static_cast<int64_t>(r.frame_index) > last_index, "frame_index %u after %lld",
               r.frame_index, static_cast<long long>(last_index));
    FUZZ_CHECK(r.frame_index < good.size(), "frame_index %u but %zu good frames", r.frame_index,
               good.size());
    last_index = r.frame_index;
    ++published;
    const Frame& f = good[r.frame_index];
    const uint64_t pixels = uint64_t{f.cfg.width} * f.cfg.height;
    FUZZ_CHECK(
        std::accumulate(r.histogram.bins.begin(), r.histogram.bins.end(), uint64_t{0}) == pixels,
        "histogram sum != %llu pixels", static_cast<unsigned long long>(pixels));
    FUZZ_CHECK(r.histogram == f.fast.histogram, "histogram != fast path (frame %u)", r.frame_index);
    FUZZ_CHECK(r.moments == f.fast.moments, "moments != fast path (frame %u)", r.frame_index);
    FUZZ_CHECK(r.run_stats.runs_dropped_row_limit == f.fast.run_stats.runs_dropped_row_limit,
               "row-limit drops %u != fast %u", r.run_stats.runs_dropped_row_limit,
               f.fast.run_stats.runs_dropped_row_limit);
    FUZZ_CHECK(r.run_stats.runs_emitted + r.run_stats.runs_dropped_overflow ==
                   f.fast.run_stats.runs_emitted,
               "emitted %u + overflow %u != fast %u", r.run_stats.runs_emitted,
               r.run_stats.runs_dropped_overflow, f.fast.run_stats.runs_emitted);
    FUZZ_CHECK(r.run_stats.fifo_high_water <= depth, "high water %u > depth %u",
               r.run_stats.fifo_high_water, depth);
    if (depth >= 3) {
      FUZZ_CHECK(r.run_stats.fifo_high_water >= f.fast.run_stats.fifo_high_water,
                 "high water %u < fast %u", r.run_stats.fifo_high_water,
                 f.fast.run_stats.fifo_high_water);
    }
    FUZZ_CHECK(r.errors == f.errors_at_eof, "published errors != counters at its EOF");
    FUZZ_CHECK(r.cycles_in_frame == f.cycles_in_frame, "cycles_in_frame %llu != %llu",
               static_cast<unsigned long long>(r.cycles_in_frame),
               static_cast<unsigned long long>(f.cycles_in_frame));
  }

  void finish_frame(Frame& f) {
    f.complete = true;
    f.errors_at_eof = pipeline.error_counters();
    f.cycles_in_frame = cycle - f.sof_cycle + 1;
    static Pipeline fast(4096);  // idle after every process_frame: reusable
    fast.set_config(f.cfg);
    f.fast =
        fast.process_frame(f.pixels.data(), f.cfg.width, f.cfg.height, f.cfg.width, &f.fast_runs);
    good.push_back(f);
  }

  // One edge: the consumer samples the run stream, then the pipeline clocks.
  void clock(const VideoBeat& v, bool tready) {
    const RunBeat out = pipeline.m_axis_runs();
    if (out.tvalid && tready) {
      if (out.tlast) {
        on_trailer(out.tdata);
      } else {
        stream_runs.push_back(out.tdata);
      }
    }
    const PipelineConfig shadow = pipeline.shadow_config();
    const RefProtocol::Effect e =
        v.tvalid ? ref.beat(v, shadow.width, shadow.height) : RefProtocol::Effect{};
    pipeline.clock(v, tready);

    if (e.aborted) {
      FUZZ_CHECK(current.has_value(), "abort with no open frame");
      opened[*current].aborted = true;
      current.reset();
    }
    if (e.opened) {
      Frame f;
      f.cfg = shadow;
      f.sof_cycle = cycle;
      opened.push_back(f);
      current = opened.size() - 1;
    }
    if (e.accepted) {
      FUZZ_CHECK(current.has_value(), "a pixel with no open frame");
      opened[*current].pixels.push_back(v.tdata);
    }
    if (e.completed) {
      finish_frame(opened[*current]);
      current.reset();
    }

    FUZZ_CHECK(pipeline.error_counters() == ref.counters,
               "frame_check counters differ from the reference at cycle %llu: "
               "eol %u/%u late %u/%u sof %u/%u missing %u/%u ok %u/%u aborted %u/%u",
               static_cast<unsigned long long>(cycle), pipeline.error_counters().early_eol,
               ref.counters.early_eol, pipeline.error_counters().late_eol, ref.counters.late_eol,
               pipeline.error_counters().early_sof, ref.counters.early_sof,
               pipeline.error_counters().missing_sof, ref.counters.missing_sof,
               pipeline.error_counters().frames_ok, ref.counters.frames_ok,
               pipeline.error_counters().frames_aborted, ref.counters.frames_aborted);
    const FrameErrorCounters& c = pipeline.error_counters();
    FUZZ_CHECK(ref.sof_beats == uint64_t{c.frames_ok} + c.early_eol + c.late_eol + c.early_sof +
                                    (ref.state == RefProtocol::State::open ? 1u : 0u),
               "SOF accounting");
    if (pipeline.frame_done()) on_publish();
    ++cycle;
  }

  // Reset, then the host writes the configuration again: the reset leaves the
  // LUT bank select at bank 0, whose contents are stale (docs/malformed_streams.md).
  void reset() {
    const PipelineConfig cfg = pipeline.shadow_config();
    pipeline.reset();
    pipeline.set_config(cfg);
    clear_tracking();
    FUZZ_CHECK(!pipeline.results().valid, "results valid after reset");
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ByteReader in(data, size);
  static constexpr uint32_t kDepths[8] = {2, 3, 4, 5, 8, 16, 64, 1024};
  Harness hz(kDepths[in.u8() % 8]);
  hz.pipeline.set_config(decode_config(in));
  Lcg rng{0x12345u};
  uint8_t tready_p = 255;  // P(tready) * 256, saturating at 255/256
  size_t beats = 0;
  const auto tready = [&] { return tready_p == 255 || rng.chance(tready_p); };
  const auto emit_frame = [&](uint8_t seed, uint8_t gap_p, uint32_t first_row, uint32_t rows,
                              int64_t corrupt_at, uint8_t corruption) {
    const PipelineConfig& c = hz.pipeline.shadow_config();
    const uint32_t w = c.width;
    int64_t k = 0;
    for (uint32_t y = first_row; y < first_row + rows; ++y) {
      for (uint32_t x = 0; x < w; ++x, ++k) {
        while (rng.chance(gap_p) && beats < kMaxBeats) {
          hz.clock(VideoBeat{}, tready());
          ++beats;
        }
        VideoBeat b{pattern_pixel(seed, x, y, rng), true, x == 0 && y == 0, x + 1 == w};
        if (k == corrupt_at) {
          switch (corruption % 4) {
            case 0:
              b.tlast = !b.tlast;
              break;  // early / late EOL
            case 1:
              b.tuser = true;
              break;  // early SOF
            case 2:
              b.tuser = false;
              break;  // missing SOF (on the SOF pixel)
            case 3:
              continue;  // a dropped beat
          }
        }
        hz.clock(b, tready());
        if (++beats >= kMaxBeats) return;
      }
    }
  };

  while (!in.empty() && beats < kMaxBeats) {
    const uint8_t op = in.u8();
    switch (op % 8) {
      case 0: {  // one raw beat
        const uint8_t flags = in.u8();
        const VideoBeat b{in.u8(), (flags & 1u) != 0, (flags & 2u) != 0, (flags & 4u) != 0};
        hz.clock(b, (flags & 8u) != 0);
        ++beats;
        break;
      }
      case 1: {  // a well-formed frame with the shadow geometry
        const uint8_t seed = in.u8(), gap_p = in.u8();
        emit_frame(seed, static_cast<uint8_t>(gap_p / 2), 0, hz.pipeline.shadow_config().height, -1,
                   0);
        break;
      }
      case 2: {  // one well-formed line (row 0: with SOF)
        const uint8_t seed = in.u8(), row = in.u8();
        emit_frame(seed, 0, row % kMaxFuzzHeight, 1, -1, 0);
        break;
      }
      case 3:  // a configuration write
        hz.pipeline.set_config(decode_config(in));
        break;
      case 4: {  // idle cycles
        const uint8_t n = in.u8();
        for (uint32_t i = 0; i < n && beats < kMaxBeats; ++i, ++beats) {
          hz.clock(VideoBeat{}, tready());
        }
        break;
      }
      case 5:  // run-stream back-pressure
        tready_p = in.u8();
        break;
      case 6:  // reset (rare: needs the magic argument)
        if (in.u8() == 0xA5) hz.reset();
        break;
      case 7: {  // a frame with one corrupted beat
        const uint8_t seed = in.u8(), at = in.u8(), how = in.u8();
        const PipelineConfig& c = hz.pipeline.shadow_config();
        emit_frame(seed, 8, 0, c.height, at % (int64_t{c.width} * c.height), how);
        break;
      }
    }
  }
  // Drain: the consumer reads everything, the results of the last frame land.
  for (int i = 0; i < 5000; ++i) {
    hz.clock(VideoBeat{}, true);
    if (i > 2 * Pipeline::kEofToFrameDoneCycles && hz.pipeline.run_fifo_occupancy() == 0 &&
        !hz.pipeline.m_axis_runs().tvalid) {
      break;
    }
  }
  if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) {
    const FrameErrorCounters& c = hz.pipeline.error_counters();
    std::printf(
        "beats %zu depth %u: ok %u published %zu overrun %u aborted %u early_eol %u "
        "late_eol %u early_sof %u missing_sof %u trailers_lost %u\n",
        beats, hz.depth, c.frames_ok, hz.published, hz.pipeline.frames_overrun(), c.frames_aborted,
        c.early_eol, c.late_eol, c.early_sof, c.missing_sof, hz.pipeline.run_trailers_lost());
  }
  FUZZ_CHECK(hz.pipeline.run_fifo_occupancy() == 0, "the run FIFO did not drain");
  FUZZ_CHECK(hz.published + hz.pipeline.frames_overrun() == hz.pipeline.error_counters().frames_ok,
             "published %zu + overrun %u != frames_ok %u", hz.published,
             hz.pipeline.frames_overrun(), hz.pipeline.error_counters().frames_ok);
  if (hz.pipeline.run_trailers_lost() == 0) {
    size_t ended = 0;
    for (const Frame& f : hz.opened) ended += (f.complete || f.aborted) ? 1 : 0;
    FUZZ_CHECK(ended == 0, "%zu ended frames never got their trailer", ended);
  }
  return 0;
}
