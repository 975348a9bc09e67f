// Shared co-simulation harness: one Verilated top against a C++ cycle model.
// Cosim<Top> = VerilatedTop<Top, FstTrace> (clock and reset protocol,
// drivers/verilated_top.hpp) + Scoreboard (testbench/scoreboard.hpp); the
// test sets the inputs of both the RTL and the C++ model before each edge();
// the model's reset() stands for reset_cycle()'s edge. See docs/cosim.md
// "The scaffolding".
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

#include "drivers/verilated_top.hpp"
#include "testbench/fst_trace.hpp"
#include "testbench/scoreboard.hpp"

#if defined(CEILNAV_RTL_COVERAGE) && CEILNAV_RTL_COVERAGE
CEILNAV_VERILATOR_HEADERS_BEGIN
#include "verilated_cov.h"
CEILNAV_VERILATOR_HEADERS_END
#endif

namespace ceilnav::testbench {

using drivers::VerilatedTop;

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

// The co-simulation harness: one Verilated top (VerilatedTop with the FST
// trace policy) and the scoreboard its outputs are compared on.
template <class Top>
class Cosim {
 public:
  static constexpr uint64_t kPeriodTicks = VerilatedTop<Top, FstTrace>::kPeriodTicks;

  // The scoreboard first: it prints the seed before the model runs.
  Cosim(const std::string& name, uint64_t seed) : board_(name, seed), top_(seed, name) {
    top_.reset_cycle();
  }

  ~Cosim() { write_coverage(); }

  Cosim(const Cosim&) = delete;
  Cosim& operator=(const Cosim&) = delete;

  Top& dut() { return top_.dut(); }
  VerilatedContext& ctx() { return top_.ctx(); }
  Scoreboard& board() { return board_; }
  uint64_t seed() const { return board_.seed(); }
  uint64_t cycle() const { return top_.cycle(); }  // rising edges so far
  uint64_t checks() const { return board_.checks(); }
  bool failed() const { return board_.failed(); }

  void edge() { top_.edge(); }
  void reset_cycle() { top_.reset_cycle(); }

  // Compares one output port (Scoreboard::check at this cycle).
  template <class R, class M>
  bool check(const char* port, R rtl, M model) {
    return board_.check(top_.cycle(), port, rtl, model);
  }
  void fail(const std::string& what) { board_.fail(top_.cycle(), what); }
  void report() const { board_.report(top_.cycle()); }

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
    const std::string path = std::string(dir) + "/" + test + "." + board_.name() + ".s" +
                             std::to_string(board_.seed()) + "." + std::to_string(serial++) +
                             ".dat";
    top_.ctx().coveragep()->write(path.c_str());
#endif
  }

 private:
  Scoreboard board_;
  VerilatedTop<Top, FstTrace> top_;
};

}  // namespace ceilnav::testbench
