// Co-simulation: rtl_model/frame_check.sv against stream::FrameCheck, every
// output port on every clock, under random geometry, tvalid gaps, zero
// blanking, malformed streams, configuration changes and resets.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stream/beat.hpp"
#include "stream/frame_check.hpp"
#include "stream/tests/video_source.hpp"
#include "testbench/block_bench.hpp"
#include "testbench/ports.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "Vframe_check.h"
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::testbench {
namespace {

using stream::FrameCheck;
using stream::VideoBeat;

// One clock of stimulus: the beat, the configuration inputs, or a reset cycle.
struct VideoCycle {
  VideoBeat beat;
  uint16_t cfg_width = 1;  // 12-bit port: 0 .. 4095
  uint16_t cfg_height = 1;
  bool reset_before = false;  // reset_cycle() before this cycle's edge
};

// frame_check's ports for BlockBench.
struct FrameCheckPorts {
  using Stim = VideoCycle;

  void drive(Vframe_check& d, const VideoCycle& c) {
    drive_s_axis_video(d, c.beat);
    d.cfg_width_i = c.cfg_width;
    d.cfg_height_i = c.cfg_height;
  }
  void clock(FrameCheck& m, const VideoCycle& c) { m.clock(c.beat, c.cfg_width, c.cfg_height); }
  bool compare(Cosim<Vframe_check>& sim, const FrameCheck& m) {
    const Vframe_check& d = sim.dut();
    const stream::PixelBeat& p = m.m_pix();
    const stream::FrameErrorCounters& k = m.counters();
    bool ok = sim.check("s_axis_video_tready_o", d.s_axis_video_tready_o, 1);
    ok = sim.check("m_pix_valid_o", d.m_pix_valid_o, p.valid) && ok;
    ok = sim.check("m_pix_grey_o", d.m_pix_grey_o, p.grey) && ok;
    ok = sim.check("m_pix_x_o", d.m_pix_x_o, p.x) && ok;
    ok = sim.check("m_pix_y_o", d.m_pix_y_o, p.y) && ok;
    ok = sim.check("m_pix_sof_o", d.m_pix_sof_o, p.sof) && ok;
    ok = sim.check("m_pix_eol_o", d.m_pix_eol_o, p.eol) && ok;
    ok = sim.check("m_pix_eof_o", d.m_pix_eof_o, p.eof) && ok;
    ok = sim.check("m_pix_abort_o", d.m_pix_abort_o, p.abort) && ok;
    ok = sim.check("early_eol_o", d.early_eol_o, k.early_eol) && ok;
    ok = sim.check("late_eol_o", d.late_eol_o, k.late_eol) && ok;
    ok = sim.check("early_sof_o", d.early_sof_o, k.early_sof) && ok;
    ok = sim.check("missing_sof_o", d.missing_sof_o, k.missing_sof) && ok;
    ok = sim.check("frames_ok_o", d.frames_ok_o, k.frames_ok) && ok;
    ok = sim.check("frames_aborted_o", d.frames_aborted_o, k.frames_aborted) && ok;
    sof_pixels += (p.valid && p.sof) ? 1u : 0u;
    return ok;
  }

  uint64_t sof_pixels = 0;  // frames opened, across resets
};

using FrameCheckBench = BlockBench<Vframe_check, FrameCheck, FrameCheckPorts>;

// What goes wrong in a generated frame.
enum class Fault {
  kNone,
  kEarlyEol,      // one line shorter than the width
  kLateEol,       // one line longer than the width
  kMissingTlast,  // one line without tlast (merges into the next)
  kZeroLength,    // tlast on the first pixel of a line
  kMissingSof,    // no tuser on the first pixel
  kTruncated,     // the frame stops early: the next SOF is an early SOF
  kExtraLines,    // more lines than configured: a missing-SOF burst follows
  kStraySof,      // tuser on a pixel inside the frame
  kCfgMismatch,   // configured geometry differs from the stream's
  kFaultCount
};

struct StimulusState {
  uint16_t cfg_width = 1;
  uint16_t cfg_height = 1;
};

// A frame size: mostly small, sometimes up to 640 x 480, sometimes at the
// 2048 limit in one dimension.
void random_size(Rng& rng, int& width, int& height) {
  const int64_t pick = rng.uniform(0, 999);
  if (pick < 500) {
    width = static_cast<int>(rng.uniform(1, 8));
    height = static_cast<int>(rng.uniform(1, 8));
  } else if (pick < 960) {
    width = static_cast<int>(rng.uniform(1, 64));
    height = static_cast<int>(rng.uniform(1, 48));
  } else if (pick < 990) {
    width = static_cast<int>(rng.uniform(1, 640));
    height = static_cast<int>(rng.uniform(1, std::max<int64_t>(1, 60000 / width)));
    height = std::min(height, 480);
  } else if (pick < 996) {
    width = 2048;
    height = static_cast<int>(rng.uniform(1, 3));
  } else {
    width = static_cast<int>(rng.uniform(1, 2));
    height = 2048;
  }
}

VideoBeat gap_beat(Rng& rng) {
  VideoBeat b;
  if (rng.chance(0.5)) {  // garbage on the idle bus must be ignored
    b.tdata = rng.byte();
    b.tuser = rng.chance(0.3);
    b.tlast = rng.chance(0.3);
  }
  return b;
}

// Appends one frame of width x height (pixels from img if given, else random)
// with tvalid gaps of probability gap_prob, the given fault and, with
// probability reset_prob, one reset cycle at a random cycle of the frame.
void append_frame(std::vector<VideoCycle>& out, Rng& rng, StimulusState& st, int width, int height,
                  const cv::Mat* img, double gap_prob, Fault fault, double reset_prob) {
  const size_t first = out.size();
  int lines = height;
  if (fault == Fault::kExtraLines) {
    lines += static_cast<int>(rng.uniform(1, 3));
  }
  const int total = width * lines;
  const int fault_line = static_cast<int>(rng.uniform(0, lines - 1));
  const int cut_at = (fault == Fault::kTruncated && total > 1)
                         ? static_cast<int>(rng.uniform(1, total - 1))
                         : total;
  const int stray_at = static_cast<int>(rng.uniform(1, std::max(1, total - 1)));

  uint16_t frame_cfg_w = static_cast<uint16_t>(width);
  uint16_t frame_cfg_h = static_cast<uint16_t>(height);
  if (fault == Fault::kCfgMismatch) {
    frame_cfg_w = rng.uniform_as<uint16_t>(0, rng.chance(0.2) ? 4095 : width + 2);
    frame_cfg_h = rng.uniform_as<uint16_t>(0, rng.chance(0.2) ? 4095 : height + 2);
  }

  int sent = 0;
  for (int y = 0; y < lines && sent < cut_at; ++y) {
    int len = width;
    bool tlast_at_end = true;
    if (y == fault_line) {
      if (fault == Fault::kEarlyEol && width > 1) {
        len = static_cast<int>(rng.uniform(1, width - 1));
      } else if (fault == Fault::kLateEol) {
        len = width + static_cast<int>(rng.uniform(1, 4));
      } else if (fault == Fault::kMissingTlast) {
        tlast_at_end = false;
      } else if (fault == Fault::kZeroLength) {
        len = 1;
      }
    }
    for (int x = 0; x < len && sent < cut_at; ++x, ++sent) {
      while (gap_prob > 0.0 && rng.chance(gap_prob)) {
        out.push_back({gap_beat(rng), st.cfg_width, st.cfg_height, false});
      }
      VideoCycle c;
      const bool first_pixel = x == 0 && y == 0;
      if (first_pixel) {
        st.cfg_width = frame_cfg_w;
        st.cfg_height = frame_cfg_h;
      } else if (rng.chance(0.002)) {
        // The shadow configuration may change at any time; only SOF samples it.
        st.cfg_width = rng.uniform_as<uint16_t>(0, 4095);
        st.cfg_height = rng.uniform_as<uint16_t>(0, 4095);
      }
      c.cfg_width = st.cfg_width;
      c.cfg_height = st.cfg_height;
      const int ix = std::min(x, width - 1);
      const int iy = std::min(y, height - 1);
      c.beat.tdata = img != nullptr ? img->at<uchar>(iy, ix) : rng.byte();
      c.beat.tvalid = true;
      c.beat.tuser = (first_pixel && fault != Fault::kMissingSof) ||
                     (fault == Fault::kStraySof && sent == stray_at);
      c.beat.tlast = x == len - 1 && tlast_at_end;
      out.push_back(c);
    }
  }
  if (rng.chance(reset_prob) && out.size() > first) {
    const auto at = static_cast<size_t>(
        rng.uniform(static_cast<int64_t>(first), static_cast<int64_t>(out.size() - 1)));
    out[at].reset_before = true;
  }
}

void append_blanking(std::vector<VideoCycle>& out, Rng& rng, const StimulusState& st) {
  const int64_t pick = rng.uniform(0, 9);
  const int64_t gaps = pick < 4 ? 0 : (pick < 8 ? rng.uniform(1, 4) : rng.uniform(5, 200));
  for (int64_t i = 0; i < gaps; ++i) {
    out.push_back({gap_beat(rng), st.cfg_width, st.cfg_height, false});
  }
}

double random_gap_prob(Rng& rng) {
  static constexpr double kGapProbs[] = {0.0, 0.0, 0.02, 0.2, 0.6};
  return kGapProbs[rng.index(5)];
}

// Random frames; fault_prob of them malformed. Runs until cycle_budget.
void run_random(FrameCheckBench& bench, Rng& rng, uint64_t cycle_budget, double fault_prob,
                double reset_prob) {
  StimulusState st;
  std::vector<VideoCycle> cycles;
  while (bench.sim().cycle() < cycle_budget && !bench.sim().failed()) {
    cycles.clear();
    int width = 1;
    int height = 1;
    random_size(rng, width, height);
    Fault fault = Fault::kNone;
    if (rng.chance(fault_prob)) {
      fault = static_cast<Fault>(rng.uniform(1, static_cast<int>(Fault::kFaultCount) - 1));
    }
    append_frame(cycles, rng, st, width, height, nullptr, random_gap_prob(rng), fault, reset_prob);
    append_blanking(cycles, rng, st);
    bench.run(cycles);
  }
}

TEST(CosimFrameCheck, WellFormedFramesWithGapsAndZeroBlanking) {
  const uint64_t seed = cosim_seed(0xF00D0001);
  Rng rng(seed);
  FrameCheckBench bench("frame_check_well_formed", seed);
  run_random(bench, rng, cosim_count(1'000'000), 0.0, 0.0);
  bench.sim().report();
  // The stimulus was well formed: no error may have been counted.
  EXPECT_EQ(bench.model().counters().early_eol, 0u);
  EXPECT_EQ(bench.model().counters().missing_sof, 0u);
  EXPECT_GT(bench.model().counters().frames_ok, 300u);
}

TEST(CosimFrameCheck, MalformedStreamsAndResets) {
  const uint64_t seed = cosim_seed(0xF00D0002);
  Rng rng(seed);
  FrameCheckBench bench("frame_check_malformed", seed);
  run_random(bench, rng, cosim_count(1'000'000), 0.5, 0.03);
  bench.sim().report();
  // Counters restart at every reset; frames must still have gone through.
  EXPECT_GT(bench.ports().sof_pixels, 300u);
}

TEST(CosimFrameCheck, EveryFaultClassIsHit) {
  // One frame per fault class, each after a clean frame, no resets: each class
  // must move its own counter in both models (the comparison is per cycle).
  const uint64_t seed = cosim_seed(0xF00D0003);
  Rng rng(seed);
  FrameCheckBench bench("frame_check_fault_classes", seed);
  StimulusState st;
  std::vector<VideoCycle> cycles;
  for (int f = 0; f < static_cast<int>(Fault::kFaultCount); ++f) {
    append_frame(cycles, rng, st, 12, 5, nullptr, 0.1, Fault::kNone, 0.0);
    append_frame(cycles, rng, st, 12, 5, nullptr, 0.1, static_cast<Fault>(f), 0.0);
  }
  append_frame(cycles, rng, st, 12, 5, nullptr, 0.0, Fault::kNone, 0.0);
  bench.run(cycles);
  bench.sim().report();
  const stream::FrameErrorCounters& k = bench.model().counters();
  EXPECT_GT(k.early_eol, 0u);
  EXPECT_GT(k.late_eol, 0u);
  EXPECT_GT(k.early_sof, 0u);
  EXPECT_GT(k.missing_sof, 0u);
  EXPECT_GT(k.frames_aborted, 0u);
}

TEST(CosimFrameCheck, PhotosBackToBack) {
  const uint64_t seed = cosim_seed(0xF00D0004);
  Rng rng(seed);
  FrameCheckBench bench("frame_check_photos", seed);
  StimulusState st;
  int photos = 0;
  for (const char* name : {"building.jpg", "fruits.jpg"}) {
    const auto img = stream::test::load_photo(name, 320, 240);
    if (!img) {
      continue;
    }
    ++photos;
    std::vector<VideoCycle> cycles;
    // Zero blanking, then with gaps, then a truncated copy followed by a clean one.
    append_frame(cycles, rng, st, img->cols, img->rows, &*img, 0.0, Fault::kNone, 0.0);
    append_frame(cycles, rng, st, img->cols, img->rows, &*img, 0.1, Fault::kNone, 0.0);
    append_frame(cycles, rng, st, img->cols, img->rows, &*img, 0.0, Fault::kTruncated, 0.0);
    append_frame(cycles, rng, st, img->cols, img->rows, &*img, 0.0, Fault::kNone, 0.0);
    append_blanking(cycles, rng, st);
    bench.run(cycles);
  }
  ASSERT_GT(photos, 0) << "no photo found under /usr/share/doc/opencv-doc/examples/data/";
  bench.sim().report();
  EXPECT_EQ(bench.model().counters().frames_ok, static_cast<uint32_t>(3 * photos));
}

}  // namespace
}  // namespace ceilnav::testbench
