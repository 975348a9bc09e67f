// Evidence that the disc class's runs are the image of one filled ellipse
// before the coverage fit is run on them (docs/pattern.md, "Bounded time on
// real frames"). On frames without the pattern the disc class is whatever is
// bright (lamps, windows, paper); its runs then reach far from the moments'
// ellipse and the fit, which evaluates every pixel it cannot place deep
// inside, cost up to a second a frame. The check looks only at the runs' two
// ends, stops at the first evidence against, and so costs at most one
// undistortion per run end.
#pragma once

#include <span>

#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/ellipse_from_moments.hpp"

namespace ceilnav::host::pattern {

// A run end (its first or last pixel centre) of a disc that `start`
// describes lies within this distance (px) of start's outline: half a pixel
// for the end pixel's centre, one margin pixel, the blur, and the 3 px by
// which fit_disc_coverage lets the outline move from its start.
inline constexpr double kRunEndTolerancePx = 5.0;
// More than this many disc runs per row spanned: not one convex region.
inline constexpr double kMaxDiscRunsPerRow = 1.1;

// True when the disc runs are one convex region's: at most
// kMaxDiscRunsPerRow runs per row spanned (plus 2) and no more runs than the
// image has rows. Bounds the sub-pixel outline's work (linear in the runs).
bool one_run_per_row(std::span<const stream::RunRecord> disc_runs, int height);

// True when one_run_per_row holds and every disc run not touching the
// image's border has both ends within kRunEndTolerancePx of start's outline
// (in pixels, through the lens's Jacobian). Bounds the coverage fit's work:
// a run's pixels farther inside than the fit's reach are not evaluated, so
// each run costs at most a few pixels' coverage per iteration.
bool runs_fit_ellipse(std::span<const stream::RunRecord> disc_runs, const Ellipse& start,
                      const CameraModel& camera, int width, int height);

}  // namespace ceilnav::host::pattern
