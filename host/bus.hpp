// The host's view of the device: 32-bit register reads/writes, the interrupt
// line, the run stream's consumer (a DMA in a real system) and the device
// clock. One Driver runs on every backend: the C++ model and the Verilated RTL
// (drivers::SimBus and its devices), a memory-mapped device. Feeding camera
// frames is not the host's business on hardware (the camera does it); the
// simulation backends offer it themselves (drivers::SimBus::queue_frame).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/results.hpp"

namespace ceilnav::host {

// A transaction answered with SLVERR (or a backend failure).
class BusError : public std::runtime_error {
 public:
  explicit BusError(const std::string& what) : std::runtime_error(what) {}
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

  // Beats (runs and trailers) the m_axis_runs consumer (a DMA in a real
  // system) has received since the last call, in order.
  virtual std::vector<stream::RunBeat> take_run_stream() = 0;

  // Device clock cycles since the backend was created.
  virtual uint64_t cycles() const = 0;
};

}  // namespace ceilnav::host
