// The host's view of the device: 32-bit register reads/writes, the interrupt
// line, and (for simulation backends) the camera feed and the run stream
// consumer. One Driver runs on every backend: the C++ model (ModelBus), the
// Verilated RTL, a memory-mapped device.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "stream/results.hpp"

namespace ceilnav::host {

// A transaction answered with SLVERR (or a backend failure).
class BusError : public std::runtime_error {
 public:
  explicit BusError(const std::string& what) : std::runtime_error(what) {}
};

// How a queued frame is streamed into s_axis_video.
struct FrameFeed {
  double gap_probability = 0.0;  // before every pixel, idle cycles while a coin with P = this hits
  uint32_t blanking_cycles = 0;  // idle cycles after the frame's last pixel
  uint32_t line_blanking_cycles = 0;  // idle cycles after every line but the last
};

class Bus {
 public:
  virtual ~Bus() = default;

  // addr is the register offset (docs/registers.md). A SLVERR response throws BusError.
  virtual uint32_t read32(uint32_t addr) = 0;
  virtual void write32(uint32_t addr, uint32_t value) = 0;
  // Returns as soon as irq is high (at once if it already is); false after
  // timeout_cycles device clocks without it.
  virtual bool wait_irq(uint64_t timeout_cycles) = 0;
  // Lets the device run for `cycles` clocks.
  virtual void idle(uint64_t cycles) = 0;

  // Appends one frame (8-bit grey, row stride in bytes) to the camera feed;
  // simulation backends stream it one beat per clock, behind frames queued
  // earlier, while the host's transactions run.
  virtual void queue_frame(const uint8_t* grey, int width, int height, size_t stride_bytes,
                           const FrameFeed& feed) = 0;
  // Beats (runs and trailers) the m_axis_runs consumer (a DMA in a real
  // system) has received since the last call, in order.
  virtual std::vector<stream::RunBeat> take_run_stream() = 0;

  // Device clock cycles since the backend was created.
  virtual uint64_t cycles() const = 0;
};

}  // namespace ceilnav::host
