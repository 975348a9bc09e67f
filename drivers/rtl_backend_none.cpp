// Build without the Verilated RTL: `--backend rtl` reports that it is missing.
#include "drivers/rtl_backend.hpp"

namespace ceilnav::drivers {

BusFactory rtl_bus_factory() {
  return {};
}

}  // namespace ceilnav::drivers
