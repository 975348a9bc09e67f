// Seed 004's FindOrientation on the host: the major orientation of an image
// from its folded orientation histogram (the orientation block's readout,
// or golden::orientation_histogram_ref's), in the image's angles (u right,
// v down: clockwise positive on the screen). docs/homing.md, "Orientation".
#pragma once

#include <span>

namespace ceilnav::host::homing {

// The peak of a histogram folded modulo 90 deg (bin k centred on k x 90 /
// bins degrees): the largest bin (ties: the lowest), refined to the
// centroid of it and the two bins on each side (circular), in degrees in
// [-45, 45) (the seed's gamma'); NaN for an empty histogram.
double major_orientation_deg(std::span<const double> histogram);

// a - b folded into [-45, 45) degrees: two major orientations' difference.
double orientation_difference_deg(double a_deg, double b_deg);

}  // namespace ceilnav::host::homing
