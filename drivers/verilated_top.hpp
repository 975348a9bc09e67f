// One Verilated top (ports clk_i and rst_ni) in its own VerilatedContext: the
// Verilator glue every co-simulation, benchmark and RTL backend needs, in one
// copy. No GoogleTest and no trace library here, so a speed build of the RTL
// (verilated without --trace) can use it as well.
//
// Clock protocol (Verilator's examples): every cycle starts with clk_i low;
// the caller sets the inputs, then edge() settles them, raises clk_i (the
// sampling edge), settles the outputs and lowers clk_i again, so inputs never
// change on the sampling edge. reset_cycle() holds rst_ni low across one
// rising edge: an asynchronous reset sees the falling rst_ni, a synchronous
// one the edge, so the same harness serves both.
//
// Trace is a policy: NoTrace here, testbench::FstTrace (testbench/fst_trace.hpp) for the
// co-simulation builds. It sees the context before the model exists (trace
// switched on), the model after, and every time step.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

// Verilator's headers (verilated*.h and the generated model classes) trip the
// project warnings: every co-simulation includes them between these two.
#define CEILNAV_VERILATOR_HEADERS_BEGIN                                         \
  _Pragma("GCC diagnostic push") _Pragma("GCC diagnostic ignored \"-Wshadow\"") \
      _Pragma("GCC diagnostic ignored \"-Wconversion\"")                        \
          _Pragma("GCC diagnostic ignored \"-Wsign-conversion\"")               \
              _Pragma("GCC diagnostic ignored \"-Wpedantic\"")                  \
                  _Pragma("GCC diagnostic ignored \"-Wunused-parameter\"")
#define CEILNAV_VERILATOR_HEADERS_END _Pragma("GCC diagnostic pop")

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "verilated.h"
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::drivers {

// The trace policy of a build without trace support.
struct NoTrace {
  void before_model(VerilatedContext& /*ctx*/) {}
  template <class Top>
  void after_model(Top& /*top*/, const std::string& /*name*/) {}
  void dump(uint64_t /*time*/) {}
  void close() {}
};

template <class Top, class Trace = NoTrace>
class VerilatedTop {
 public:
  static constexpr uint64_t kPeriodTicks = 10;  // time units per clock

  // Registers without a reset start random (randReset 2), drawn from `seed`,
  // as the flops of a real device power up. `name` names the trace file.
  explicit VerilatedTop(uint64_t seed, const std::string& name = "top")
      : ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->randReset(2);
    ctx_->randSeed(static_cast<int>(seed & 0x7FFFFFFFu));
    const char* argv[] = {"ceilnav"};
    ctx_->commandArgs(1, argv);
    trace_.before_model(*ctx_);
    top_ = std::make_unique<Top>(ctx_.get(), "TOP");
    trace_.after_model(*top_, name);
    top_->clk_i = 0;
    top_->rst_ni = 1;
    top_->eval();
  }

  ~VerilatedTop() {
    top_->final();
    trace_.close();
  }

  VerilatedTop(const VerilatedTop&) = delete;
  VerilatedTop& operator=(const VerilatedTop&) = delete;

  Top& dut() { return *top_; }
  const Top& dut() const { return *top_; }
  VerilatedContext& ctx() { return *ctx_; }
  uint64_t cycle() const { return cycle_; }  // rising edges so far

  // One clock: inputs settle with clk_i low, rising edge, outputs settle.
  void edge() {
    top_->eval();
    dump(cycle_ * kPeriodTicks + 4);
    top_->clk_i = 1;
    top_->eval();
    dump(cycle_ * kPeriodTicks + 5);
    ++cycle_;
    top_->clk_i = 0;
    ctx_->time(cycle_ * kPeriodTicks);
  }

  // One reset cycle: rst_ni falls with clk_i low, stays low across one rising
  // edge (counted in cycle()) and rises again with clk_i low.
  void reset_cycle() {
    top_->rst_ni = 0;
    top_->eval();
    dump(cycle_ * kPeriodTicks + 1);
    edge();
    top_->rst_ni = 1;
    top_->eval();
    dump(cycle_ * kPeriodTicks + 2);
  }

 private:
  void dump(uint64_t time) {
    ctx_->time(time);
    trace_.dump(time);
  }

  std::unique_ptr<VerilatedContext> ctx_;
  Trace trace_;
  std::unique_ptr<Top> top_;
  uint64_t cycle_ = 0;
};

}  // namespace ceilnav::drivers
