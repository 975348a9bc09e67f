// The Verilated RTL as a Bus backend, when this build has it (the
// co-simulation build, CEILNAV_BUILD_COSIM=ON). Empty function otherwise.
#pragma once

#include <functional>
#include <memory>

#include "host/bus.hpp"
#include "host/sim_bus.hpp"

namespace ceilnav::app {

std::function<std::unique_ptr<host::Bus>(const host::SimBusOptions&)> rtl_bus_factory();

}  // namespace ceilnav::app
