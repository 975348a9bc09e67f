// A Verilated ceilnav_top (either configuration) as a SimDevice, so that
// SimBus clocks it and the host Driver runs on it exactly as on the C++ model
// (ModelBus). Non-owning: the VerilatedTop (drivers/verilated_top.hpp) lives
// elsewhere — in OwnedVerilatedDevice below, or in a benchmark that also
// drives it directly.
#pragma once

#include <cstdint>
#include <string>

#include "drivers/sim_bus.hpp"
#include "drivers/verilated_ports.hpp"
#include "drivers/verilated_top.hpp"

namespace ceilnav::drivers {

template <class Top, class Trace = NoTrace>
class VerilatedDevice : public SimDevice {
 public:
  explicit VerilatedDevice(VerilatedTop<Top, Trace>& top) : top_(top) {}

  // The flops reset synchronously: rst_ni low across one rising edge.
  void reset() override { top_.reset_cycle(); }

  SimOutputs outputs() const override {
    const Top& t = top_.dut();
    SimOutputs o;
    o.s_axil = read_s_axil(t);
    o.m_axis_runs = read_m_axis_runs(t);
    o.irq = t.irq_o;
    o.s_axis_video_tready = t.s_axis_video_tready_o;
    return o;
  }

  void clock(const SimInputs& in) override {
    Top& t = top_.dut();
    drive_s_axis_video(t, in.s_axis_video);
    drive_s_axil(t, in.s_axil);
    t.m_axis_runs_tready_i = in.m_axis_runs_tready;
    top_.edge();
  }

 private:
  VerilatedTop<Top, Trace>& top_;
};

namespace detail {
template <class Top>
struct VerilatedTopHolder {
  VerilatedTop<Top> top;
  explicit VerilatedTopHolder(uint64_t seed) : top(seed, "ceilnav_top") {}
};
}  // namespace detail

// A VerilatedDevice that owns its top, in its own VerilatedContext; registers
// without a reset start random from `seed`, as in silicon. Reset once.
template <class Top>
class OwnedVerilatedDevice : private detail::VerilatedTopHolder<Top>, public VerilatedDevice<Top> {
 public:
  explicit OwnedVerilatedDevice(uint64_t seed)
      : detail::VerilatedTopHolder<Top>(seed), VerilatedDevice<Top>(this->top) {
    VerilatedDevice<Top>::reset();
  }
};

}  // namespace ceilnav::drivers
