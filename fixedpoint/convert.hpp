// Resizing / requantising between fixed-point types.
#pragma once

#include "fixedpoint/fixed_type.hpp"
#include "fixedpoint/quantise.hpp"

namespace ceilnav::fp {

// x's exact value into Target: Target's rounding on the dropped fractional
// bits, then Target's overflow on the result.
template <FixedPoint Target, FixedPoint Source>
constexpr Target convert(const Source& x) {
  return Target::from_raw(static_cast<typename Target::raw_type>(
      detail::requantise(static_cast<detail::i128>(x.raw()), Source::frac, Target::format)));
}

}  // namespace ceilnav::fp
