// The Verilated RTL top (rtl_model/ceilnav_top.sv) as a SimDevice, so the one
// Driver runs on it through SimBus exactly as on the C++ model (ModelBus): the
// full configuration (Vceilnav_top), the tape one (Vceilnav_top_tape) or the
// homing one (Vceilnav_top_homing), each built with the configuration's
// parameters, as SimBusOptions::device_config says.
#include <cstdint>
#include <memory>

#include "drivers/verilated_top.hpp"

CEILNAV_VERILATOR_HEADERS_BEGIN
#include "Vceilnav_top.h"
#include "Vceilnav_top_homing.h"
#include "Vceilnav_top_tape.h"
CEILNAV_VERILATOR_HEADERS_END

#include <cstring>
#include <stdexcept>
#include <string>

#include "ceilnav/regs.hpp"
#include "drivers/rtl_backend.hpp"
#include "drivers/verilated_device.hpp"

namespace ceilnav::drivers {

BusFactory rtl_bus_factory() {
  return [](const SimBusOptions& options) -> std::unique_ptr<SimBus> {
    const regs::Config& c = options.device_config;
    const auto is = [&c](const regs::Config& k) {
      return c.has_class_moments == k.has_class_moments && c.has_corridor == k.has_corridor &&
             c.has_orientation == k.has_orientation;
    };
    if (is(regs::kConfigFull)) {
      return std::make_unique<SimBus>(
          std::make_unique<OwnedVerilatedDevice<Vceilnav_top>>(options.seed), options);
    }
    if (is(regs::kConfigTape)) {
      return std::make_unique<SimBus>(
          std::make_unique<OwnedVerilatedDevice<Vceilnav_top_tape>>(options.seed), options);
    }
    if (is(regs::kConfigHoming)) {
      return std::make_unique<SimBus>(
          std::make_unique<OwnedVerilatedDevice<Vceilnav_top_homing>>(options.seed), options);
    }
    throw std::runtime_error(std::string("no Verilated top for configuration ") + c.name);
  };
}

}  // namespace ceilnav::drivers
