// Co-simulation of rtl_model/ceilnav_top.sv (Vceilnav_top, library
// ceilnav_rtl_top) against stream::CeilnavTop: the same video, AXI4-Lite and
// m_axis_runs_tready stimulus into both on every cycle, and every output port
// compared after every edge. See docs/cosim.md.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <vector>

#include "ceilnav/regs.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/config.hpp"
#include "stream/run_scanner.hpp"
#include "testbench/cosim_common.hpp"
#include "testbench/top_cosim.hpp"

namespace ceilnav::testbench {
namespace {

namespace r = regs;
using stream::AxiLiteIn;
using stream::AxiLiteMaster;
using stream::VideoBeat;

// One bus transaction of the host script. `sync`: the video source waits for
// it (geometry and LUT writes that the next frame must see).
struct BusOp {
  bool write = false;
  uint32_t addr = 0;
  uint32_t data = 0;
  uint8_t strb = 0xF;
  bool sync = false;
};

// Threshold LUT: remap = grey (or a random table), mask = grey >= threshold.
std::vector<BusOp> lut_program(Rng& rng, bool sync) {
  std::vector<BusOp> ops;
  ops.push_back({true, r::lut_index::kOffset, 0, 0xF, sync});
  const bool random_remap = rng.chance(0.3);
  const auto threshold = static_cast<uint32_t>(rng.uniform(40, 220));
  for (uint32_t g = 0; g < 256; ++g) {
    const uint32_t remap = random_remap ? static_cast<uint32_t>(rng.byte()) : g;
    const uint32_t data =
        r::lut_data::kRemap.put(remap) | r::lut_data::kMask.put(g >= threshold ? 1u : 0u);
    ops.push_back({true, r::lut_data::kOffset, data, 0xF, sync});
  }
  return ops;
}

// Pixels of one frame: dark noise with bright rectangles (runs for the scanner).
std::vector<uint8_t> frame_pixels(Rng& rng, int w, int h) {
  std::vector<uint8_t> px(static_cast<size_t>(w) * static_cast<size_t>(h));
  const auto dark = static_cast<int>(rng.uniform(0, 80));
  for (auto& p : px) p = static_cast<uint8_t>(rng.uniform(0, dark));
  const auto blobs = rng.uniform(0, 6);
  for (int64_t b = 0; b < blobs; ++b) {
    const auto x0 = static_cast<int>(rng.uniform(0, w - 1));
    const auto y0 = static_cast<int>(rng.uniform(0, h - 1));
    const auto bw = static_cast<int>(rng.uniform(1, std::max(1, w / 3)));
    const auto bh = static_cast<int>(rng.uniform(1, std::max(1, h / 3)));
    const auto level = static_cast<int>(rng.uniform(120, 255));
    for (int y = y0; y < std::min(h, y0 + bh); ++y) {
      for (int x = x0; x < std::min(w, x0 + bw); ++x) {
        const int v = level - static_cast<int>(rng.uniform(0, 30));
        px[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] =
            static_cast<uint8_t>(std::max(0, v));
      }
    }
  }
  return px;
}

enum class Malform : uint8_t { kNone, kEarlyEol, kLateEol, kMissingSof, kEarlySof, kStray };

// The beats of one frame (gaps included), possibly malformed.
void frame_beats(Rng& rng, int w, int h, double gap_p, Malform m, std::deque<VideoBeat>& out) {
  const std::vector<uint8_t> px = frame_pixels(rng, w, h);
  const int64_t total = int64_t{w} * h;
  const int64_t bad_at = rng.uniform(0, total - 1);
  for (int64_t i = 0; i < total; ++i) {
    while (gap_p > 0.0 && rng.chance(gap_p)) out.push_back(VideoBeat{});
    const int x = static_cast<int>(i % w);
    VideoBeat b;
    b.tvalid = true;
    b.tdata = px[static_cast<size_t>(i)];
    b.tuser = i == 0;
    b.tlast = x == w - 1;
    if (i == bad_at) {
      if (m == Malform::kEarlyEol && !b.tlast) b.tlast = true;
      if (m == Malform::kLateEol && b.tlast) b.tlast = false;
      if (m == Malform::kEarlySof && i > 0) {
        return;  // cut: the next frame's SOF arrives inside this one
      }
    }
    if (m == Malform::kMissingSof && i == 0) b.tuser = false;
    out.push_back(b);
  }
  if (m == Malform::kStray) {  // pixels outside any frame
    const auto n = rng.uniform(1, 5);
    for (int64_t k = 0; k < n; ++k) {
      VideoBeat b;
      b.tvalid = true;
      b.tdata = rng.byte();
      b.tlast = rng.chance(0.3);
      out.push_back(b);
    }
  }
}

// What the random stimulus reached (printed; checked on full-length runs).
struct Coverage {
  uint64_t frames_published = 0;
  uint64_t malformed = 0;
  uint64_t slverr = 0;
  uint64_t hist_nonzero = 0;    // HIST_DATA reads with a non-zero bin
  uint64_t run_word_valid = 0;  // RUN_WORD0 reads with VALID = 1
  uint64_t stream_beats = 0;    // m_axis_runs transfers
  uint64_t irq_rises = 0;
  uint64_t soft_resets = 0;

  void note_response(const BusOp& op, uint32_t rdata, uint8_t resp) {
    if (resp == r::kRespSlvErr) ++slverr;
    if (op.write || resp != r::kRespOkay) return;
    const uint32_t a = op.addr & r::kAddrMask;
    if (a == r::hist_data::kOffset && rdata != 0) ++hist_nonzero;
    if (a == r::run_word0::kOffset && r::run_word0::kValid.get(rdata) != 0) ++run_word_valid;
  }
  void print() const {
    std::printf(
        "[cosim] ceilnav_top coverage: %llu frames published, %llu malformed, %llu SLVERR, "
        "%llu non-zero bins read, %llu runs in the register window, %llu stream beats, "
        "%llu irq rises, %llu soft resets\n",
        static_cast<unsigned long long>(frames_published),
        static_cast<unsigned long long>(malformed), static_cast<unsigned long long>(slverr),
        static_cast<unsigned long long>(hist_nonzero),
        static_cast<unsigned long long>(run_word_valid),
        static_cast<unsigned long long>(stream_beats), static_cast<unsigned long long>(irq_rises),
        static_cast<unsigned long long>(soft_resets));
  }
};

constexpr uint64_t kCoverageCycles = 100'000;

// The whole scenario: a host script with random register traffic next to a
// video source with random frames, until `cycles` edges have been compared.
struct Scenario {
  uint64_t cycles = 1'000'000;
  double run_sink_share = 0.25;  // chance that a CONTROL write selects RUN_SINK = 1
  bool big_frame = true;         // one 1280x960 frame (the largest geometry the issue names)
};

void run_scenario(const Scenario& sc, uint64_t seed) {
  TopCosim top(seed);
  Rng rng(seed);
  std::deque<BusOp> ops;
  std::deque<VideoBeat> video;
  int sync_pending = 0;  // sync ops queued or in flight
  bool op_in_flight = false;
  BusOp op_now;
  Coverage cov;
  bool run_sink = false;
  uint32_t control = 0;
  uint64_t frames = 0;
  uint64_t big_frame_at = sc.big_frame ? static_cast<uint64_t>(rng.uniform(5, 40)) : ~0ull;
  double tready_p = 1.0;

  const auto push = [&](const BusOp& op) {
    ops.push_back(op);
    if (op.sync) ++sync_pending;
  };
  const auto push_all = [&](const std::vector<BusOp>& v) {
    for (const BusOp& op : v) push(op);
  };

  // Start-up: interrupts on, LUT programmed, video enabled; a first 1x1 frame
  // swaps the LUT in, then the other bank is programmed too (the BRAM starts
  // random in the RTL: both banks must hold a known table).
  push({true, r::intr_enable::kOffset, 0x7, 0xF, true});
  push_all(lut_program(rng, true));
  push({true, r::width::kOffset, 1, 0xF, true});
  push({true, r::height::kOffset, 1, 0xF, true});
  control = r::control::kEnable.mask();
  push({true, r::control::kOffset, control, 0xF, true});
  bool primed = false;
  bool planned = false;  // the next frame's geometry writes are queued
  int plan_w = 1;
  int plan_h = 1;

  while (top.sim().cycle() < sc.cycles) {
    // ---- Host script.
    AxiLiteMaster& m = top.master();
    if (op_in_flight && m.idle()) {
      op_in_flight = false;
      if (op_now.sync) --sync_pending;
      cov.note_response(op_now, m.rdata(), m.resp());
    }
    if (ops.empty() && primed) {
      // Random traffic.
      const auto pick = rng.uniform(0, 99);
      if (pick < 30) {
        // A read anywhere: mapped, unmapped or misaligned.
        uint32_t addr = 0;
        if (rng.chance(0.7)) {
          addr = r::kRegisters[rng.index(r::kRegisters.size())].offset;
        } else {
          addr = static_cast<uint32_t>(rng.uniform(0, 0x3FF));
        }
        if (rng.chance(0.05)) addr |= static_cast<uint32_t>(rng.uniform(1, 0xFFFFF)) << 10;
        push({false, addr, 0, 0xF, false});
      } else if (pick < 42) {
        // Histogram: index, then a burst of HIST_DATA reads.
        push({true, r::hist_index::kOffset, static_cast<uint32_t>(rng.byte()), 0xF, false});
        const auto n = rng.uniform(1, 12);
        for (int64_t k = 0; k < n; ++k) push({false, r::hist_data::kOffset, 0, 0xF, false});
      } else if (pick < 55) {
        // Run window: a few entries, WORD0..3 each (pops with RUN_SINK = 1).
        const auto n = rng.uniform(1, 6);
        for (int64_t k = 0; k < n; ++k) {
          for (uint32_t wd : {r::run_word0::kOffset, r::run_word1::kOffset, r::run_word2::kOffset,
                              r::run_word3::kOffset}) {
            push({false, wd, 0, 0xF, false});
          }
        }
      } else if (pick < 65) {
        // Run-scanner / histogram configuration, any time (mid-frame too).
        switch (rng.uniform(0, 3)) {
          case 0:
            push({true, r::background_level::kOffset, static_cast<uint32_t>(rng.uniform(0, 90)),
                  0xF, false});
            break;
          case 1:
            push({true, r::min_run_length::kOffset, static_cast<uint32_t>(rng.uniform(0, 6)), 0xF,
                  false});
            break;
          case 2:
            push({true, r::max_runs_per_row::kOffset, static_cast<uint32_t>(rng.uniform(0, 12)),
                  0xF, false});
            break;
          default:
            push({true, r::hist_source::kOffset, static_cast<uint32_t>(rng.uniform(0, 1)), 0xF,
                  false});
            break;
        }
      } else if (pick < 72) {
        // Interrupts: W1C, enable, test.
        const auto bits = static_cast<uint32_t>(rng.uniform(0, 7));
        switch (rng.uniform(0, 2)) {
          case 0:
            push({true, r::intr_state::kOffset, bits, 0xF, false});
            break;
          case 1:
            push({true, r::intr_enable::kOffset, bits | (rng.chance(0.8) ? 1u : 0u), 0xF, false});
            break;
          default:
            push({true, r::intr_test::kOffset, bits, 0xF, false});
            break;
        }
      } else if (pick < 76) {
        // Bus errors: partial strobes, read-only and unmapped writes.
        const uint32_t addr = rng.chance(0.5)
                                  ? r::kRegisters[rng.index(r::kRegisters.size())].offset
                                  : static_cast<uint32_t>(rng.uniform(0, 0x3FF));
        const auto strb = static_cast<uint8_t>(rng.chance(0.5) ? rng.uniform(0, 14) : 0xF);
        const bool harmful = addr == r::control::kOffset || addr == r::width::kOffset ||
                             addr == r::height::kOffset || addr == r::lut_data::kOffset ||
                             addr == r::lut_index::kOffset;
        if (!harmful || strb != 0xF) {
          push({true, addr, static_cast<uint32_t>(rng.engine()()), strb, false});
        }
      } else if (pick < 79) {
        push_all(lut_program(rng, rng.chance(0.7)));
      } else if (pick < 83) {
        // CONTROL: run sink, enable, rarely a soft reset.
        run_sink = rng.chance(sc.run_sink_share);
        const bool enable = rng.chance(0.92);
        control = r::control::kEnable.put(enable ? 1u : 0u) |
                  r::control::kRunSink.put(run_sink ? 1u : 0u);
        const bool soft = rng.chance(0.03);
        push({true, r::control::kOffset, control | r::control::kSoftReset.put(soft ? 1u : 0u), 0xF,
              false});
      } else {
        // Idle bus for a while: a read of ID later.
        if (rng.chance(0.2)) push({false, r::id::kOffset, 0, 0xF, false});
      }
    }
    if (!op_in_flight && !ops.empty() && m.idle()) {
      const BusOp op = ops.front();
      ops.pop_front();
      if (op.write) {
        m.start_write(op.addr, op.data, op.strb);
      } else {
        m.start_read(op.addr);
      }
      op_in_flight = true;
      op_now = op;
      if (op.write && op.addr == r::control::kOffset && r::control::kSoftReset.get(op.data) != 0) {
        ++cov.soft_resets;
      }
    }

    // ---- Video source. The next frame's geometry is written while the
    // current one streams (active from the next SOF), and the next frame
    // starts once those writes are done: blanking down to zero cycles.
    if (!primed) {
      if (video.empty() && sync_pending == 0) {
        frame_beats(rng, 1, 1, 0.0, Malform::kNone, video);
        push_all(lut_program(rng, true));
        primed = true;
      }
    } else if (!planned && sync_pending == 0) {
      {
        int w = 1;
        int h = 1;
        const auto size = rng.uniform(0, 99);
        if (frames == big_frame_at) {
          w = 1280;
          h = 960;
          control |= r::control::kEnable.mask();  // this one must not be gated off
          push({true, r::control::kOffset, control, 0xF, true});
        } else if (size < 55) {
          w = static_cast<int>(rng.uniform(1, 8));
          h = static_cast<int>(rng.uniform(1, 6));
        } else if (size < 93) {
          w = static_cast<int>(rng.uniform(1, 64));
          h = static_cast<int>(rng.uniform(1, 48));
        } else {
          w = static_cast<int>(rng.uniform(1, 320));
          h = static_cast<int>(rng.uniform(1, 240));
        }
        // The geometry registers, written before the SOF (5 %: racing it).
        const bool race = rng.chance(0.05);
        push({true, r::width::kOffset, static_cast<uint32_t>(w), 0xF, !race});
        push({true, r::height::kOffset, static_cast<uint32_t>(h), 0xF, !race});
        plan_w = w;
        plan_h = h;
        planned = true;
      }
    }
    if (video.empty() && planned && sync_pending == 0) {
      {
        const int w = plan_w;
        const int h = plan_h;
        planned = false;
        const auto bl = rng.uniform(0, 9);
        const int64_t blanking = bl < 4 ? 0 : (bl < 8 ? rng.uniform(1, 12) : rng.uniform(13, 300));
        for (int64_t k = 0; k < blanking; ++k) video.push_back(VideoBeat{});
        const auto gp = rng.uniform(0, 3);
        const double gap_p = gp < 2 ? 0.0 : (gp == 2 ? 0.05 : 0.3);
        Malform mal = Malform::kNone;
        if (rng.chance(0.08)) {
          mal = static_cast<Malform>(rng.uniform(1, 5));
          ++cov.malformed;
        }
        frame_beats(rng, w, h, gap_p, mal, video);
        ++frames;
        tready_p = std::array<double, 4>{1.0, 1.0, 0.7, 0.15}[rng.index(4)];
      }
    }
    // Frames already queued run on; only the next frame waits for its writes.
    VideoBeat beat;
    if (!video.empty()) {
      beat = video.front();
      video.pop_front();
    }
    const bool runs_tready = rng.chance(tready_p);
    const bool irq_before = top.model().irq();
    if (top.model().m_axis_runs().tvalid && runs_tready) ++cov.stream_beats;
    if (!top.step(beat, runs_tready)) break;
    if (top.model().pipeline().frame_done()) ++cov.frames_published;
    if (!irq_before && top.model().irq()) ++cov.irq_rises;
  }
  top.sim().report();
  // The run stops at the first mismatching cycle.
  std::printf("[cosim] ceilnav_top: %llu cycles compared, %llu frames, mismatches: %d\n",
              static_cast<unsigned long long>(top.sim().cycle()),
              static_cast<unsigned long long>(frames), top.sim().failed() ? 1 : 0);
  cov.print();
  EXPECT_FALSE(top.sim().failed());
  EXPECT_GE(top.sim().cycle(), sc.cycles);
  if (sc.cycles >= kCoverageCycles) {
    // The stimulus reached what it is meant to: a silent run proves little.
    EXPECT_GT(cov.frames_published, 10u);
    EXPECT_GT(cov.malformed, 0u);
    EXPECT_GT(cov.slverr, 0u);
    EXPECT_GT(cov.hist_nonzero, 0u);
    EXPECT_GT(cov.run_word_valid, 0u);
    EXPECT_GT(cov.irq_rises, 0u);
    EXPECT_GT(cov.soft_resets, 0u);
    EXPECT_GT(cov.stream_beats + cov.run_word_valid, 100u);
  }
}

// 3e6 cycles (about 3 s in Release); CEILNAV_COSIM_CYCLES scales it.
TEST(CeilnavTopCosim, RandomTrafficEveryPortEveryCycle) {
  Scenario sc;
  sc.cycles = cosim_count(3'000'000);
  run_scenario(sc, cosim_seed(20261122));
}

// Mostly RUN_SINK = 1 (runs popped through RUN_WORD0..3, FIFO overflow) and
// small frames only.
TEST(CeilnavTopCosim, RunSinkRegistersAndOverflow) {
  Scenario sc;
  sc.cycles = cosim_count(300'000);
  sc.run_sink_share = 0.9;
  sc.big_frame = false;
  run_scenario(sc, cosim_seed(77));
}

}  // namespace
}  // namespace ceilnav::testbench
