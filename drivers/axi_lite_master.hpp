// A clocked AXI4-Lite master: one transaction at a time, with random valid
// delays and ready stalls. The simulation bus (SimBus) and the
// testbenches drive the register top's s_axil port with it.
#pragma once

#include <cstdint>
#include <stdexcept>

#include "stream/axi_lite.hpp"

namespace ceilnav::drivers {

using stream::AxiLiteIn;
using stream::AxiLiteOut;

class AxiLiteMaster {
 public:
  struct Timing {
    double valid_delay_probability = 0.0;  // per cycle: keep a valid low one more cycle
    double ready_low_probability = 0.0;    // per cycle: hold bready/rready low
  };

  explicit AxiLiteMaster(uint64_t seed = 1) : rng_state_(seed) {}
  AxiLiteMaster(uint64_t seed, const Timing& timing) : rng_state_(seed), timing_(timing) {}

  void set_timing(const Timing& timing) { timing_ = timing; }

  void start_write(uint32_t addr, uint32_t data, uint8_t strb = 0xF) {
    require_idle();
    op_ = Op::kWrite;
    addr_ = addr;
    data_ = data;
    strb_ = strb;
    aw_done_ = w_done_ = aw_on_ = w_on_ = done_ = false;
  }
  void start_read(uint32_t addr) {
    require_idle();
    op_ = Op::kRead;
    addr_ = addr;
    ar_done_ = ar_on_ = done_ = false;
  }
  bool idle() const { return op_ == Op::kNone; }
  // The last transaction completed (response received).
  bool done() const { return done_; }
  uint32_t rdata() const { return rdata_; }
  uint8_t resp() const { return resp_; }

  // The master's outputs for the coming edge. Call once per cycle, before edge().
  const AxiLiteIn& drive() {
    in_ = AxiLiteIn{};
    if (op_ == Op::kWrite) {
      // A valid, once raised, stays high until its handshake (AXI rule).
      if (!aw_done_) aw_on_ = aw_on_ || !chance(timing_.valid_delay_probability);
      if (!w_done_) w_on_ = w_on_ || !chance(timing_.valid_delay_probability);
      in_.awvalid = !aw_done_ && aw_on_;
      in_.awaddr = in_.awvalid ? addr_ : 0u;
      in_.wvalid = !w_done_ && w_on_;
      in_.wdata = in_.wvalid ? data_ : 0u;
      in_.wstrb = in_.wvalid ? strb_ : uint8_t{0xF};
      in_.bready = !chance(timing_.ready_low_probability);
    } else if (op_ == Op::kRead) {
      if (!ar_done_) ar_on_ = ar_on_ || !chance(timing_.valid_delay_probability);
      in_.arvalid = !ar_done_ && ar_on_;
      in_.araddr = in_.arvalid ? addr_ : 0u;
      in_.rready = !chance(timing_.ready_low_probability);
    }
    return in_;
  }

  // The clock edge: handshakes of the driven inputs with the slave's pre-edge
  // outputs. Throws std::logic_error on a response nobody asked for.
  void edge(const AxiLiteOut& s) {
    if (s.bvalid && in_.bready && !(op_ == Op::kWrite && aw_done_ && w_done_)) {
      throw std::logic_error("AxiLiteMaster: unexpected B response");
    }
    if (s.rvalid && in_.rready && !(op_ == Op::kRead && ar_done_)) {
      throw std::logic_error("AxiLiteMaster: unexpected R response");
    }
    if (op_ == Op::kWrite) {
      const bool b = aw_done_ && w_done_ && s.bvalid && in_.bready;
      aw_done_ = aw_done_ || (in_.awvalid && s.awready);
      w_done_ = w_done_ || (in_.wvalid && s.wready);
      if (b) finish(0, s.bresp);
    } else if (op_ == Op::kRead) {
      const bool r = ar_done_ && s.rvalid && in_.rready;
      ar_done_ = ar_done_ || (in_.arvalid && s.arready);
      if (r) finish(s.rdata, s.rresp);
    }
  }

 private:
  enum class Op : uint8_t { kNone, kRead, kWrite };

  void require_idle() const {
    if (op_ != Op::kNone) throw std::logic_error("AxiLiteMaster: transaction in progress");
  }
  void finish(uint32_t rdata, uint8_t resp) {
    rdata_ = rdata;
    resp_ = resp;
    done_ = true;
    op_ = Op::kNone;
  }
  // splitmix64: the same delay pattern for a seed on every platform.
  uint64_t next() {
    uint64_t z = (rng_state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  bool chance(double p) {
    if (p <= 0.0) return false;
    return static_cast<double>(next() >> 11) * 0x1.0p-53 < p;
  }

  uint64_t rng_state_;
  Timing timing_;
  Op op_ = Op::kNone;
  uint32_t addr_ = 0;
  uint32_t data_ = 0;
  uint8_t strb_ = 0xF;
  bool aw_done_ = false, w_done_ = false, ar_done_ = false;
  bool aw_on_ = false, w_on_ = false, ar_on_ = false;
  bool done_ = false;
  uint32_t rdata_ = 0;
  uint8_t resp_ = 0;
  AxiLiteIn in_{};
};

}  // namespace ceilnav::drivers
