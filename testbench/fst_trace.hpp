// The trace policy of the co-simulation builds (VerilatedTop's Trace): an FST
// wave file when CEILNAV_TRACE=<file.fst> is set ("%n" in the name becomes the
// harness name, one file per harness), nothing otherwise. The Verilated model
// must be built with TRACE_FST.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include "drivers/verilated_top.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "verilated_fst_c.h"
CEILNAV_VERILATOR_HEADERS_END

namespace ceilnav::testbench {

class FstTrace {
 public:
  // Trace must be switched on before the model is built.
  void before_model(VerilatedContext& ctx) {
    const char* path = std::getenv("CEILNAV_TRACE");
    if (path != nullptr && *path != '\0') {
      path_ = path;
      ctx.traceEverOn(true);
    }
  }

  template <class Top>
  void after_model(Top& top, const std::string& name) {
    if (path_.empty()) {
      return;
    }
    if (const size_t at = path_.find("%n"); at != std::string::npos) {
      path_.replace(at, 2, name);
    }
    fst_ = std::make_unique<VerilatedFstC>();
    top.trace(fst_.get(), 99);
    fst_->open(path_.c_str());
  }

  void dump(uint64_t time) {
    if (fst_) {
      fst_->dump(time);
    }
  }

  void close() {
    if (fst_) {
      fst_->close();
    }
  }

 private:
  std::string path_;
  std::unique_ptr<VerilatedFstC> fst_;
};

}  // namespace ceilnav::testbench
