#pragma once
#include <cstdint>
namespace ceilnav {
// Device identification, also readable from the ID/VERSION registers.
inline constexpr uint32_t kDeviceId = 0x4345494Cu;  // "CEIL"
uint32_t version_word();                            // major << 16 | minor << 8 | patch
const char* version_string();
}  // namespace ceilnav
