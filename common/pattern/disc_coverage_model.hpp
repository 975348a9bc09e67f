// The model of how the pattern's coverage LUT weighs a disc pixel. The host's
// coverage fit (host/pattern/disc_coverage.hpp) predicts run weights with it,
// and the golden pattern (golden::pattern::disc_coverage_model) states it for
// the LUT it builds: it lives in common/ so that golden needs nothing of the
// host, in the host's namespace that owns the fit.
#pragma once

#include <cstdint>

namespace ceilnav::host::pattern {

// How a pixel's disc coverage c (0..1, after the blur) becomes its run
// weight: grey = wall + c * contrast + noise; the LUT gives weight / k =
// (wall - grey) / k below the wall (the dark side's ink), 0 up to
// dead_lo, c up to dead_hi and 1 from there (golden::pattern::bar_mask_lut).
struct DiscCoverageModel {
  uint32_t k = 0;           // run weight of a fully covered pixel
  double contrast = 0.0;    // disc grey - wall grey
  double dead_lo = 0.0;     // coverage below this weighs nothing
  double dead_hi = 1.0;     // coverage from this weighs 1
  double noise_grey = 0.0;  // the camera's pixel noise (sigma, grey levels; calibrated)
  // The camera's blur (calibrated), one of two forms: a continuous Gaussian
  // PSF before the pixels integrate (psf_sigma_px > 0), or a Gaussian kernel
  // over pixel values after they do (kernel_sigma_px > 0: cv::GaussianBlur's
  // sampled kernel, half width ceil(5 sigma); the renderer's form,
  // golden::finish_render). Both 0: no blur.
  double psf_sigma_px = 0.0;
  double kernel_sigma_px = 0.0;
};

}  // namespace ceilnav::host::pattern
