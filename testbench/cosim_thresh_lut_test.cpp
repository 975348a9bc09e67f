// Co-simulation: rtl_model/thresh_lut.sv against stream::ThreshLut, every
// output port on every clock, with random pixel streams and gaps, LUT writes
// at random times (also mid-frame and on the commit edge), frame starts with
// zero blanking, resets, and real photos.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/pipeline_config.hpp"
#include "stream/beat.hpp"
#include "stream/tests/video_source.hpp"
#include "stream/thresh_lut.hpp"
#include "testbench/block_bench.hpp"
#include "testbench/video_stream.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "Vthresh_lut.h"
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::testbench {
namespace {

using stream::LutEntry;
using stream::LutWrite;
using stream::PixelBeat;
using stream::ThreshLut;
using Table = std::array<LutEntry, 256>;

struct LutCycle {
  PixelBeat pix;
  bool frame_start = false;
  LutWrite wr;
  bool reset_before = false;  // reset_cycle() before this cycle's edge
};

// thresh_lut's ports for BlockBench.
struct ThreshLutPorts {
  using Stim = LutCycle;

  void drive(Vthresh_lut& d, const LutCycle& c) {
    d.s_pix_valid_i = c.pix.valid;
    d.s_pix_grey_i = c.pix.grey;
    d.s_pix_x_i = c.pix.x;
    d.s_pix_y_i = c.pix.y;
    d.s_pix_sof_i = c.pix.sof;
    d.s_pix_eol_i = c.pix.eol;
    d.s_pix_eof_i = c.pix.eof;
    d.s_pix_abort_i = c.pix.abort;
    d.frame_start_i = c.frame_start;
    d.lut_wr_en_i = c.wr.en;
    d.lut_wr_index_i = c.wr.index;
    d.lut_wr_data_i = c.wr.data & 0x7FFu;  // the port is 11 bits wide
  }
  void clock(ThreshLut& m, const LutCycle& c) { m.clock(c.pix, c.frame_start, c.wr); }
  bool compare(Cosim<Vthresh_lut>& sim, const ThreshLut& m) {
    const Vthresh_lut& d = sim.dut();
    const stream::LutBeat& o = m.m_lut();
    bool ok = sim.check("m_lut_valid_o", d.m_lut_valid_o, o.pix.valid);
    ok = sim.check("m_lut_grey_o", d.m_lut_grey_o, o.pix.grey) && ok;
    ok = sim.check("m_lut_x_o", d.m_lut_x_o, o.pix.x) && ok;
    ok = sim.check("m_lut_y_o", d.m_lut_y_o, o.pix.y) && ok;
    ok = sim.check("m_lut_sof_o", d.m_lut_sof_o, o.pix.sof) && ok;
    ok = sim.check("m_lut_eol_o", d.m_lut_eol_o, o.pix.eol) && ok;
    ok = sim.check("m_lut_eof_o", d.m_lut_eof_o, o.pix.eof) && ok;
    ok = sim.check("m_lut_abort_o", d.m_lut_abort_o, o.pix.abort) && ok;
    ok = sim.check("m_lut_remap_o", d.m_lut_remap_o, o.remap) && ok;
    ok = sim.check("m_lut_mask_o", d.m_lut_mask_o, o.mask) && ok;
    ok = sim.check("m_lut_class_o", d.m_lut_class_o, o.cls) && ok;
    return ok;
  }
};

using ThreshLutBench = BlockBench<Vthresh_lut, ThreshLut, ThreshLutPorts>;

Table random_table(Rng& rng) {
  Table t{};
  for (LutEntry& e : t) {
    e = rng.uniform_as<LutEntry>(0, 0x7FF);
  }
  return t;
}

// An idle beat; its fields are garbage half the time (they are delayed as is).
PixelBeat idle_beat(Rng& rng) {
  PixelBeat p;
  if (rng.chance(0.5)) {
    p.grey = rng.byte();
    p.x = rng.uniform_as<uint16_t>(0, 2047);
    p.y = rng.uniform_as<uint16_t>(0, 2047);
    p.sof = rng.chance(0.2);
    p.eol = rng.chance(0.2);
    p.eof = rng.chance(0.2);
    p.abort = rng.chance(0.1);
  }
  return p;
}

// Both banks hold defined contents (the RTL's BRAM powers up random): write a
// table, commit it with a lone frame_start, write the other bank.
void initialise_banks(ThreshLutBench& bench, Rng& rng) {
  for (int bank = 0; bank < 2; ++bank) {
    const Table t = random_table(rng);
    for (unsigned g = 0; g < 256; ++g) {
      LutCycle c;
      c.wr = {true, static_cast<uint8_t>(g), t[g]};
      bench.step(c);
    }
    LutCycle commit;
    commit.frame_start = bank == 0;
    bench.step(commit);
  }
}

// Appends a frame of pixel beats. frame_start is raised on the cycle before
// the SOF pixel (frame_check samples the SOF there), which is the previous
// frame's last cycle with zero blanking.
void append_frame(std::vector<LutCycle>& out, Rng& rng, int width, int height, const cv::Mat* img,
                  double gap_prob) {
  if (out.empty()) {
    out.push_back({idle_beat(rng), false, {}, false});
  }
  out.back().frame_start = true;
  const bool aborted = rng.chance(0.1);
  const int64_t abort_at = rng.uniform(0, int64_t{width} * height);
  int64_t sent = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x, ++sent) {
      while (gap_prob > 0.0 && rng.chance(gap_prob)) {
        out.push_back({idle_beat(rng), false, {}, false});
      }
      if (aborted && sent == abort_at) {
        PixelBeat a;
        a.abort = true;
        out.push_back({a, false, {}, false});
        return;
      }
      PixelBeat p;
      p.valid = true;
      p.grey = img != nullptr ? img->at<uchar>(y, x) : rng.byte();
      p.x = static_cast<uint16_t>(x);
      p.y = static_cast<uint16_t>(y);
      p.sof = x == 0 && y == 0;
      p.eol = x == width - 1;
      p.eof = p.eol && y == height - 1;
      out.push_back({p, false, {}, false});
    }
  }
}

// Sprinkles host writes over cycles [from, end): a full table, a few single
// entries, or nothing; sometimes one write lands on a frame_start cycle.
void add_writes(std::vector<LutCycle>& cycles, size_t from, Rng& rng) {
  if (cycles.size() <= from) {
    return;
  }
  const auto pick_cycle = [&] {
    return static_cast<size_t>(
        rng.uniform(static_cast<int64_t>(from), static_cast<int64_t>(cycles.size() - 1)));
  };
  const int64_t mode = rng.uniform(0, 9);
  int writes = 0;
  if (mode < 3) {
    writes = 0;
  } else if (mode < 7) {
    writes = static_cast<int>(rng.uniform(1, 8));
  } else {
    writes = 256;
  }
  for (int i = 0; i < writes; ++i) {
    LutCycle& c = cycles[pick_cycle()];
    c.wr = {true, rng.byte(), rng.uniform_as<LutEntry>(0, 0xFFFF)};  // bits 15:9 ignored
  }
  if (rng.chance(0.3)) {
    for (size_t i = from; i < cycles.size(); ++i) {
      if (cycles[i].frame_start) {
        cycles[i].wr = {true, rng.byte(), rng.uniform_as<LutEntry>(0, 0x7FF)};
        break;
      }
    }
  }
}

void random_size(Rng& rng, int& width, int& height) {
  pixel_frame_size(rng, rng.uniform(0, 9), 5, 9, width, height);
}

TEST(CosimThreshLut, RandomStreamsWritesAndCommits) {
  const uint64_t seed = cosim_seed(0x1A7E0001);
  Rng rng(seed);
  ThreshLutBench bench("thresh_lut_random", seed);
  initialise_banks(bench, rng);
  const uint64_t budget = cosim_count(1'000'000);
  std::vector<LutCycle> cycles;
  int commits = 0;
  while (bench.sim().cycle() < budget && !bench.sim().failed()) {
    int width = 1;
    int height = 1;
    random_size(rng, width, height);
    append_frame(cycles, rng, width, height, nullptr, std::array{0.0, 0.05, 0.5}[rng.index(3)]);
    const int64_t blank = rng.chance(0.5) ? 0 : rng.uniform(1, 50);
    for (int64_t i = 0; i < blank; ++i) {
      cycles.push_back({idle_beat(rng), rng.chance(0.01), {}, false});
    }
    add_writes(cycles, 1, rng);
    if (cycles.size() > 1 && rng.chance(0.02)) {
      cycles[1 + rng.index(cycles.size() - 1)].reset_before = true;
    }
    // The last cycle is kept: the next frame's frame_start may land on it
    // (zero blanking).
    const LutCycle last = cycles.back();
    cycles.pop_back();
    for (const LutCycle& c : cycles) {
      if (bench.sim().failed()) {
        break;
      }
      commits += (c.frame_start && (bench.model().commit_pending() || c.wr.en)) ? 1 : 0;
      bench.step(c);
    }
    cycles.assign(1, last);
  }
  bench.sim().report();
  EXPECT_GT(commits, 10);
}

TEST(CosimThreshLut, PhotosWithGammaAndThresholdTables) {
  const uint64_t seed = cosim_seed(0x1A7E0002);
  Rng rng(seed);
  ThreshLutBench bench("thresh_lut_photos", seed);
  initialise_banks(bench, rng);
  int photos = 0;
  for (const char* name : {"building.jpg", "baboon.jpg"}) {
    const auto img = stream::test::load_photo(name, 320, 240);
    if (!img) {
      continue;
    }
    ++photos;
    for (int variant = 0; variant < 2; ++variant) {
      // Write a full table during the previous frame's tail; it commits at this SOF.
      Table table{};
      for (unsigned g = 0; g < 256; ++g) {
        const double gamma = variant == 0 ? 0.5 : 2.2;
        const auto remap = static_cast<uint8_t>(std::lround(255.0 * std::pow(g / 255.0, gamma)));
        table[g] = stream::lut_entry(remap, g >= (variant == 0 ? 128u : 200u),
                                     static_cast<uint8_t>(g * 4 / 256));
      }
      std::vector<LutCycle> cycles;
      for (unsigned g = 0; g < 256; ++g) {
        cycles.push_back({idle_beat(rng), false, {true, static_cast<uint8_t>(g), table[g]}, false});
      }
      const size_t frame_begin = cycles.size();
      append_frame(cycles, rng, img->cols, img->rows, &*img, variant == 0 ? 0.0 : 0.1);
      // Independent check of the committed table: remap/mask == table[grey].
      for (size_t i = 0; i < cycles.size() && !bench.sim().failed(); ++i) {
        bench.step(cycles[i]);
        const Vthresh_lut& d = bench.sim().dut();
        if (i > frame_begin && d.m_lut_valid_o &&
            (d.m_lut_remap_o != (table[d.m_lut_grey_o] & 0xFF) ||
             d.m_lut_mask_o != ((table[d.m_lut_grey_o] >> 8) & 1) ||
             d.m_lut_class_o != stream::lut_class(table[d.m_lut_grey_o]))) {
          bench.sim().fail("RTL lookup differs from the written table");
        }
      }
    }
  }
  ASSERT_GT(photos, 0) << "no photo found under /usr/share/doc/opencv-doc/examples/data/";
  bench.sim().report();
}

}  // namespace
}  // namespace ceilnav::testbench
