// Photometric self-calibration of a pattern frame: the camera's grey levels
// of the pattern's albedos (bar, wall, side wall, disc), i.e. its gain and
// offset as seen at the pattern, estimated from the frame's own histogram
// (the device's 256 bins of camera grey) before the class LUT and the
// coverage model are programmed from them (docs/pattern.md §2,
// "Photometric self-calibration").
//
// Model: a Lambertian pattern lit by one lamp and seen by a linear camera
// gives grey = black + scale * albedo at the pattern (black = the camera's
// black level plus its offset; scale = the lamp, the camera's gain and its
// vignetting at the pattern, which is smooth and so constant over the disc's
// few degrees), clipped by the camera to 0..255. The albedos are the
// pattern's printed ones (known); black and scale are the two unknowns.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace ceilnav::host::pattern {

// The pattern's albedos (the print's; golden::pattern::Radiometry's defaults).
struct PatternAlbedos {
  double bar = 0.0, wall = 0.18, shadow = 0.32, disc = 0.98;
};

struct PhotometryOptions {
  double noise_grey = 3.0;  // the camera's pixel noise (sigma, calibrated)
  // Where the estimate starts (the nominal camera) and how far from it the
  // calibration is trusted: scale / nominal_scale within [min_gain,
  // max_gain], |black - nominal_black| <= max_offset_grey. Beyond that the
  // frame is refused (not a wrong pose with `ok`).
  double nominal_black = 4.0, nominal_scale = 250.0;
  double min_gain = 0.7, max_gain = 1.4, max_offset_grey = 25.0;
  // Least bar/wall contrast in noise sigmas: below it the bars' ink, the
  // bar class and the wall's level are not told apart reliably.
  double min_bar_contrast_sigmas = 8.0;
  // A clipped disc leaves its contrast to the bars' and the wall's levels,
  // wall - bar = scale * albedo_wall, which the coverage LUT magnifies
  // (a_disc - a_wall) / a_wall = 4.4 times. Their error (the bars' level
  // read from cores the blur mixes with the plate, the wall's from the rim
  // and the recessed wall: up to level_error_grey together) moves the disc's
  // outline by edge_px_per_contrast times the relative contrast error (every
  // partly covered pixel's weight scales with it; measured on the study's
  // frames: 2.6 px); where that exceeds max_radius_error of the disc's radius
  // (disc_radius_px, from the class moments) the frame is refused.
  double level_error_grey = 1.2, edge_px_per_contrast = 2.6, max_radius_error = 0.002;
  double disc_radius_px = 0.0;  // 0: not known, not checked
  int min_disc_pixels = 50, min_bar_pixels = 30;
};

enum class PhotometryStatus {
  ok,
  no_disc,        // too few pixels brighter than the wall: nothing to calibrate on
  clipped,        // bars and disc both clipped: the wall's level alone, one equation
  out_of_range,   // gain or offset beyond the calibrated range
  low_contrast,   // bar/wall contrast under min_bar_contrast_sigmas
  imprecise,      // the disc clipped and too small for its contrast's precision
  inconsistent,   // the levels put more pixels in the bar class than in the wall's
  not_converged,  // the class split did not settle
};
std::string to_string(PhotometryStatus s);

struct PhotometricCalibration {
  PhotometryStatus status = PhotometryStatus::no_disc;
  double black = 0.0, scale = 0.0;  // level(albedo) = black + scale * albedo
  // What the histogram gave (NaN where not measured or clipped).
  double disc_grey = 0.0, bar_grey = 0.0, wall_grey = 0.0;
  bool disc_clipped = false, bar_clipped = false;
  int iterations = 0;
  bool ok() const { return status == PhotometryStatus::ok; }
  double level(double albedo) const { return black + scale * albedo; }
  // Relative to the nominal camera: the gain at the pattern and the offset.
  double gain(const PhotometryOptions& o) const { return scale / o.nominal_scale; }
  double offset(const PhotometryOptions& o) const { return black - o.nominal_black; }
};

// The calibration from the histogram of camera grey (docs/pattern.md). The
// wall's level, needed where the bars or the disc are clipped, is
// local_wall_grey when given (level_from_band_counts around the disc), else
// the mode of the histogram's wall class (the whole frame's wall: darker
// toward the image's corners by the lamp's falloff and the vignetting).
PhotometricCalibration calibrate_photometry(const std::array<uint32_t, 256>& histogram,
                                            const PatternAlbedos& albedos,
                                            const PhotometryOptions& options,
                                            double local_wall_grey = -1.0);

// The mean of a normal population of pixels (sigma: the camera noise) from
// its counts in two adjacent grey bands [lo, mid) and [mid, hi) of the
// camera's integer greys (a true grey rounds to the nearest): the mean whose
// band probabilities have the counts' ratio (bisection; monotone). NaN when
// either count is zero.
double level_from_band_counts(double n_low, double n_high, int lo, int mid, int hi, double sigma);

}  // namespace ceilnav::host::pattern
