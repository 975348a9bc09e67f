// ceilnav::fp — bit-true fixed-point and integer types (front header).
// See docs/fixedpoint.md for formats, widening rules and rounding/overflow.
#pragma once

#include "fixedpoint/arith.hpp"       // + - * and += -= *=
#include "fixedpoint/compare.hpp"     // == <=> across formats
#include "fixedpoint/convert.hpp"     // convert<Target>(x)
#include "fixedpoint/fixed_type.hpp"  // Fixed, UInt, Int, FixedPoint
#include "fixedpoint/overflow.hpp"    // Overflow
#include "fixedpoint/rounding.hpp"    // Rounding
