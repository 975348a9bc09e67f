// Co-simulation of rtl_model/ceilnav_top.sv (Vceilnav_top, library
// ceilnav_rtl_top) against stream::CeilnavTop: the same video, AXI4-Lite and
// m_axis_runs_tready stimulus into both on every cycle, and every output port
// compared after every edge. See docs/cosim.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "ceilnav/regs.hpp"
#include "common/camera_config.hpp"
#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "common/pipeline_config.hpp"
#include "drivers/axi_lite_master.hpp"
#include "golden/class_moments_ref.hpp"
#include "golden/corridor/corridor.hpp"
#include "golden/corridor/render.hpp"
#include "golden/edge_ref.hpp"
#include "golden/hough_ref.hpp"
#include "golden/orientation_ref.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/hough.hpp"
#include "stream/orientation.hpp"
#include "stream/run_scanner.hpp"
#include "testbench/cosim_common.hpp"
#include "testbench/top_cosim.hpp"
#include "testbench/video_stream.hpp"

namespace ceilnav::testbench {
namespace {

namespace r = regs;
using drivers::AxiLiteMaster;
using stream::AxiLiteIn;
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

// Threshold LUT: remap = grey (or a random table), mask = grey >= threshold,
// pixel class in grey bands of random width (class_moments).
std::vector<BusOp> lut_program(Rng& rng, bool sync) {
  std::vector<BusOp> ops;
  ops.push_back({true, r::lut_index::kOffset, 0, 0xF, sync});
  const bool random_remap = rng.chance(0.3);
  const auto threshold = static_cast<uint32_t>(rng.uniform(40, 220));
  const auto band = static_cast<uint32_t>(rng.uniform(1, 80));
  for (uint32_t g = 0; g < 256; ++g) {
    const uint32_t remap = random_remap ? static_cast<uint32_t>(rng.byte()) : g;
    const uint32_t data = r::lut_data::kRemap.put(remap) |
                          r::lut_data::kMask.put(g >= threshold ? 1u : 0u) |
                          r::lut_data::kClass.put((g / band) % 4);
    ops.push_back({true, r::lut_data::kOffset, data, 0xF, sync});
  }
  return ops;
}

// Pixels of one frame: dark noise with bright rectangles (runs for the scanner).
std::vector<uint8_t> frame_pixels(Rng& rng, int w, int h) {
  return blob_pixels(rng, w, h, BlobStyle{});
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
  uint64_t class_nonzero = 0;   // CLASS_MOM_* reads with a non-zero value
  uint64_t mom_nonzero = 0;     // MOM_* reads (the result store) with a non-zero value
  uint64_t mom_held = 0;        // cycles a MOM_* read waited for the store's writes
  uint64_t stream_beats = 0;    // m_axis_runs transfers
  uint64_t irq_rises = 0;
  uint64_t soft_resets = 0;
  uint64_t hard_resets = 0;
  uint64_t hough_nonzero = 0;      // HOUGH_DATA reads with a non-zero cell
  uint64_t hough_read_voting = 0;  // HOUGH_DATA reads sampled while the next frame votes
  uint64_t hough_published = 0;    // hough done pulses
  uint64_t edge_dropped = 0;       // EDGE_DROPPED reads with a non-zero count
  uint64_t hough_stalls = 0;       // HOUGH_STALLS reads with a non-zero count
  uint64_t ori_nonzero = 0;        // ORI_DATA reads with a non-zero bin
  uint64_t ori_published = 0;      // orientation done pulses
  uint64_t ori_read_clearing = 0;  // ORI_DATA reads sampled while the block swept its bank

  static bool is_mom(uint32_t a) {
    return r::mom_grey_lo::kArray.index(a) >= 0 || r::mom_grey_hi::kArray.index(a) >= 0 ||
           r::mom_mask_lo::kArray.index(a) >= 0 || r::mom_mask_hi::kArray.index(a) >= 0;
  }
  void note_response(const BusOp& op, uint32_t rdata, uint8_t resp) {
    if (resp == r::kRespSlvErr) ++slverr;
    if (op.write || resp != r::kRespOkay) return;
    const uint32_t a = op.addr & r::kAddrMask;
    if (a == r::hist_data::kOffset && rdata != 0) ++hist_nonzero;
    if (a == r::run_word0::kOffset && r::run_word0::kValid.get(rdata) != 0) ++run_word_valid;
    if (is_mom(a) && rdata != 0) ++mom_nonzero;
    if (a == r::hough_data::kOffset && rdata != 0) ++hough_nonzero;
    if (a == r::edge_dropped::kOffset && rdata != 0) ++edge_dropped;
    if (a == r::hough_stalls::kOffset && rdata != 0) ++hough_stalls;
    if (a == r::ori_data::kOffset && rdata != 0) ++ori_nonzero;
    if ((r::class_mom_lo::kArray.index(a) >= 0 || r::class_mom_hi::kArray.index(a) >= 0) &&
        rdata != 0) {
      ++class_nonzero;
    }
  }
  void print() const {
    std::printf(
        "[cosim] ceilnav_top coverage: %llu frames published, %llu malformed, %llu SLVERR, "
        "%llu non-zero bins read, %llu runs in the register window, %llu stream beats, "
        "%llu irq rises, %llu soft resets, %llu hard resets, %llu non-zero class moment "
        "reads, %llu non-zero moment reads, %llu cycles a moment read waited\n",
        static_cast<unsigned long long>(frames_published),
        static_cast<unsigned long long>(malformed), static_cast<unsigned long long>(slverr),
        static_cast<unsigned long long>(hist_nonzero),
        static_cast<unsigned long long>(run_word_valid),
        static_cast<unsigned long long>(stream_beats), static_cast<unsigned long long>(irq_rises),
        static_cast<unsigned long long>(soft_resets), static_cast<unsigned long long>(hard_resets),
        static_cast<unsigned long long>(class_nonzero),
        static_cast<unsigned long long>(mom_nonzero), static_cast<unsigned long long>(mom_held));
    std::printf(
        "[cosim] ceilnav_top corridor coverage: %llu hough publications, %llu non-zero cells "
        "read, %llu cell reads while the next frame voted, %llu non-zero EDGE_DROPPED reads, "
        "%llu non-zero HOUGH_STALLS reads\n",
        static_cast<unsigned long long>(hough_published),
        static_cast<unsigned long long>(hough_nonzero),
        static_cast<unsigned long long>(hough_read_voting),
        static_cast<unsigned long long>(edge_dropped),
        static_cast<unsigned long long>(hough_stalls));
    if (kTopConfig.has_orientation) {
      std::printf(
          "[cosim] ceilnav_top orientation coverage: %llu publications, %llu non-zero bins "
          "read, %llu bin reads while the accumulating bank was swept\n",
          static_cast<unsigned long long>(ori_published),
          static_cast<unsigned long long>(ori_nonzero),
          static_cast<unsigned long long>(ori_read_clearing));
    }
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

// The registers the random traffic draws from (present or not): the whole
// map with the orientation block; without it the map without the ORI_*
// registers (appended last), so that the configurations older than the block
// keep the stimulus of their earlier runs (tape's ORI_* SLVERR is checked by
// AbsentClassMomentRegistersAnswerSlvErr; random unmapped offsets hit them too).
std::vector<r::Register> random_traffic_registers() {
  std::vector<r::Register> out;
  for (const r::Register& reg : r::kRegisters) {
    if (kTopConfig.has_orientation || reg.block != r::Block::kOrientation) out.push_back(reg);
  }
  return out;
}

void run_scenario(const Scenario& sc, uint64_t seed) {
  const std::vector<r::Register> traffic_registers = random_traffic_registers();
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
  bool hard_reset_pending = false;

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
  push({true, r::intr_enable::kOffset, 0xF, 0xF, true});
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
          addr = traffic_registers[rng.index(traffic_registers.size())].offset;
        } else {
          addr = static_cast<uint32_t>(rng.uniform(0, 0x3FF));
        }
        if (rng.chance(0.05)) addr |= static_cast<uint32_t>(rng.uniform(1, 0xFFFFF)) << 10;
        push({false, addr, 0, 0xF, false});
      } else if (pick < 42 && kTopConfig.has_corridor && rng.chance(0.4)) {
        // Hough accumulator: index (mostly inside the shape), then a burst
        // of HOUGH_DATA reads; or the corridor counters.
        if (rng.chance(0.25)) {
          for (uint32_t a :
               {r::edge_count::kOffset, r::edge_dropped::kOffset, r::edge_fifo_level::kOffset,
                r::hough_status::kOffset, r::hough_frame_count::kOffset, r::hough_stalls::kOffset,
                r::hough_trailer_flags::kOffset}) {
            push({false, a, 0, 0xF, false});
          }
        } else {
          // Mostly a theta row from its first rho bin (where small frames vote).
          const uint32_t index = rng.chance(0.8)   ? static_cast<uint32_t>(rng.uniform(0, 44)) << 6
                                 : rng.chance(0.8) ? static_cast<uint32_t>(rng.uniform(0, 45 * 64))
                                                   : static_cast<uint32_t>(rng.uniform(0, 0xFFFFF));
          push({true, r::hough_index::kOffset, index, 0xF, false});
          const auto n = rng.uniform(1, 48);
          for (int64_t k = 0; k < n; ++k) push({false, r::hough_data::kOffset, 0, 0xF, false});
        }
      } else if (pick < 42 && kTopConfig.has_orientation && rng.chance(0.4)) {
        // Orientation histogram: index (mostly a valid bin), then a burst of
        // ORI_DATA reads; or its counters and status.
        if (rng.chance(0.25)) {
          for (uint32_t a : {r::ori_status::kOffset, r::ori_frames::kOffset,
                             r::ori_skipped::kOffset, r::ori_votes::kOffset}) {
            push({false, a, 0, 0xF, false});
          }
        } else {
          const auto index =
              static_cast<uint32_t>(rng.chance(0.9) ? rng.uniform(0, 89) : rng.uniform(0, 255));
          push({true, r::ori_index::kOffset, index, 0xF, false});
          const auto n = rng.uniform(1, 24);
          for (int64_t k = 0; k < n; ++k) push({false, r::ori_data::kOffset, 0, 0xF, false});
        }
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
      } else if (pick < 65 && kTopConfig.has_orientation && rng.chance(0.3)) {
        // ORI_CONTROL, any time (mid-frame too): mostly enabled, a threshold
        // giving some to many votes.
        push({true, r::ori_control::kOffset,
              r::ori_control::kEnable.put(rng.chance(0.85) ? 1u : 0u) |
                  r::ori_control::kThreshold.put(static_cast<uint32_t>(
                      rng.chance(0.1) ? rng.uniform(0, 0xFFF) : rng.uniform(0, 150))),
              0xF, false});
      } else if (pick < 65) {
        // Run-scanner / histogram / class window / corridor configuration,
        // any time (mid-frame too).
        switch (rng.uniform(0, kTopConfig.has_corridor ? 7 : 4)) {
          case 5:
          case 6: {
            // EDGE_CONTROL: mostly enabled, a threshold giving some to many edges.
            const uint32_t mode = rng.chance(0.1) ? 3u : static_cast<uint32_t>(rng.uniform(0, 2));
            push({true, r::edge_control::kOffset,
                  r::edge_control::kEnable.put(rng.chance(0.85) ? 1u : 0u) |
                      r::edge_control::kMode.put(mode) |
                      r::edge_control::kThreshold.put(static_cast<uint32_t>(
                          rng.chance(0.1) ? rng.uniform(0, 0xFFF) : rng.uniform(0, 120))),
                  0xF, false});
            break;
          }
          case 7: {
            // HOUGH_CONTROL / HOUGH_GEOMETRY.
            if (rng.chance(0.3)) {
              push({true, r::hough_geometry::kOffset,
                    static_cast<uint32_t>(rng.chance(0.8) ? rng.uniform(0, 24)
                                                          : rng.uniform(0, 0xFFF)),
                    0xF, false});
            } else {
              push({true, r::hough_control::kOffset,
                    r::hough_control::kEnable.put(rng.chance(0.9) ? 1u : 0u) |
                        r::hough_control::kUnitWeight.put(rng.chance(0.3) ? 1u : 0u) |
                        r::hough_control::kWeightShift.put(
                            static_cast<uint32_t>(rng.uniform(0, 15))) |
                        r::hough_control::kRhoShift.put(static_cast<uint32_t>(
                            rng.chance(0.7) ? rng.uniform(0, 2) : rng.uniform(0, 7))) |
                        r::hough_control::kThetaFirst.put(
                            static_cast<uint32_t>(rng.chance(0.6) ? 0 : rng.uniform(0, 60))) |
                        r::hough_control::kThetaCount.put(
                            static_cast<uint32_t>(rng.chance(0.5) ? 0 : rng.uniform(0, 60))),
                    0xF, false});
            }
            break;
          }
          case 4: {
            const bool x = rng.chance(0.5);
            const uint32_t lo = static_cast<uint32_t>(rng.uniform(0, 70));
            const uint32_t hi =
                rng.chance(0.2) ? 2048u : static_cast<uint32_t>(rng.uniform(0, 0xFFF));
            push({true, x ? r::class_win_x::kOffset : r::class_win_y::kOffset, lo | (hi << 16), 0xF,
                  false});
            break;
          }
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
        const auto bits = static_cast<uint32_t>(rng.uniform(0, 15));
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
                                  ? traffic_registers[rng.index(traffic_registers.size())].offset
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
      } else if (video.size() < 100'000 && rng.chance(0.002)) {
        hard_reset_pending = true;  // at the next idle bus cycle, below
      } else {
        // Idle bus for a while: a read of ID later.
        if (rng.chance(0.2)) push({false, r::id::kOffset, 0, 0xF, false});
      }
    }
    if (hard_reset_pending && !op_in_flight && m.idle()) {
      // Hardware reset (rst_ni), the bus idle, anywhere in a frame (not in
      // the big one): every register to its reset value, the device
      // disabled; the LUT RAM keeps its tables. The host enables it again;
      // the geometry written for the next frame is lost, so that frame may
      // well be malformed against the reset geometry.
      hard_reset_pending = false;
      top.hard_reset();
      ++cov.hard_resets;
      run_sink = false;
      control = r::control::kEnable.mask();
      ops.push_front({true, r::control::kOffset, control, 0xF, false});
      ops.push_front({true, r::intr_enable::kOffset, 0xF, 0xF, false});
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
    if (top.model().pipeline().frame_done()) {
      ++cov.frames_published;
      // Read a moment while the result store is being written (the read waits).
      if (rng.chance(0.5)) {
        const uint32_t word = static_cast<uint32_t>(rng.uniform(0, 5));
        ops.push_front(
            {false,
             rng.chance(0.5) ? r::mom_grey_lo::kArray.at(word) : r::mom_mask_hi::kArray.at(word), 0,
             0xF, false});
      }
    }
    if (op_in_flight && !op_now.write && Coverage::is_mom(op_now.addr & r::kAddrMask) &&
        top.model().pipeline().mom_wr().valid) {
      ++cov.mom_held;
    }
    if (!irq_before && top.model().irq()) ++cov.irq_rises;
    if (top.model().pipeline().hough_done()) ++cov.hough_published;
    if (kTopConfig.has_orientation) {
      const stream::Orientation& ori = top.model().pipeline().orientation();
      if (ori.done()) ++cov.ori_published;
      // An ORI_DATA read sampled on this edge while the other bank is swept.
      if (op_in_flight && !op_now.write && (op_now.addr & r::kAddrMask) == r::ori_data::kOffset &&
          ori.results_valid() && ori.clearing()) {
        ++cov.ori_read_clearing;
      }
    }
    // A HOUGH_DATA read sampled on this edge while the hough votes the next frame.
    if (op_in_flight && !op_now.write && (op_now.addr & r::kAddrMask) == r::hough_data::kOffset &&
        top.model().pipeline().hough().results_valid() &&
        top.model().pipeline().hough().state() == stream::Hough::State::kVote) {
      ++cov.hough_read_voting;
    }
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
    EXPECT_GT(cov.mom_nonzero, 0u);
    EXPECT_GT(cov.mom_held, 0u);
    EXPECT_GT(cov.soft_resets, 0u);
    EXPECT_GT(cov.hard_resets, 0u);
    if (kTopConfig.has_class_moments) {
      EXPECT_GT(cov.class_nonzero, 0u);
    } else {
      EXPECT_EQ(cov.class_nonzero, 0u);  // every CLASS_MOM_* read is SLVERR
    }
    if (kTopConfig.has_corridor) {
      EXPECT_GT(cov.hough_published, 10u);
      EXPECT_GT(cov.hough_nonzero, 0u);
      EXPECT_GT(cov.hough_read_voting, 0u);
    } else {
      EXPECT_EQ(cov.hough_published, 0u);
      EXPECT_EQ(cov.hough_nonzero, 0u);  // every HOUGH_* read is SLVERR
    }
    if (kTopConfig.has_orientation) {
      EXPECT_GT(cov.ori_published, 10u);
      EXPECT_GT(cov.ori_nonzero, 0u);
      EXPECT_GT(cov.ori_read_clearing, 0u);
    } else {
      EXPECT_EQ(cov.ori_nonzero, 0u);  // every ORI_* read is SLVERR
    }
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

// ---------------------------------------------------------------------------
// class_moments at device level: the CLASS_MOM registers read over AXI4-Lite
// equal cv::moments of each class mask inside the class window, with every
// port still compared on every cycle (TopCosim).
class RegBench : public DeviceBench {
 public:
  // m_axis_runs_tready always high.
  explicit RegBench(uint64_t seed) : DeviceBench(seed, "ceilnav_top_class_moments", 1.0) {}

  // A well-formed frame of `img` with tvalid gaps of probability gap_p.
  void queue_frame(const cv::Mat& img, double gap_p, Rng& rng) {
    std::vector<uint8_t> px;
    for (int y = 0; y < img.rows; ++y) {
      for (int x = 0; x < img.cols; ++x) px.push_back(img.at<uint8_t>(y, x));
    }
    queue(video_beats(px, img.cols), gap_p, -1, rng);
  }
  void set_window(const stream::ClassWindow& w) {
    write(r::class_win_x::kOffset, r::class_win_x::kX0.put(w.x0) | r::class_win_x::kX1.put(w.x1));
    write(r::class_win_y::kOffset, r::class_win_y::kY0.put(w.y0) | r::class_win_y::kY1.put(w.y1));
  }
  // The published hough accumulator through HOUGH_INDEX / HOUGH_DATA, j-major
  // (HOUGH_SHAPE's n_theta x 2^RHO_BITS cells, golden::hough_ref's order).
  // `reads_while_voting`: the HOUGH_DATA reads issued while the hough block
  // voted an edge of the next frame.
  std::vector<uint32_t> read_hough(const stream::HoughShape& shape, uint64_t& reads_while_voting) {
    std::vector<uint32_t> cells;
    write(r::hough_index::kOffset, 0);
    const auto n = static_cast<uint32_t>(shape.n_theta()) * shape.rho_bins();
    for (uint32_t i = 0; i < n; ++i) {
      if (model().pipeline().hough().state() == stream::Hough::State::kVote) ++reads_while_voting;
      cells.push_back(read(r::hough_data::kOffset));
    }
    return cells;
  }
  // The whole LUT from entry 0 (remap and mask; class 0).
  void write_lut(const std::array<stream::LutEntry, 256>& lut) {
    write(r::lut_index::kOffset, 0);
    for (const stream::LutEntry e : lut) {
      write(r::lut_data::kOffset, r::lut_data::kRemap.put(e & stream::kLutRemapMask) |
                                      r::lut_data::kMask.put((e & stream::kLutMaskBit) != 0));
    }
  }
  stream::ClassMomentResults read_class_moments() {
    stream::ClassMomentResults m;
    for (uint32_t i = 0; i < r::class_mom_lo::kCount; ++i) {
      m.cls[i / stream::kMomentCount][i % stream::kMomentCount] =
          read(r::class_mom_lo::kArray.at(i)) |
          (uint64_t{read(r::class_mom_hi::kArray.at(i))} << 32);
    }
    return m;
  }
};

#if CEILNAV_TOP_CONFIG_TAPE || CEILNAV_TOP_CONFIG_HOMING
// The tape and homing configurations have no class_moments and no corridor
// blocks (tape no orientation block either): every CLASS_*, EDGE_* and
// HOUGH_* (and ORI_*) register answers SLVERR (read 0, writes change
// nothing), while the rest of the device publishes its frames (the
// random-traffic test compares all of it).
TEST(CeilnavTopCosim, AbsentClassMomentRegistersAnswerSlvErr) {
  static_assert(!kTopConfig.has_class_moments && !kTopConfig.has_corridor);
  const uint64_t seed = cosim_seed(0x74617065);
  Rng rng(seed);
  RegBench b(seed);
  int absent = 0;
  for (const r::Register& reg : r::kRegisters) {
    if (kTopConfig.has(reg)) continue;
    uint32_t data = 0xDEADBEEFu;
    EXPECT_EQ(b.read_resp(reg.offset, data), r::kRespSlvErr) << reg.name;
    EXPECT_EQ(data, 0u) << reg.name;
    EXPECT_EQ(b.write_resp(reg.offset, 0x00100010u), r::kRespSlvErr) << reg.name;
    ++absent;
  }
  int corridor = 0;
  for (const r::Register& reg : r::kRegisters) corridor += reg.block == r::Block::kCorridor ? 1 : 0;
  EXPECT_EQ(corridor, 6 + 15);  // EDGE_*, HOUGH_*
  int orientation = 0;
  for (const r::Register& reg : r::kRegisters) {
    orientation += reg.block == r::Block::kOrientation ? 1 : 0;
  }
  EXPECT_EQ(orientation, 7);  // ORI_*
  // window + moments, the corridor registers, the orientation registers (tape)
  EXPECT_EQ(absent, 2 + 2 * static_cast<int>(r::class_mom_lo::kCount) + corridor +
                        (kTopConfig.has_orientation ? 0 : orientation));
  // A frame still streams, is published and raises the interrupt (the LUT
  // BRAM is not reset: program it first).
  b.write(r::lut_index::kOffset, 0);
  for (uint32_t g = 0; g < 256; ++g) {
    b.write(r::lut_data::kOffset,
            r::lut_data::kRemap.put(g) | r::lut_data::kMask.put(g >= 128 ? 1u : 0u));
  }
  b.write(r::intr_enable::kOffset, r::intr_enable::kFrameDone.mask());
  b.write(r::width::kOffset, 32);
  b.write(r::height::kOffset, 8);
  b.write(r::control::kOffset, r::control::kEnable.mask());
  cv::Mat img(8, 32, CV_8UC1);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) img.at<uint8_t>(y, x) = rng.byte();
  }
  b.queue_frame(img, 0.1, rng);
  b.drain_video();
  EXPECT_EQ(b.read(r::frame_count::kOffset), 1u);
  EXPECT_EQ(b.read(r::res_frame_index::kOffset), 0u);
  EXPECT_NE(b.read(r::intr_state::kOffset) & r::intr_state::kFrameDone.mask(), 0u);
  EXPECT_FALSE(b.sim().failed());
  b.sim().report();
}

#else
TEST(CeilnavTopCosim, ClassMomentsThroughRegistersEqualCvMoments) {
  const uint64_t seed = cosim_seed(0x636c7370);
  Rng rng(seed);
  RegBench b(seed);
  const cv::Mat photo_full =
      cv::imread("/usr/share/doc/opencv-doc/examples/data/building.jpg", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(photo_full.empty()) << "opencv-doc sample data missing";
  cv::Mat photo;
  cv::resize(photo_full, photo, cv::Size(160, 120), 0, 0, cv::INTER_AREA);
  // Classes by grey band: 0..63 background, 64..127 pattern, 128..191 shadow, 192.. bar.
  std::array<stream::LutEntry, 256> lut{};
  for (unsigned g = 0; g < 256; ++g) {
    lut[g] = stream::lut_entry(static_cast<uint8_t>(g), g > 100, static_cast<uint8_t>(g / 64));
  }
  const auto golden_of = [&lut](const cv::Mat& img, const stream::ClassWindow& w) {
    return golden::class_moments_ref(golden::lut_class_ref(img, lut), w);
  };
  const auto random_frame = [&rng](int w, int h) {
    cv::Mat img(h, w, CV_8UC1);
    uint8_t v = rng.byte();
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        if (rng.chance(0.1)) v = rng.byte();
        img.at<uint8_t>(y, x) = v;
      }
    }
    return img;
  };

  b.write(r::intr_enable::kOffset, r::intr_enable::kFrameDone.mask());
  b.write(r::width::kOffset, 160);
  b.write(r::height::kOffset, 120);
  b.write(r::lut_index::kOffset, 0);
  for (unsigned g = 0; g < 256; ++g) {
    const stream::LutEntry e = lut[g];
    b.write(r::lut_data::kOffset, r::lut_data::kRemap.put(e & stream::kLutRemapMask) |
                                      r::lut_data::kMask.put((e & stream::kLutMaskBit) != 0) |
                                      r::lut_data::kClass.put(stream::lut_class(e)));
  }
  // Reset value of the window: the whole frame.
  EXPECT_EQ(b.read(r::class_win_x::kOffset), 2048u << 16);
  b.write(r::control::kOffset, r::control::kEnable.mask());

  // Frame 0: the photo, whole frame.
  b.queue_frame(photo, 0.05, rng);
  b.drain_video();
  ASSERT_EQ(b.read(r::res_frame_index::kOffset), 0u);
  const stream::ClassMomentResults want0 = golden_of(photo, stream::ClassWindow{});
  EXPECT_EQ(b.read_class_moments(), want0);
  for (int c = 1; c <= stream::kMomentClasses; ++c) EXPECT_GT(want0.of(c)[stream::kM00], 0u) << c;

  // Frame 1 with window A; window B written while it streams applies to frame 2.
  const stream::ClassWindow win_a{13, 150, 7, 101};
  const stream::ClassWindow win_b{0, 40, 60, 4095};
  b.set_window(win_a);
  const cv::Mat img1 = random_frame(160, 120);
  const cv::Mat img2 = random_frame(160, 120);
  b.queue_frame(img1, 0.0, rng);
  b.queue_frame(img2, 0.1, rng);  // back to back, zero blanking
  for (int k = 0; k < 500; ++k) b.step();
  b.set_window(win_b);  // during frame 1
  // Frame 1 is published while frame 2 streams.
  while (b.model().pipeline().results().frame_index < 1 && !b.sim().failed()) b.step();
  const stream::ClassMomentResults got1 = b.read_class_moments();
  EXPECT_EQ(b.read(r::res_frame_index::kOffset), 1u) << "frame 2 published during the readout";
  EXPECT_EQ(got1, golden_of(img1, win_a));
  b.drain_video();
  ASSERT_EQ(b.read(r::res_frame_index::kOffset), 2u);
  EXPECT_EQ(b.read_class_moments(), golden_of(img2, win_b));

  // Tiny frames back to back: moment_gen drops those that end within its
  // combine; their class sums must not reach the published set.
  b.write(r::width::kOffset, 3);
  b.write(r::height::kOffset, 2);
  const stream::ClassWindow win_c{1, 3, 0, 2};
  b.set_window(win_c);
  std::vector<cv::Mat> tiny;
  for (int f = 0; f < 30; ++f) {
    tiny.push_back(random_frame(3, 2));
    b.queue_frame(tiny.back(), 0.0, rng);
  }
  b.drain_video();
  const uint32_t overrun = b.read(r::frames_overrun::kOffset);
  const uint32_t index = b.read(r::res_frame_index::kOffset);
  EXPECT_GT(overrun, 20u);
  ASSERT_GE(index, 3u);
  ASSERT_LT(index - 3u, tiny.size());
  EXPECT_EQ(b.read_class_moments(), golden_of(tiny[index - 3u], win_c));
  EXPECT_FALSE(b.sim().failed());
  b.sim().report();
}
#endif

#if !CEILNAV_TOP_CONFIG_TAPE && !CEILNAV_TOP_CONFIG_HOMING
// The corridor blocks at device level: corridor renders (seed 002's default
// corridor, two poses) stream back to back through the LUT's remap, the edge
// block and the hough voter; frame 0's accumulator, read over AXI4-Lite while
// frame 1 votes, and frame 1's equal golden::hough_ref on
// golden::find_edges_ref of the same remapped frames (exactly), with every
// port compared on every cycle. Prints the cycles from each frame's EOF to
// its publication (HOUGH_FRAME_COUNT moving) and the host reads.
TEST(CeilnavTopCosim, CorridorAccumulatorThroughRegistersEqualsGolden) {
  static_assert(kTopConfig.has_corridor);
  const uint64_t seed = cosim_seed(0x686f7567);
  Rng rng(seed);
  RegBench b(seed);
  constexpr int kW = 160;
  constexpr int kH = 120;
  // The camera of docs/renderer.md at a quarter of the resolution.
  host::CameraConfig camera;
  camera.image_width = kW;
  camera.image_height = kH;
  camera.camera_matrix = {505.0 / 4, 0.0, 322.3 / 4, 0.0, 498.0 / 4, 236.8 / 4, 0.0, 0.0, 1.0};
  const golden::corridor::Corridor corridor = golden::corridor::default_corridor();
  golden::corridor::Pose pose_b = golden::corridor::default_pose();
  pose_b.y_m += 0.3;
  pose_b.pan_rad += 0.15;
  const golden::corridor::RenderParams params;
  const std::array<cv::Mat, 2> frames = {
      golden::corridor::render_frame(camera, corridor, golden::corridor::default_pose(), params),
      golden::corridor::render_frame(camera, corridor, pose_b, params)};
  // A non-identity remap (a contrast stretch), so the edges are the remap's.
  std::array<stream::LutEntry, 256> lut{};
  for (unsigned g = 0; g < 256; ++g) {
    lut[g] = stream::lut_entry(static_cast<uint8_t>(std::min(255u, g * 3 / 2)), g > 100, 0);
  }
  const stream::HoughShape shape;  // the top's default parameters
  stream::HoughConfig hcfg;
  hcfg.enable = true;
  hcfg.weight_shift = 3;
  hcfg.rho_shift = 3;  // 8-pixel bins: 64 bins cover rho in [-160, 352)
  hcfg.width = kW;
  const golden::EdgeParams eparams{stream::EdgeMode::kSobel, 150};

  // Shape as the device reports it.
  const uint32_t shape_word = b.read(r::hough_shape::kOffset);
  EXPECT_EQ(r::hough_shape::kLanes.get(shape_word), static_cast<uint32_t>(shape.lanes));
  EXPECT_EQ(r::hough_shape::kThetaStep.get(shape_word), static_cast<uint32_t>(shape.theta_step));
  EXPECT_EQ(r::hough_shape::kRhoBits.get(shape_word), static_cast<uint32_t>(shape.rho_bits));
  EXPECT_EQ(r::hough_shape::kAccBits.get(shape_word), static_cast<uint32_t>(shape.acc_bits));
  EXPECT_NE(r::features::kCorridor.get(b.read(r::features::kOffset)), 0u);

  b.write(r::intr_enable::kOffset, r::intr_enable::kHoughDone.mask());
  b.write(r::width::kOffset, kW);
  b.write(r::height::kOffset, kH);
  b.write_lut(lut);
  b.write(r::edge_control::kOffset, r::edge_control::kEnable.put(1) |
                                        r::edge_control::kMode.put(2) |
                                        r::edge_control::kThreshold.put(eparams.threshold));
  b.write(r::hough_control::kOffset, r::hough_control::kEnable.put(1) |
                                         r::hough_control::kWeightShift.put(hcfg.weight_shift) |
                                         r::hough_control::kRhoShift.put(hcfg.rho_shift));
  b.write(r::hough_geometry::kOffset, r::hough_geometry::kWidth.put(hcfg.width));
  b.write(r::control::kOffset, r::control::kEnable.mask());

  // The golden accumulators (saturated as the cells are).
  std::array<std::vector<uint32_t>, 2> want;
  std::array<size_t, 2> n_edges{};
  for (size_t f = 0; f < frames.size(); ++f) {
    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(frames[f], lut, remap, mask);
    const std::vector<stream::EdgeRecord> pts = golden::find_edges_ref(remap, eparams);
    n_edges[f] = pts.size();
    want[f] = golden::hough_cells_ref(shape, hcfg, pts);
  }
  std::printf("[cosim] corridor frames %dx%d: %zu and %zu edge points\n", kW, kH, n_edges[0],
              n_edges[1]);
  EXPECT_GT(n_edges[0], 300u);
  EXPECT_GT(n_edges[1], 300u);

  // Both frames back to back; EOF -> publication of each.
  for (const cv::Mat& f : frames) b.queue_frame(f, 0.05, rng);
  std::array<uint64_t, 2> eof_cycle{};
  std::array<uint64_t, 2> done_cycle{};
  size_t eofs = 0;
  size_t dones = 0;
  uint32_t frames_ok = b.model().pipeline().error_counters().frames_ok;
  const auto watch = [&] {
    // frames_ok moves one edge after the edge that accepted the EOF beat.
    if (b.model().pipeline().error_counters().frames_ok != frames_ok && eofs < 2) {
      frames_ok = b.model().pipeline().error_counters().frames_ok;
      eof_cycle[eofs++] = b.sim().cycle() - 1;
    }
    if (b.model().pipeline().hough_done() && dones < 2) done_cycle[dones++] = b.sim().cycle() - 1;
  };
  while (dones < 1 && !b.sim().failed()) {
    b.step();
    watch();
  }
  ASSERT_EQ(eofs, 1u);
  EXPECT_NE(b.read(r::intr_state::kOffset) & r::intr_state::kHoughDone.mask(), 0u);
  EXPECT_EQ(b.read(r::hough_frame_count::kOffset), 1u);
  // Frame 0's accumulator while frame 1 streams and votes.
  uint64_t reads_voting = 0;
  const std::vector<uint32_t> got0 = b.read_hough(shape, reads_voting);
  EXPECT_EQ(b.read(r::hough_frame_count::kOffset), 1u) << "frame 1 published during the readout";
  EXPECT_GT(reads_voting, 100u);
  EXPECT_EQ(b.read(r::hough_trailer_edges::kOffset), n_edges[0]);
  EXPECT_EQ(b.read(r::hough_trailer_flags::kOffset), 0u);
  EXPECT_TRUE(got0 == want[0]) << "frame 0 accumulator differs from golden::hough_ref";
  while (dones < 2 && !b.sim().failed()) {
    b.step();
    watch();
  }
  ASSERT_EQ(eofs, 2u);
  for (int k = 0; k < 4; ++k) b.step();
  EXPECT_EQ(r::status::kHoughPending.get(b.read(r::status::kOffset)), 0u);
  EXPECT_EQ(b.read(r::hough_frame_count::kOffset), 2u);
  EXPECT_EQ(b.read(r::edge_dropped::kOffset), 0u);
  EXPECT_EQ(b.read(r::edge_count::kOffset), n_edges[1]);
  EXPECT_EQ(b.read(r::hough_edges::kOffset), n_edges[1]);
  EXPECT_EQ(b.read(r::hough_trailer_edges::kOffset), n_edges[1]);
  uint64_t unused_reads = 0;
  EXPECT_TRUE(b.read_hough(shape, unused_reads) == want[1])
      << "frame 1 accumulator differs from golden::hough_ref";
  const uint32_t stalls = b.read(r::hough_stalls::kOffset);
  for (size_t f = 0; f < 2; ++f) {
    std::printf("[cosim] corridor frame %zu: %zu edges, EOF -> hough published %llu cycles\n", f,
                n_edges[f], static_cast<unsigned long long>(done_cycle[f] - eof_cycle[f]));
  }
  std::printf("[cosim] corridor: %u stall cycles, %u HOUGH_DATA reads per frame\n", stalls,
              static_cast<uint32_t>(shape.n_theta()) * shape.rho_bins());
  EXPECT_FALSE(b.sim().failed());
  b.sim().report();
}
#endif

#if CEILNAV_TOP_CONFIG_HOMING
// The orientation block at device level (the homing configuration): two
// gratings with noise stream back to back through a non-identity LUT remap
// (tvalid gaps, run back-pressure); frame 0's histogram, read over AXI4-Lite
// through ORI_INDEX / ORI_DATA while frame 1 streams and votes, and frame 1's
// equal golden::orientation_histogram_fixed of the remapped frames (exactly),
// with every port compared on every cycle.
TEST(CeilnavTopCosim, OrientationHistogramThroughRegistersEqualsGolden) {
  static_assert(kTopConfig.has_orientation);
  const uint64_t seed = cosim_seed(0x6f726965);
  Rng rng(seed);
  RegBench b(seed);
  b.set_tready_p(0.6);
  constexpr int kW = 120;
  constexpr int kH = 90;
  constexpr uint32_t kThreshold = 24;
  const std::array<double, 2> angles = {28.0, 71.0};
  std::array<cv::Mat, 2> frames;
  for (size_t f = 0; f < frames.size(); ++f) {
    frames[f] = cv::Mat(kH, kW, CV_8UC1);
    const double a = angles[f] * CV_PI / 180.0;
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const double t = (x * std::cos(a) + y * std::sin(a)) * 2.0 * CV_PI / 11.0;
        frames[f].at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(
            128.0 + 80.0 * std::sin(t) + static_cast<double>(rng.uniform(-12, 12)));
      }
    }
  }
  std::array<stream::LutEntry, 256> lut{};
  for (unsigned g = 0; g < 256; ++g) {
    lut[g] = stream::lut_entry(static_cast<uint8_t>(std::min(255u, g * 3 / 2)), g > 100, 0);
  }
  std::array<std::vector<uint32_t>, 2> want;
  for (size_t f = 0; f < frames.size(); ++f) {
    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(frames[f], lut, remap, mask);
    want[f] = golden::orientation_histogram_fixed(remap, {90, static_cast<int>(kThreshold)});
  }

  EXPECT_NE(r::features::kOrientation.get(b.read(r::features::kOffset)), 0u);
  const uint32_t status0 = b.read(r::ori_status::kOffset);
  EXPECT_EQ(r::ori_status::kNumBins.get(status0), stream::Orientation::kDefaultBins);
  EXPECT_EQ(r::ori_status::kResultsValid.get(status0), 0u);
  b.write(r::width::kOffset, kW);
  b.write(r::height::kOffset, kH);
  b.write_lut(lut);
  b.write(r::ori_control::kOffset,
          r::ori_control::kEnable.put(1) | r::ori_control::kThreshold.put(kThreshold));
  b.write(r::control::kOffset, r::control::kEnable.mask());

  const auto read_bins = [&b] {
    std::vector<uint32_t> bins;
    b.write(r::ori_index::kOffset, 0);
    for (uint32_t k = 0; k < stream::Orientation::kDefaultBins; ++k) {
      bins.push_back(b.read(r::ori_data::kOffset));
    }
    return bins;
  };
  for (const cv::Mat& f : frames) b.queue_frame(f, 0.05, rng);
  while (b.model().pipeline().orientation().frames() < 1 && !b.sim().failed()) b.step();
  EXPECT_TRUE(b.frame_streaming());
  EXPECT_EQ(b.read(r::ori_frames::kOffset), 1u);
  const uint32_t votes0 = b.read(r::ori_votes::kOffset);
  EXPECT_GT(votes0, 0u);
  EXPECT_LE(votes0, static_cast<uint32_t>((kW - 2) * (kH - 2)));
  // Frame 0's histogram while frame 1 streams and votes.
  const std::vector<uint32_t> got0 = read_bins();
  EXPECT_TRUE(b.frame_streaming()) << "frame 1 ended during the readout";
  EXPECT_EQ(b.read(r::ori_frames::kOffset), 1u) << "frame 1 published during the readout";
  EXPECT_TRUE(got0 == want[0]) << "frame 0 histogram differs from the golden";
  b.drain_video();
  EXPECT_EQ(b.read(r::ori_frames::kOffset), 2u);
  EXPECT_EQ(b.read(r::ori_skipped::kOffset), 0u);
  EXPECT_EQ(r::ori_status::kResultsValid.get(b.read(r::ori_status::kOffset)), 1u);
  EXPECT_TRUE(read_bins() == want[1]) << "frame 1 histogram differs from the golden";
  // The peak is near the grating's angle (1-degree bins; the 3 x 3 Sobel's
  // anisotropy on an 11-pixel period with noise moves it by a few degrees).
  for (size_t f = 0; f < 2; ++f) {
    const auto peak = std::max_element(want[f].begin(), want[f].end()) - want[f].begin();
    EXPECT_LE(std::abs(static_cast<double>(peak) - angles[f]), 4.0) << "frame " << f;
  }
  // Past the bins: 0.
  b.write(r::ori_index::kOffset, 200);
  EXPECT_EQ(b.read(r::ori_data::kOffset), 0u);
  EXPECT_EQ(b.read(r::ori_index::kOffset), 201u);
  EXPECT_FALSE(b.sim().failed());
  b.sim().report();
}
#endif

}  // namespace
}  // namespace ceilnav::testbench
