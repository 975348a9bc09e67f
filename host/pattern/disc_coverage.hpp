// The disc's ellipse fitted to what the device measured of it: every disc
// run's weight sum and first moment (run + one margin pixel each side) against
// the same sums predicted, pixel by pixel, for a candidate ellipse seen
// through the lens's blur, the pixel's area, the pixel noise and the coverage
// LUT's dead zones (docs/pattern.md, "coverage fit"). Uses every row the
// device reports, the top and bottom rows of the disc too, and no chord
// correction: the prediction is made over the run's own pixels.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/pattern/disc_coverage_model.hpp"
#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/pattern_pose.hpp"

namespace ceilnav::host::pattern {

// Expected weight / k of a pixel of coverage c under the model (smooth in c).
double expected_weight(double c, const DiscCoverageModel& m);
// Coverage of the unit pixel centred at signed distance d (px, > 0 outside)
// from a straight edge with unit outward normal (nx, ny), blurred by a
// Gaussian of sigma px: exact box x Gaussian integral (sigma 0: the box's
// area inside the edge).
double edge_pixel_coverage(double d, double nx, double ny, double sigma);
// cv::getGaussianKernel's weights for sigma (half width ceil(5 sigma)) from
// the centre outward; taps under kMinKernelWeight dropped and the rest
// renormalised (for sigma 0.5 the +-2 taps weigh 2.6e-4: dropping them
// halves the fit's time and moves no study frame by more than 0.01 %);
// {1} for sigma 0.
inline constexpr double kMinKernelWeight = 1e-3;
std::vector<double> pixel_kernel(double sigma);

struct CoverageFit {
  Ellipse ellipse;  // normalised coordinates, as ellipse_from_moments
  int runs = 0, iterations = 0;
  double rms_px = 0.0;  // RMS residual (area and first moment per run, px)
};
// Levenberg-Marquardt from `start` (e.g. ellipse_from_disc_runs or the
// moments' ellipse) on every run's two sums; the ellipse comes with its
// parameter covariance (Ellipse::param_cov). Runs on the image's top and
// bottom rows and runs touching its left or right edge are left out (the
// blur reflects at the border). Empty with fewer than 6 runs, when the
// ellipse degenerates or when the fit moves the outline into the runs' deep
// interiors (more than 3 px from the start: the start was not close).
std::optional<CoverageFit> fit_disc_coverage(std::span<const stream::RunRecord> disc_runs,
                                             const Ellipse& start, const DiscCoverageModel& model,
                                             const CameraModel& camera, int width, int height);

}  // namespace ceilnav::host::pattern
