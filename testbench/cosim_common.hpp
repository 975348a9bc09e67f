// Shared co-simulation harness: one Verilated top against a C++ cycle model.
//
// Protocol (Verilator's examples): every cycle starts with clk_i low; the test
// sets the inputs of both the RTL and the C++ model, then edge() settles the
// inputs, raises clk_i (the sampling edge), settles the outputs and lowers
// clk_i again, so inputs never change on the sampling edge. async_reset()
// pulses rst_ni low between two edges (the C++ model's reset()).
//
// Environment (switched by option, not by editing code):
//   CEILNAV_COSIM_SEED=<n>    overrides every test's default seed
//   CEILNAV_COSIM_CYCLES=<f>  scales every test's length by f (soak: 10, 100)
//   CEILNAV_TRACE=<file.fst>  dumps an FST trace; "%n" in the name is replaced
//                             by the harness name (one file per test)
//   CEILNAV_COVERAGE_DIR=<dir> in a coverage build (CEILNAV_RTL_COVERAGE=ON),
//                             writes this harness's Verilator coverage to
//                             <dir>/<test>.<harness>.s<seed>.<n>.dat
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include "verilated.h"
#include "verilated_fst_c.h"
#if defined(CEILNAV_RTL_COVERAGE) && CEILNAV_RTL_COVERAGE
#include "verilated_cov.h"
#endif
#pragma GCC diagnostic pop

namespace ceilnav::testbench {

// Unsigned integer from the environment, or fallback if unset or unparsable.
inline uint64_t env_u64(const char* name, uint64_t fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') {
    return fallback;
  }
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text, &end, 0);
  return (end != nullptr && *end == '\0') ? value : fallback;
}

// The seed of a test: CEILNAV_COSIM_SEED if set, else the test's default.
inline uint64_t cosim_seed(uint64_t default_seed) {
  return env_u64("CEILNAV_COSIM_SEED", default_seed);
}

// Length scale factor from CEILNAV_COSIM_CYCLES (default 1).
inline double cosim_scale() {
  const char* text = std::getenv("CEILNAV_COSIM_CYCLES");
  if (text == nullptr || *text == '\0') {
    return 1.0;
  }
  const double scale = std::strtod(text, nullptr);
  return scale > 0.0 ? scale : 1.0;
}

// A test's cycle (or frame) budget: default_count scaled, at least 1.
inline uint64_t cosim_count(uint64_t default_count) {
  const double scaled = std::round(static_cast<double>(default_count) * cosim_scale());
  return std::max<uint64_t>(1, static_cast<uint64_t>(scaled));
}

// Seeded random source for stimulus.
class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}

  // Uniform integer in [lo, hi].
  int64_t uniform(int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(engine_);
  }
  template <class T>
  T uniform_as(int64_t lo, int64_t hi) {
    return static_cast<T>(uniform(lo, hi));
  }
  // Uniform index in [0, count), count > 0.
  size_t index(size_t count) {
    return std::uniform_int_distribution<size_t>(0, count - 1)(engine_);
  }
  bool chance(double probability) { return std::bernoulli_distribution(probability)(engine_); }
  uint8_t byte() { return uniform_as<uint8_t>(0, 255); }
  std::mt19937_64& engine() { return engine_; }

 private:
  std::mt19937_64 engine_;
};

// One Verilated top (with ports clk_i and rst_ni) and its context.
template <class Top>
class Cosim {
 public:
  static constexpr uint64_t kPeriodTicks = 10;  // trace time units per clock

  Cosim(const std::string& name, uint64_t seed) : name_(name), seed_(seed) {
    ctx_ = std::make_unique<VerilatedContext>();
    ctx_->randReset(2);  // registers without reset start random, seeded
    ctx_->randSeed(static_cast<int>(seed & 0x7FFFFFFFu));
    const char* argv[] = {"cosim"};
    ctx_->commandArgs(1, argv);
    const char* trace = std::getenv("CEILNAV_TRACE");
    if (trace != nullptr && *trace != '\0') {
      ctx_->traceEverOn(true);
    }
    top_ = std::make_unique<Top>(ctx_.get(), "TOP");
    if (trace != nullptr && *trace != '\0') {
      std::string path = trace;
      if (const size_t at = path.find("%n"); at != std::string::npos) {
        path.replace(at, 2, name_);
      }
      fst_ = std::make_unique<VerilatedFstC>();
      top_->trace(fst_.get(), 99);
      fst_->open(path.c_str());
    }
    // Printed first so that a failing RTL assertion ($stop) still shows it.
    std::printf("[cosim] %s: seed %llu (rerun with CEILNAV_COSIM_SEED=%llu)\n", name_.c_str(),
                static_cast<unsigned long long>(seed_), static_cast<unsigned long long>(seed_));
    std::fflush(stdout);
    top_->clk_i = 0;
    top_->rst_ni = 1;
    top_->eval();
    async_reset();
  }

  ~Cosim() {
    top_->final();
    if (fst_) {
      fst_->close();
    }
    write_coverage();
  }

  Cosim(const Cosim&) = delete;
  Cosim& operator=(const Cosim&) = delete;

  Top& dut() { return *top_; }
  VerilatedContext& ctx() { return *ctx_; }
  uint64_t seed() const { return seed_; }
  uint64_t cycle() const { return cycle_; }  // rising edges so far
  uint64_t checks() const { return checks_; }
  bool failed() const { return failed_; }

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

  // Reset: rst_ni held low across one rising edge (the flops reset
  // synchronously; the C++ model's reset() stands for that edge).
  void async_reset() {
    top_->rst_ni = 0;
    edge();
    top_->rst_ni = 1;
    top_->eval();
    dump(cycle_ * kPeriodTicks + 2);
  }

  // Compares one output port; the first mismatch fails the test with the
  // cycle, the port, both values and the seed. Returns true while all match.
  template <class R, class M>
  bool check(const char* port, R rtl, M model) {
    static_assert(std::is_integral_v<R> && std::is_integral_v<M>);
    ++checks_;
    const auto rtl_value = static_cast<uint64_t>(rtl);
    const auto model_value = static_cast<uint64_t>(model);
    if (rtl_value == model_value) {
      return true;
    }
    if (!failed_) {
      failed_ = true;
      std::ostringstream msg;
      msg << name_ << ": mismatch at cycle " << cycle_ << " on port " << port << ": rtl=0x"
          << std::hex << rtl_value << " model=0x" << model_value << std::dec << " (seed " << seed_
          << "; rerun with CEILNAV_COSIM_SEED=" << seed_ << ")";
      ADD_FAILURE() << msg.str();
    }
    return false;
  }

  // Prints what was compared (for the soak logs and the report).
  void report() const {
    std::printf("[cosim] %s: seed %llu, %llu cycles, %llu port comparisons\n", name_.c_str(),
                static_cast<unsigned long long>(seed_), static_cast<unsigned long long>(cycle_),
                static_cast<unsigned long long>(checks_));
  }

  // Fails the test with a message that carries the seed (stimulus errors).
  void fail(const std::string& what) {
    if (!failed_) {
      failed_ = true;
      ADD_FAILURE() << name_ << ": " << what << " at cycle " << cycle_ << " (seed " << seed_
                    << "; rerun with CEILNAV_COSIM_SEED=" << seed_ << ")";
    }
  }

  // The coverage counters of this context, written where CEILNAV_COVERAGE_DIR
  // says (no-op in a build without coverage or without the variable).
  void write_coverage() {
#if defined(CEILNAV_RTL_COVERAGE) && CEILNAV_RTL_COVERAGE
    const char* dir = std::getenv("CEILNAV_COVERAGE_DIR");
    if (dir == nullptr || *dir == '\0') {
      return;
    }
    static int serial = 0;  // several harnesses in one test write several files
    std::string test = "harness";
    if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
      test = std::string(info->test_suite_name()) + "." + info->name();
    }
    std::replace(test.begin(), test.end(), '/', '_');
    // The seed in the name: runs of one test with several seeds add up.
    const std::string path = std::string(dir) + "/" + test + "." + name_ + ".s" +
                             std::to_string(seed_) + "." + std::to_string(serial++) + ".dat";
    ctx_->coveragep()->write(path.c_str());
#endif
  }

 private:
  void dump(uint64_t time) {
    ctx_->time(time);
    if (fst_) {
      fst_->dump(time);
    }
  }

  std::string name_;
  uint64_t seed_;
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Top> top_;
  std::unique_ptr<VerilatedFstC> fst_;
  uint64_t cycle_ = 0;
  uint64_t checks_ = 0;
  bool failed_ = false;
};

}  // namespace ceilnav::testbench
