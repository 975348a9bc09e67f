// Frame-size limits of the device, from fixedpoint/datapath.hpp (where every
// accumulator width of the stream blocks is derived, with its proof).
#pragma once

#include <cstdint>

#include "fixedpoint/datapath.hpp"

namespace ceilnav::stream {

using fp::datapath::bits_for;
using fp::datapath::kCoordBits;  // x in [0, 2047], y in [0, 2047]
using fp::datapath::kMaxHeight;  // lines per frame
using fp::datapath::kMaxWidth;   // pixels per line
using fp::datapath::kPixelBits;

}  // namespace ceilnav::stream
