// Build without the Verilated RTL: `--backend rtl` reports that it is missing.
#include "apps/rtl_backend.hpp"

namespace ceilnav::app {

std::function<std::unique_ptr<host::Bus>(const host::SimBusOptions&)> rtl_bus_factory() {
  return {};
}

}  // namespace ceilnav::app
