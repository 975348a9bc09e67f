// The disc's runs told from the bars' and the disc's ellipse from the
// sub-pixel outline of its runs (docs/pattern.md §2, sub-pixel outline).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/class_moments.hpp"
#include "host/pattern/ellipse_from_moments.hpp"

namespace ceilnav::host::pattern {

// With the coverage LUT (golden::pattern::bar_mask_lut) the disc's runs weigh
// their chords: they are told from the bars' by position. A run is the
// disc's when its midpoint lies inside the disc class's moment ellipse
// (pixel coordinates, 1.1 x its size); the bars start 4 cm beyond the disc.
// Splits runs into (disc runs, other runs); no disc class -> all are other.
std::pair<std::vector<stream::RunRecord>, std::vector<stream::RunRecord>> split_disc_runs(
    std::span<const stream::RunRecord> runs, const ClassMoments& disc);

// The disc's ellipse (normalised) from the sub-pixel outline of its runs
// (docs/pattern.md §2, sub-pixel outline): per row the chord sum_w / k (k =
// golden::pattern::disc_coverage_weight), the left edge solving
// sum_xw / k = integral of round(x) over the chord, less the strip-average
// bias of the chord (pixel rows and the lens's Gaussian blur psf_sigma_px:
// chord'' (1/24 + sigma^2/2)); rows within 1 px of the ellipse's top and bottom and
// runs at the image border are left out. The edge points go through the
// camera model and a conic is fitted (algebraic, Sampson-reweighted). Empty
// when fewer than 24 rows remain (a flat disc: the moments are better) or
// the fit is not an ellipse.
std::optional<Ellipse> ellipse_from_disc_runs(std::span<const stream::RunRecord> disc_runs,
                                              const ClassMoments& disc, uint32_t k, int width,
                                              double psf_sigma_px, const CameraModel& camera);

}  // namespace ceilnav::host::pattern
