// Device identification, also readable from the ID and VERSION registers
// (docs/registers.md). The C++ model's reset value of VERSION and the host
// driver's compatibility check both read these constants.
#pragma once

#include <cstdint>

namespace ceilnav {

inline constexpr uint32_t kDeviceId = 0x4345494Cu;  // "CEIL"
inline constexpr uint32_t kVersionMajor = 0;
inline constexpr uint32_t kVersionMinor = 1;
inline constexpr uint32_t kVersionPatch = 0;

// major << 16 | minor << 8 | patch
constexpr uint32_t version_word() {
  return (kVersionMajor << 16) | (kVersionMinor << 8) | kVersionPatch;
}
constexpr const char* version_string() {
  return "0.1.0";
}

}  // namespace ceilnav
