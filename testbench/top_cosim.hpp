// The device co-simulation harness shared by the device-level tests:
// Vceilnav_top (library ceilnav_rtl_top) and stream::CeilnavTop in lockstep,
// the same video, AXI4-Lite and m_axis_runs_tready stimulus into both on every
// cycle and every output port compared after every edge. See docs/cosim.md.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "ceilnav/regs.hpp"

#include "common/run_record.hpp"
#include "drivers/axi_lite_master.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/run_scanner.hpp"
#include "testbench/cosim_common.hpp"
#include "testbench/ports.hpp"
#include "testbench/video_stream.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#if CEILNAV_TOP_CONFIG_TAPE
#include "Vceilnav_top_tape.h"
#elif CEILNAV_TOP_CONFIG_HOMING
#include "Vceilnav_top_homing.h"
#else
#include "Vceilnav_top.h"
#endif
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::testbench {

// The device configuration under test (docs/registers.md "Configurations"):
// the same test sources are built once per configuration, against the RTL
// verilated with that configuration's parameters and the C++ model given the
// same regs::Config.
#if CEILNAV_TOP_CONFIG_TAPE
using VDeviceTop = Vceilnav_top_tape;
inline constexpr const regs::Config& kTopConfig = regs::kConfigTape;
#elif CEILNAV_TOP_CONFIG_HOMING
using VDeviceTop = Vceilnav_top_homing;
inline constexpr const regs::Config& kTopConfig = regs::kConfigHoming;
#else
using VDeviceTop = Vceilnav_top;
inline constexpr const regs::Config& kTopConfig = regs::kConfigFull;
#endif

// The registers of the configuration under test, in map order (an absent
// block's registers answer SLVERR like unmapped offsets).
inline std::vector<regs::Register> present_registers() {
  std::vector<regs::Register> out;
  for (const regs::Register& reg : regs::kRegisters) {
    if (kTopConfig.has(reg)) out.push_back(reg);
  }
  return out;
}

// The register at `offset` if the configuration under test has it, else nullptr.
inline const regs::Register* present(uint32_t offset) {
  const regs::Register* reg = regs::find(offset);
  return reg != nullptr && kTopConfig.has(*reg) ? reg : nullptr;
}

// The two tops in lockstep.
class TopCosim {
 public:
  explicit TopCosim(uint64_t seed, const char* name = "ceilnav_top")
      : sim_(name, seed),
        model_(regs::kRunFifoDepth, kTopConfig),
        master_(seed ^ 0xA5A5A5A5u, drivers::AxiLiteMaster::Timing{0.3, 0.3}) {
    // The datapath's reset is rst_ni & ~soft_rst_q. With the random power-up
    // state soft_rst_q may start at 1, and then the first rst_ni fall makes no
    // negedge on the datapath reset in the simulator (real reset is a level):
    // a second reset cycle, with soft_rst_q now 0, resets the datapath too.
    sim_.reset_cycle();
    model_.reset();
  }

  // One clock with the given video beat and run tready; the bus master's
  // outputs come from the master. Returns false at the first mismatch.
  bool step(const stream::VideoBeat& video, bool runs_tready) {
    const stream::AxiLiteIn& in = master_.drive();
    auto& d = sim_.dut();
    drive_s_axis_video(d, video);
    drive_s_axil(d, in);
    d.m_axis_runs_tready_i = runs_tready;
    master_.edge(model_.s_axil_out());  // handshakes with the pre-edge outputs
    model_.clock(video, in, runs_tready);
    sim_.edge();
    return compare();
  }

  // Hardware reset (rst_ni low across one edge) of both tops, e.g. in
  // mid-frame. Call with the bus master idle: a reset drops a transaction.
  void hard_reset() {
    sim_.reset_cycle();
    model_.reset();
  }

  Cosim<VDeviceTop>& sim() { return sim_; }
  drivers::AxiLiteMaster& master() { return master_; }
  const stream::CeilnavTop& model() const { return model_; }

 private:
  bool compare() {
    auto& d = sim_.dut();
    bool ok = check_s_axil(sim_, d, model_.s_axil_out());
    ok = check_m_axis_runs(sim_, d, model_.m_axis_runs()) && ok;
    ok = sim_.check("irq_o", d.irq_o, model_.irq()) && ok;
    ok = sim_.check("s_axis_video_tready_o", d.s_axis_video_tready_o, 1) && ok;
    return ok;
  }

  Cosim<VDeviceTop> sim_;
  stream::CeilnavTop model_;
  drivers::AxiLiteMaster master_;
};

// A scripted device bench on TopCosim: a video queue (one beat per edge), a
// blocking register bus, random m_axis_runs back-pressure (tready low) and a
// log of the run stream. Used by the malformed-stream and register-fault
// tests and the scripted tests of the top co-simulation.
class DeviceBench {
 public:
  static constexpr uint64_t kLoopLimitCycles = 200'000;

  DeviceBench(uint64_t seed, const char* name, double tready_p)
      : top_(seed, name), rng_(seed), tready_p_(tready_p) {}

  Rng& rng() { return rng_; }
  Cosim<VDeviceTop>& sim() { return top_.sim(); }
  const stream::CeilnavTop& model() const { return top_.model(); }
  void hard_reset() { top_.hard_reset(); }
  std::deque<stream::VideoBeat>& video() { return video_; }
  // Queues a frame's beats (video_beats) behind blanking and tvalid gaps
  // (queue_video), drawn from `rng`.
  void queue(const std::vector<stream::VideoBeat>& beats, double gap_p, int64_t max_blanking,
             Rng& rng) {
    queue_video(video_, rng, beats, gap_p, max_blanking);
  }
  std::vector<stream::RunBeat>& runs_log() { return runs_log_; }
  void set_tready_p(double p) { tready_p_ = p; }

  // One edge: the next queued video beat (or a gap) and a random run tready.
  void step() {
    stream::VideoBeat beat;
    if (!video_.empty()) {
      beat = video_.front();
      video_.pop_front();
    }
    const bool tready = rng_.chance(tready_p_);
    const stream::RunBeat runs = top_.model().m_axis_runs();
    if (runs.tvalid && tready) runs_log_.push_back(runs);
    top_.step(beat, tready);
    if (top_.sim().cycle() > kLoopLimitCycles) top_.sim().fail("bench ran past its cycle limit");
  }

  uint32_t read(uint32_t addr, uint8_t want_resp = regs::kRespOkay) {
    top_.master().start_read(addr);
    wait_bus();
    EXPECT_EQ(top_.master().resp(), want_resp) << "read of 0x" << std::hex << addr;
    return top_.master().rdata();
  }
  // The response of a read or a write, whatever it is.
  uint8_t read_resp(uint32_t addr, uint32_t& data) {
    top_.master().start_read(addr);
    wait_bus();
    data = top_.master().rdata();
    return top_.master().resp();
  }
  uint8_t write_resp(uint32_t addr, uint32_t data) {
    top_.master().start_write(addr, data, 0xF);
    wait_bus();
    return top_.master().resp();
  }
  void write(uint32_t addr, uint32_t data, uint8_t strb = 0xF,
             uint8_t want_resp = regs::kRespOkay) {
    top_.master().start_write(addr, data, strb);
    wait_bus();
    EXPECT_EQ(top_.master().resp(), want_resp)
        << "write of 0x" << std::hex << addr << " strb 0x" << unsigned{strb};
  }
  uint64_t read64(uint32_t lo_addr) {
    const uint64_t lo = read(lo_addr);
    return lo | (uint64_t{read(lo_addr + 4)} << 32);
  }

  // Until the video queue is empty and the results of its last frame are
  // published (EOF -> INTR_STATE.FRAME_DONE: kEofToIntrCycles edges).
  void drain_video() {
    while (!video_.empty() && !top_.sim().failed()) step();
    for (int k = 0; k < stream::CeilnavTop::kEofToIntrCycles + 4; ++k) step();
  }
  // Until the run FIFO and its output register are empty.
  void drain_runs() {
    while (
        (top_.model().pipeline().run_fifo_occupancy() != 0 || top_.model().m_axis_runs().tvalid) &&
        !top_.sim().failed()) {
      step();
    }
  }
  // The run records of the last frame whose trailer has left m_axis_runs.
  std::vector<stream::RunRecord> last_frame_runs() {
    drain_runs();
    std::vector<stream::RunRecord> out;
    if (runs_log_.empty() || !runs_log_.back().tlast) return out;
    size_t first = runs_log_.size() - 1;
    while (first > 0 && !runs_log_[first - 1].tlast) --first;
    for (size_t i = first; i + 1 < runs_log_.size(); ++i) out.push_back(runs_log_[i].tdata);
    return out;
  }
  bool frame_streaming() const {
    return std::any_of(video_.begin(), video_.end(),
                       [](const stream::VideoBeat& v) { return v.tvalid; });
  }

 private:
  void wait_bus() {
    do {
      step();
    } while (!top_.master().idle() && !top_.sim().failed());
  }

  TopCosim top_;
  Rng rng_;
  std::deque<stream::VideoBeat> video_;
  std::vector<stream::RunBeat> runs_log_;
  double tready_p_;
};

}  // namespace ceilnav::testbench
