#include "drivers/sim_bus.hpp"

#include <string>

#include "ceilnav/regs.hpp"

namespace ceilnav::drivers {

SimBus::SimBus(std::unique_ptr<SimDevice> device, const SimBusOptions& options)
    : device_(std::move(device)),
      options_(options),
      master_(options.seed, options.axi_timing),
      rng_state_(options.seed ^ 0x5DEECE66Dull) {
  device_->reset();
}

bool SimBus::chance(double p) {
  if (p <= 0.0) return false;
  // splitmix64
  uint64_t z = (rng_state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53 < p;
}

void SimBus::tick() {
  SimInputs in;
  const SimOutputs out = device_->outputs();
  if (!video_.empty()) {
    in.s_axis_video = video_.front();
    // An idle cycle passes whatever tready is; a valid beat waits for tready.
    if (out.s_axis_video_tready || !in.s_axis_video.tvalid) video_.pop_front();
  }
  in.s_axil = master_.drive();
  in.m_axis_runs_tready = !chance(options_.run_tready_low_probability);
  if (out.m_axis_runs.tvalid && in.m_axis_runs_tready) runs_.push_back(out.m_axis_runs);
  if (observer_ != nullptr) observer_->on_edge(cycles_, in, out);
  device_->clock(in);
  master_.edge(out.s_axil);
  ++cycles_;
}

void SimBus::run_transaction() {
  for (uint64_t i = 0; i < options_.transaction_timeout_cycles; ++i) {
    if (master_.done()) return;
    tick();
  }
  if (!master_.done()) throw host::BusError("SimBus: AXI4-Lite transaction timed out");
}

uint8_t SimBus::read32_resp(uint32_t addr, uint32_t& value) {
  master_.start_read(addr);
  run_transaction();
  value = master_.rdata();
  return master_.resp();
}

uint8_t SimBus::write32_resp(uint32_t addr, uint32_t value, uint8_t strb) {
  master_.start_write(addr, value, strb);
  run_transaction();
  return master_.resp();
}

uint32_t SimBus::read32(uint32_t addr) {
  uint32_t value = 0;
  if (read32_resp(addr, value) != regs::kRespOkay) {
    throw host::BusError("SimBus: SLVERR reading 0x" + std::to_string(addr));
  }
  return value;
}

void SimBus::write32(uint32_t addr, uint32_t value) {
  if (write32_resp(addr, value) != regs::kRespOkay) {
    throw host::BusError("SimBus: SLVERR writing 0x" + std::to_string(addr));
  }
}

bool SimBus::wait_irq(uint64_t timeout_cycles) {
  for (uint64_t i = 0; i < timeout_cycles; ++i) {
    if (device_->outputs().irq) return true;
    tick();
  }
  return device_->outputs().irq;
}

void SimBus::idle(uint64_t cycles) {
  for (uint64_t i = 0; i < cycles; ++i) tick();
}

void SimBus::queue_frame(const uint8_t* grey, int width, int height, size_t stride_bytes,
                         const FrameFeed& feed) {
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = grey + static_cast<size_t>(y) * stride_bytes;
    for (int x = 0; x < width; ++x) {
      while (chance(feed.gap_probability)) video_.push_back({});
      stream::VideoBeat b;
      b.tvalid = true;
      b.tdata = row[x];
      b.tuser = x == 0 && y == 0;
      b.tlast = x == width - 1;
      video_.push_back(b);
    }
    if (y + 1 < height) video_.insert(video_.end(), feed.line_blanking_cycles, stream::VideoBeat{});
  }
  video_.insert(video_.end(), feed.blanking_cycles, stream::VideoBeat{});
}

std::vector<stream::RunBeat> SimBus::take_run_stream() {
  std::vector<stream::RunBeat> out;
  out.swap(runs_);
  return out;
}

}  // namespace ceilnav::drivers
