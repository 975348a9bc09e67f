// The scoreboard of a co-simulation: counts every port comparison of RTL
// against the C++ model and fails the running GoogleTest at the first
// mismatch with the cycle, the port, both values and the seed to rerun with.
// Later mismatches are counted but not reported (they follow from the first).
#pragma once

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

namespace ceilnav::testbench {

class Scoreboard {
 public:
  // Prints the seed at once, so that a failing RTL assertion ($stop) still
  // shows it.
  Scoreboard(const std::string& name, uint64_t seed) : name_(name), seed_(seed) {
    std::printf("[cosim] %s: seed %llu (rerun with CEILNAV_COSIM_SEED=%llu)\n", name_.c_str(),
                static_cast<unsigned long long>(seed_), static_cast<unsigned long long>(seed_));
    std::fflush(stdout);
  }

  const std::string& name() const { return name_; }
  uint64_t seed() const { return seed_; }
  uint64_t checks() const { return checks_; }
  bool failed() const { return failed_; }

  // Compares one output port at `cycle`. Returns true while all match.
  template <class R, class M>
  bool check(uint64_t cycle, const char* port, R rtl, M model) {
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
      msg << name_ << ": mismatch at cycle " << cycle << " on port " << port << ": rtl=0x"
          << std::hex << rtl_value << " model=0x" << model_value << std::dec << " (seed " << seed_
          << "; rerun with CEILNAV_COSIM_SEED=" << seed_ << ")";
      ADD_FAILURE() << msg.str();
    }
    return false;
  }

  // Fails the test with a message that carries the seed (stimulus errors,
  // independent checks against a reference).
  void fail(uint64_t cycle, const std::string& what) {
    if (!failed_) {
      failed_ = true;
      ADD_FAILURE() << name_ << ": " << what << " at cycle " << cycle << " (seed " << seed_
                    << "; rerun with CEILNAV_COSIM_SEED=" << seed_ << ")";
    }
  }

  // What was compared (for the soak logs and the report).
  void report(uint64_t cycles) const {
    std::printf("[cosim] %s: seed %llu, %llu cycles, %llu port comparisons\n", name_.c_str(),
                static_cast<unsigned long long>(seed_), static_cast<unsigned long long>(cycles),
                static_cast<unsigned long long>(checks_));
  }

 private:
  std::string name_;
  uint64_t seed_;
  uint64_t checks_ = 0;
  bool failed_ = false;
};

}  // namespace ceilnav::testbench
