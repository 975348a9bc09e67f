// The bench of one block's co-simulation: Cosim<Top> (the Verilated block and
// its scoreboard) and the block's C++ cycle model in lockstep, one stimulus
// record per clock edge, every output port compared after every edge (and
// after every reset). What is block specific is a small policy, Ports:
//
//   using Stim = ...;                    one clock of stimulus; it has
//                                        `bool reset_before` (a reset cycle
//                                        of both before this edge)
//   void drive(Top&, const Stim&)        the RTL's inputs
//   void clock(Model&, const Stim&)      the model's edge
//   bool compare(Cosim<Top>&, const Model&)   every output port; false at a
//                                        mismatch (may count events too)
//   void before_edge(Cosim<Top>&, Model&, const Stim&)   optional: outputs
//                                        that depend on this cycle's inputs,
//                                        transfers on this edge
//
// The Ports object lives in the bench (ports()), so it can count what the
// stimulus reached. See docs/cosim.md "The scaffolding".
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "testbench/cosim_common.hpp"

namespace ceilnav::testbench {

template <class Top, class Model, class Ports>
class BlockBench {
 public:
  using Stim = typename Ports::Stim;

  // model_args construct the model (e.g. a FIFO depth).
  template <class... ModelArgs>
  BlockBench(const std::string& name, uint64_t seed, ModelArgs&&... model_args)
      : sim_(name, seed), model_(std::forward<ModelArgs>(model_args)...) {
    compare();  // the reset state
  }

  // One clock; false after the first mismatch or RTL assertion.
  bool step(const Stim& s) {
    if (s.reset_before) {
      sim_.reset_cycle();
      model_.reset();
      if (!compare()) {
        return false;
      }
    }
    ports_.drive(sim_.dut(), s);
    if constexpr (requires { ports_.before_edge(sim_, model_, s); }) {
      ports_.before_edge(sim_, model_, s);
    }
    ports_.clock(model_, s);
    sim_.edge();
    if (sim_.ctx().gotError()) {
      sim_.fail("RTL assertion failed");
      return false;
    }
    return compare();
  }

  // Every record in order; stops at the first failure.
  bool run(const std::vector<Stim>& stim) {
    for (const Stim& s : stim) {
      if (sim_.failed() || !step(s)) {
        return false;
      }
    }
    return !sim_.failed();
  }

  Cosim<Top>& sim() { return sim_; }
  const Model& model() const { return model_; }
  Ports& ports() { return ports_; }
  const Ports& ports() const { return ports_; }
  uint64_t cycles() const { return sim_.cycle(); }
  bool failed() const { return sim_.failed(); }

 private:
  bool compare() { return ports_.compare(sim_, model_); }

  Cosim<Top> sim_;
  Model model_;
  Ports ports_;
};

}  // namespace ceilnav::testbench
