// ModelBus: the SimBus on the C++ cycle model of the device (CeilnavTop).
#pragma once

#include <cstdint>

#include "ceilnav/regs.hpp"
#include "drivers/sim_bus.hpp"
#include "stream/ceilnav_top.hpp"

namespace ceilnav::drivers {

class ModelBus : public SimBus {
 public:
  explicit ModelBus(const SimBusOptions& options = {},
                    uint32_t run_fifo_depth = regs::kRunFifoDepth);

  const stream::CeilnavTop& top() const { return *top_; }

 private:
  const stream::CeilnavTop* top_;
};

}  // namespace ceilnav::drivers
