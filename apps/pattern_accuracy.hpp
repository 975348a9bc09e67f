// `ceilnav pattern-accuracy`: the error study of the pattern pose on rendered
// frames (seed 003 Tables I and II; docs/pattern.md). The study renders and
// measures (pattern_accuracy.cpp); its statistics, tables, CSV and chart are
// in pattern_accuracy_report.cpp.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "apps/pattern_commands.hpp"
#include "common/camera_config.hpp"
#include "golden/pattern/pattern.hpp"

namespace ceilnav::app {

// The pose methods compared, in the order of PatternAccuracyRow's arrays.
inline constexpr int kPatternMethods = 4;  // projection, moment, conic, conic+bars

// One rendered frame of the study.
struct PatternAccuracyRow {
  double d, theta, beta;
  bool seed_set;                   // beta = +-90 deg (the seed's experiments)
  double err[kPatternMethods][2];  // method x (D %, theta deg)
  bool ok[kPatternMethods];        // the method found a pose of the disc in view
  bool beta_ok[kPatternMethods];
  bool code_visible;
  double bar_px;
  int identity, read;
  std::string code_status;
  // conic+bars: beta error (deg, where resolved; else NaN), camera position
  // error in the pattern frame (m); the frame as `ceilnav pattern` would
  // report it: code read and pose ok (reported_ok).
  double beta_err, pos_err;
  bool reported_ok;
};

// Renders and measures every frame of the study: D in {1, 1.5, 2, 3, 4, 5} m,
// theta = 0, 7.5 .. 75 deg, beta = +-90 deg and o.betas random co-azimuths.
std::vector<PatternAccuracyRow> measure_pattern_accuracy(const PatternAccuracyOptions& o,
                                                         const host::CameraConfig& camera,
                                                         const golden::pattern::PatternGeometry& g);

// The study's figures over its rows.
struct PatternAccuracyStats {
  // theta (deg) or D (m) -> max |error| of each method (theta deg / D %; the
  // projection over beta = +-90 only) and [4] the conic+bars sum of squares.
  std::map<double, std::array<double, 5>> by_theta, by_d;
  // [0]: conic+bars frames behind the sum of squares.
  std::map<double, std::array<int, 2>> counts_theta, counts_d;
  bool bars_ok = true;                            // conic+bars found a pose on every frame
  double conic_d_max = 0, conic_theta_max15 = 0;  // conic+bars, max |D err| %, |theta err| >= 15
  int beta_frames = 0;                            // theta >= 15, D sin(theta) >= 1.5 R
  std::array<int, kPatternMethods> beta_resolved{};
  int visible = 0, visible_read = 0, wrong = 0, visible_thin = 0;  // bar code reads

  // The bars of docs/pattern.md: D <= 0.3 %, theta <= 0.3 deg (theta >= 15),
  // every fully visible code read, no wrong identity.
  bool identity_ok() const { return wrong == 0 && visible_read == visible; }
  bool pass() const {
    return bars_ok && conic_d_max <= 0.3 && conic_theta_max15 <= 0.3 && identity_ok();
  }
};
PatternAccuracyStats summarise_pattern_accuracy(const std::vector<PatternAccuracyRow>& rows,
                                                double radius_m);

// One row of the photometric sweep (docs/pattern.md): the camera's gain,
// offset and vignetting, and over the frames with a conic+bars pose the max
// and RMS of the D error (%) and of the theta error (deg, theta >= 15), the
// max beta error (deg, where resolved with theta >= 15 and D sin(theta) >=
// 1.5 R, as the study scores beta) and position error (m), the fraction
// of frames reported ok, and the frames reported ok with a D error over
// 0.3 % or a theta error (theta >= 15) over 0.3 deg.
struct PhotometricSweepRow {
  double gain = 1.0, offset = 0.0, vignetting = 0.0;
  int frames = 0, posed = 0, reported_ok = 0, wrong_ok = 0;
  double d_max = 0, d_rms = 0, theta_max = 0, theta_rms = 0, beta_max = 0, pos_max = 0;
};
PhotometricSweepRow summarise_photometric_row(const std::vector<PatternAccuracyRow>& rows,
                                              double radius_m);
// The sweep: gain 0.8 .. 1.2 x offset -15, 0, +15 x vignetting 0, 20 %, then
// rows beyond the calibrated range; printed as a table.
int run_photometric_sweep(const PatternAccuracyOptions& o, const host::CameraConfig& camera,
                          const golden::pattern::PatternGeometry& g);

// The tables and the verdict on stdout.
void print_pattern_accuracy(const PatternAccuracyOptions& o, size_t frames,
                            const PatternAccuracyStats& st);
// The per-frame CSV: the errors of each method (empty where it found no pose)
// and whether beta came out right.
void write_pattern_accuracy_csv(const std::filesystem::path& path,
                                const std::vector<PatternAccuracyRow>& rows);
// The error curves against the seed's Tables I and II and its bounds (eq. 48, 55).
void plot_pattern_accuracy(const std::filesystem::path& png, const PatternAccuracyStats& st,
                           const host::CameraConfig& camera,
                           const golden::pattern::PatternGeometry& g);

// --swing-height: seed 003's swing (eq. 57-66, 70) and sensor height (eq. 69)
// error analysis against rendered frames, as Markdown tables on stdout.
int run_pattern_swing_height_study(const PatternAccuracyOptions& o);

}  // namespace ceilnav::app
