// Co-simulation: rtl_model/histogram.sv against stream::Histogram, every
// output port on every clock: random frames whose pixels hit the same bin
// back to back (the RMW forwarding), gaps, zero blanking, 1x1 frames, aborts
// and early SOFs, source changes at any time, random reads and full read
// sweeps overlapping the next frame, resets, and real photos.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "stream/beat.hpp"
#include "stream/histogram.hpp"
#include "stream/tests/video_source.hpp"
#include "testbench/block_bench.hpp"
#include "testbench/ports.hpp"
#include "testbench/video_stream.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "Vhistogram.h"
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::testbench {
namespace {

using stream::Histogram;
using stream::LutBeat;
using stream::PixelBeat;

struct HistCycle {
  LutBeat in;
  bool source_remap = false;
  bool keep = true;  // with an EOF: the pipeline publishes the frame
  bool rd_en = false;
  uint8_t rd_bin = 0;
  bool reset_before = false;  // reset_cycle() before this cycle's edge
};

// histogram's ports for BlockBench.
struct HistogramPorts {
  using Stim = HistCycle;

  void drive(Vhistogram& d, const HistCycle& c) {
    drive_s_lut(d, c.in);
    d.source_remap_i = c.source_remap;
    d.keep_i = c.keep;
    d.hist_rd_en_i = c.rd_en;
    d.hist_rd_bin_i = c.rd_bin;
  }
  // count_ok_o is Mealy: compared with the inputs applied, before the edge.
  void before_edge(Cosim<Vhistogram>& sim, const Histogram& m, const HistCycle& c) {
    sim.dut().eval();
    sim.check("count_ok_o", sim.dut().count_ok_o, m.counts(c.in));
  }
  void clock(Histogram& m, const HistCycle& c) {
    m.clock(c.in, c.source_remap, c.keep, c.rd_en, c.rd_bin);
  }
  bool compare(Cosim<Vhistogram>& sim, const Histogram& m) {
    const Vhistogram& d = sim.dut();
    bool ok = sim.check("done_o", d.done_o, m.done());
    ok = sim.check("hist_rd_data_o", d.hist_rd_data_o, m.hist_rd_data()) && ok;
    return ok;
  }
};

using HistogramBench = BlockBench<Vhistogram, Histogram, HistogramPorts>;

// How the pixel values of a frame are drawn.
enum class Values { kUniform, kFewBins, kConstant, kRuns, kCount };

struct FrameValues {
  std::vector<uint8_t> grey;
  std::vector<uint8_t> remap;
};

FrameValues random_values(Rng& rng, size_t pixels) {
  FrameValues v;
  v.grey.resize(pixels);
  v.remap.resize(pixels);
  const auto kind = static_cast<Values>(rng.uniform(0, static_cast<int>(Values::kCount) - 1));
  const uint8_t base = rng.byte();
  uint8_t run_value = base;
  std::array<uint8_t, 256> table{};
  for (uint8_t& t : table) {
    t = rng.chance(0.5) ? rng.uniform_as<uint8_t>(0, 3) : rng.byte();
  }
  for (size_t i = 0; i < pixels; ++i) {
    switch (kind) {
      case Values::kUniform:
        v.grey[i] = rng.byte();
        break;
      case Values::kFewBins:
        v.grey[i] = static_cast<uint8_t>(base + rng.uniform(0, 2));
        break;
      case Values::kConstant:
        v.grey[i] = base;
        break;
      default:
        if (rng.chance(0.2)) {
          run_value = rng.byte();
        }
        v.grey[i] = run_value;
        break;
    }
    v.remap[i] = table[v.grey[i]];
  }
  return v;
}

LutBeat idle_beat(Rng& rng) {
  LutBeat b;
  if (rng.chance(0.5)) {  // fields of an idle beat are garbage
    b.pix.grey = rng.byte();
    b.pix.x = rng.uniform_as<uint16_t>(0, 2047);
    b.pix.y = rng.uniform_as<uint16_t>(0, 2047);
    b.pix.sof = rng.chance(0.2);
    b.pix.eol = rng.chance(0.2);
    b.pix.eof = rng.chance(0.2);
    b.remap = rng.byte();
    b.mask = rng.chance(0.5);
  }
  return b;
}

struct StimulusState {
  bool source_remap = false;
};

HistCycle make_cycle(Rng& rng, StimulusState& st, const LutBeat& in, double read_prob,
                     double source_flip_prob) {
  if (rng.chance(source_flip_prob)) {
    st.source_remap = !st.source_remap;
  }
  HistCycle c;
  c.in = in;
  c.source_remap = st.source_remap;
  c.keep = !rng.chance(0.1);  // the pipeline drops one frame in ten
  c.rd_en = rng.chance(read_prob);
  c.rd_bin = rng.byte();
  return c;
}

// Appends one frame. abort_mode: 0 none, 1 abort beat (valid 0) mid-frame,
// 2 the frame is cut short and the next frame's SOF carries the abort.
void append_frame(std::vector<HistCycle>& out, Rng& rng, StimulusState& st, int width, int height,
                  const FrameValues& v, double gap_prob, int abort_mode, bool sof_carries_abort,
                  double read_prob) {
  const int64_t total = int64_t{width} * height;
  const int64_t cut = abort_mode == 0 ? total : rng.uniform(0, total - 1);
  int64_t i = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x, ++i) {
      while (gap_prob > 0.0 && rng.chance(gap_prob)) {
        out.push_back(make_cycle(rng, st, idle_beat(rng), read_prob, 0.01));
      }
      if (i == cut) {
        if (abort_mode == 1) {
          LutBeat a;
          a.pix.abort = true;
          out.push_back(make_cycle(rng, st, a, read_prob, 0.01));
        }
        return;
      }
      LutBeat b;
      b.pix.valid = true;
      b.pix.grey = v.grey[static_cast<size_t>(i)];
      b.pix.x = static_cast<uint16_t>(x);
      b.pix.y = static_cast<uint16_t>(y);
      b.pix.sof = i == 0;
      b.pix.eol = x == width - 1;
      b.pix.eof = b.pix.eol && y == height - 1;
      b.pix.abort = b.pix.sof && sof_carries_abort;
      b.remap = v.remap[static_cast<size_t>(i)];
      b.mask = rng.chance(0.5);
      // The source select may move on any cycle; only the SOF samples it.
      out.push_back(make_cycle(rng, st, b, read_prob, b.pix.sof ? 0.5 : 0.01));
    }
  }
}

void random_size(Rng& rng, int& width, int& height) {
  const int64_t pick = rng.uniform(0, 19);
  if (pick < 4) {
    width = 1;
    height = 1;
  } else {
    pixel_frame_size(rng, pick, 12, 19, width, height);
  }
}

TEST(CosimHistogram, RandomFramesAbortsReadsAndResets) {
  const uint64_t seed = cosim_seed(0x41570001);
  Rng rng(seed);
  HistogramBench bench("histogram_random", seed);
  StimulusState st;
  const uint64_t budget = cosim_count(1'500'000);
  uint64_t dones = 0;
  bool next_sof_aborts = false;
  std::vector<HistCycle> cycles;
  while (bench.sim().cycle() < budget && !bench.sim().failed()) {
    cycles.clear();
    int width = 1;
    int height = 1;
    random_size(rng, width, height);
    const FrameValues v =
        random_values(rng, static_cast<size_t>(width) * static_cast<size_t>(height));
    const int64_t abort_pick = rng.uniform(0, 19);
    const int abort_mode = abort_pick == 0 ? 1 : (abort_pick == 1 ? 2 : 0);
    const double read_prob = std::array{0.0, 0.1, 0.9}[rng.index(3)];
    append_frame(cycles, rng, st, width, height, v, std::array{0.0, 0.05, 0.5}[rng.index(3)],
                 abort_mode, next_sof_aborts, read_prob);
    next_sof_aborts = abort_mode == 2;
    // Blanking: mostly none; sometimes a full read sweep, a stray pixel with no
    // frame open, or a long gap.
    const int64_t blank = rng.uniform(0, 9);
    if (blank < 5) {
      // zero blanking
    } else if (blank < 7) {
      for (int b = 0; b < 256; ++b) {
        HistCycle c = make_cycle(rng, st, idle_beat(rng), 0.0, 0.0);
        c.rd_en = true;
        c.rd_bin = static_cast<uint8_t>(b);
        cycles.push_back(c);
      }
    } else if (blank < 8) {
      LutBeat stray;
      stray.pix.valid = true;
      stray.pix.grey = rng.byte();
      stray.pix.eof = rng.chance(0.5);
      cycles.push_back(make_cycle(rng, st, stray, read_prob, 0.0));
    } else {
      const int64_t gaps = rng.uniform(1, 100);
      for (int64_t g = 0; g < gaps; ++g) {
        cycles.push_back(make_cycle(rng, st, idle_beat(rng), read_prob, 0.05));
      }
    }
    if (!cycles.empty() && rng.chance(0.02)) {
      cycles[rng.index(cycles.size())].reset_before = true;
    }
    for (const HistCycle& c : cycles) {
      if (bench.sim().failed()) {
        break;
      }
      bench.step(c);
      dones += bench.model().done() ? 1u : 0u;
    }
  }
  bench.sim().report();
  EXPECT_GT(dones, 300u);
}

// Photos, both sources, zero blanking and gaps. Besides RTL == C++, the bins
// the RTL read port returns are checked against a plain count of the frame.
TEST(CosimHistogram, PhotosReadBackThroughThePort) {
  const uint64_t seed = cosim_seed(0x41570002);
  Rng rng(seed);
  HistogramBench bench("histogram_photos", seed);
  int photos = 0;
  for (const char* name : {"building.jpg", "fruits.jpg"}) {
    const auto img = stream::test::load_photo(name, 240, 180);
    if (!img) {
      continue;
    }
    ++photos;
    FrameValues v;
    for (int y = 0; y < img->rows; ++y) {
      for (int x = 0; x < img->cols; ++x) {
        const uint8_t g = img->at<uchar>(y, x);
        v.grey.push_back(g);
        v.remap.push_back(static_cast<uint8_t>(255 - g / 2));  // a remap unlike grey
      }
    }
    for (const bool remap : {false, true}) {
      std::array<uint32_t, 256> expected{};
      for (size_t i = 0; i < v.grey.size(); ++i) {
        ++expected[remap ? v.remap[i] : v.grey[i]];
      }
      StimulusState st{remap};
      std::vector<HistCycle> cycles;
      append_frame(cycles, rng, st, img->cols, img->rows, v, remap ? 0.1 : 0.0, 0, false, 0.0);
      for (HistCycle& c : cycles) {
        c.source_remap = remap;
      }
      for (const HistCycle& c : cycles) {
        bench.step(c);
      }
      // done rises on the first idle cycle; then a sweep of all bins.
      std::vector<HistCycle> sweep(258);
      for (int b = 0; b < 256; ++b) {
        sweep[static_cast<size_t>(b) + 2].rd_en = true;
        sweep[static_cast<size_t>(b) + 2].rd_bin = static_cast<uint8_t>(b);
      }
      for (size_t i = 0; i < sweep.size() && !bench.sim().failed(); ++i) {
        bench.step(sweep[i]);
        if (i >= 2) {
          const auto bin = static_cast<size_t>(i - 2);
          if (bench.sim().dut().hist_rd_data_o != expected[bin]) {
            bench.sim().fail("bin " + std::to_string(bin) + " read through the RTL port is " +
                             std::to_string(bench.sim().dut().hist_rd_data_o) + ", counted " +
                             std::to_string(expected[bin]));
          }
        }
      }
    }
  }
  ASSERT_GT(photos, 0) << "no photo found under /usr/share/doc/opencv-doc/examples/data/";
  bench.sim().report();
}

}  // namespace
}  // namespace ceilnav::testbench
