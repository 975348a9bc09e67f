// The Verilated RTL as a simulation bus backend, when this build has it (the
// co-simulation build, CEILNAV_BUILD_COSIM=ON: library ceilnav_drivers_rtl).
// Without it the factory is empty, and callers report that the backend is
// missing.
#pragma once

#include "drivers/device.hpp"

namespace ceilnav::drivers {

BusFactory rtl_bus_factory();

}  // namespace ceilnav::drivers
