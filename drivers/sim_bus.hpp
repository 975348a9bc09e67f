// SimBus: a Bus on any clocked simulation of ceilnav_top. It owns the clock:
// every read32/write32/wait_irq/idle advances the device one edge at a time,
// with the queued video streaming into s_axis_video and a run-stream
// consumer with optional back-pressure. A backend only implements SimDevice
// (set inputs, clock one edge, read registered outputs): ModelBus wraps the
// C++ CeilnavTop, an RtlBus wraps the Verilated RTL the same way.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "ceilnav/regs.hpp"
#include "common/results.hpp"
#include "drivers/axi_lite_master.hpp"
#include "host/bus.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"

namespace ceilnav::drivers {

// How a queued frame is streamed into s_axis_video.
struct FrameFeed {
  double gap_probability = 0.0;  // before every pixel, idle cycles while a coin with P = this hits
  uint32_t blanking_cycles = 0;  // idle cycles after the frame's last pixel
  uint32_t line_blanking_cycles = 0;  // idle cycles after every line but the last
};

struct SimInputs {
  stream::VideoBeat s_axis_video;
  stream::AxiLiteIn s_axil;
  bool m_axis_runs_tready = true;
};

struct SimOutputs {
  stream::AxiLiteOut s_axil;
  stream::RunBeat m_axis_runs;
  bool irq = false;
  // A beat on s_axis_video is taken on an edge only with tready high before it;
  // SimBus holds the beat otherwise.
  bool s_axis_video_tready = true;
};

class SimDevice {
 public:
  virtual ~SimDevice() = default;
  virtual void reset() = 0;
  // Registered outputs, valid between edges.
  virtual SimOutputs outputs() const = 0;
  // Applies the inputs and clocks one rising edge.
  virtual void clock(const SimInputs& in) = 0;
};

// Sees every edge SimBus clocks (profiling, protocol monitors): the inputs
// sampled on edge `edge` (numbered from 0 = SimBus::cycles() before it) and
// the registered outputs before it, against which the handshakes are made.
class SimObserver {
 public:
  virtual ~SimObserver() = default;
  virtual void on_edge(uint64_t edge, const SimInputs& in, const SimOutputs& out) = 0;
};

struct SimBusOptions {
  uint64_t seed = 1;
  // The device's build-time configuration (regs::kConfigTape, regs::kConfigFull):
  // which optional blocks the simulated device has.
  regs::Config device_config = regs::kConfigFull;
  AxiLiteMaster::Timing axi_timing{};       // random valid delays / ready stalls
  double run_tready_low_probability = 0.0;  // back-pressure on m_axis_runs
  uint64_t transaction_timeout_cycles = 100000;
};

class SimBus : public host::Bus {
 public:
  explicit SimBus(std::unique_ptr<SimDevice> device, const SimBusOptions& options = {});

  uint32_t read32(uint32_t addr) override;
  void write32(uint32_t addr, uint32_t value) override;
  bool wait_irq(uint64_t timeout_cycles) override;
  void idle(uint64_t cycles) override;
  // Appends one frame (8-bit grey, row stride in bytes) to the camera feed;
  // it streams one beat per clock, behind frames queued earlier, while the
  // host's transactions run.
  void queue_frame(const uint8_t* grey, int width, int height, size_t stride_bytes,
                   const FrameFeed& feed);
  std::vector<stream::RunBeat> take_run_stream() override;
  uint64_t cycles() const override { return cycles_; }

  // Response of the last transaction without throwing (tests of the bus rules).
  uint8_t read32_resp(uint32_t addr, uint32_t& value);
  uint8_t write32_resp(uint32_t addr, uint32_t value, uint8_t strb = 0xF);
  // Video beats not yet streamed.
  size_t video_backlog() const { return video_.size(); }
  // Called on every edge from now on (nullptr: none); not owned.
  void set_observer(SimObserver* observer) { observer_ = observer; }

 protected:
  SimDevice& device() { return *device_; }

 private:
  void tick();
  void run_transaction();
  bool chance(double p);

  std::unique_ptr<SimDevice> device_;
  SimBusOptions options_;
  AxiLiteMaster master_;
  uint64_t rng_state_;
  std::deque<stream::VideoBeat> video_;
  std::vector<stream::RunBeat> runs_;
  uint64_t cycles_ = 0;
  SimObserver* observer_ = nullptr;
};

}  // namespace ceilnav::drivers
