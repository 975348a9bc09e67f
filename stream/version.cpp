#include "stream/version.hpp"

namespace ceilnav {
uint32_t version_word() {
  return (0u << 16) | (1u << 8) | 0u;
}
const char* version_string() {
  return "0.1.0";
}
}  // namespace ceilnav
