// `ceilnav pattern-accuracy --photometric-sweep`: the study under camera
// gains, offsets and vignetting the host is not told (it calibrates each
// frame from its histogram; docs/pattern.md §2 and §4).
#include <fmt/core.h>
#include <cmath>
#include <cstdio>

#include "apps/commands.hpp"
#include "apps/pattern_accuracy.hpp"

namespace ceilnav::app {

PhotometricSweepRow summarise_photometric_row(const std::vector<PatternAccuracyRow>& rows,
                                              double radius_m) {
  PhotometricSweepRow s;
  int theta_n = 0;
  for (const PatternAccuracyRow& r : rows) {
    ++s.frames;
    const double de = std::abs(r.err[3][0]), te = std::abs(r.err[3][1]);
    if (r.ok[3]) {
      ++s.posed;
      s.d_max = std::max(s.d_max, de);
      s.d_rms += de * de;
      if (r.theta >= 15.0) {
        ++theta_n;
        s.theta_max = std::max(s.theta_max, te);
        s.theta_rms += te * te;
      }
    }
    if (!r.reported_ok) continue;
    ++s.reported_ok;
    if (de > 0.3 || (r.theta >= 15.0 && te > 0.3)) ++s.wrong_ok;
    // beta where the study scores it (theta >= 15, D sin(theta) >= 1.5 R);
    // nearer the axis it hardly moves the position.
    if (std::isfinite(r.beta_err) && r.theta >= 15.0 &&
        r.d * std::sin(r.theta * kDeg) >= 1.5 * radius_m) {
      s.beta_max = std::max(s.beta_max, std::abs(r.beta_err));
    }
    s.pos_max = std::max(s.pos_max, r.pos_err);
  }
  if (s.posed > 0) s.d_rms = std::sqrt(s.d_rms / s.posed);
  if (theta_n > 0) s.theta_rms = std::sqrt(s.theta_rms / theta_n);
  return s;
}

int run_photometric_sweep(const PatternAccuracyOptions& o, const host::CameraConfig& camera,
                          const golden::pattern::PatternGeometry& g) {
  struct Setting {
    double gain, offset, vignetting;
  };
  std::vector<Setting> settings;
  for (double v : {0.0, 0.2}) {
    for (double gain : {0.8, 0.9, 1.0, 1.1, 1.2}) {
      for (double off : {-15.0, 0.0, 15.0}) settings.push_back({gain, off, v});
    }
  }
  // Beyond the calibrated range (gain 0.7 .. 1.4, offset +-25): refused.
  for (const Setting& s : std::vector<Setting>{{0.4, 0.0, 0.0},
                                               {0.6, 0.0, 0.0},
                                               {1.6, 0.0, 0.0},
                                               {1.0, 60.0, 0.0},
                                               {1.0, -40.0, 0.0},
                                               {0.5, 30.0, 0.2}}) {
    settings.push_back(s);
  }
  std::printf(
      "ceilnav pattern-accuracy --photometric-sweep: %dx%d, noise %.1f, blur %.2f px, %d random "
      "betas; host self-calibration %s\n",
      o.width, o.height, o.noise_sigma, o.blur_sigma, o.betas, o.self_calibrate ? "on" : "off");
  fmt::print("{:>5} {:>7} {:>6} | {:>8} {:>8} | {:>9} {:>9} | {:>8} {:>8} | {:>7} {:>8}\n", "gain",
             "offset", "vign", "D max %", "D rms %", "th max", "th rms", "beta max", "pos max",
             "ok", "wrong ok");
  int wrong = 0;
  for (const Setting& s : settings) {
    PatternAccuracyOptions q = o;
    q.gain = s.gain;
    q.offset_grey = s.offset;
    q.vignetting = s.vignetting;
    const PhotometricSweepRow r =
        summarise_photometric_row(measure_pattern_accuracy(q, camera, g), g.radius_m);
    wrong += r.wrong_ok;
    fmt::print(
        "{:5.2f} {:+7.1f} {:5.0f}% | {:8.3f} {:8.3f} | {:9.3f} {:9.3f} | {:8.2f} {:8.4f} | "
        "{:3d}/{:<3d} {:8d}\n",
        s.gain, s.offset, 100.0 * s.vignetting, r.d_max, r.d_rms, r.theta_max, r.theta_rms,
        r.beta_max, r.pos_max, r.reported_ok, r.frames, r.wrong_ok);
    std::fflush(stdout);
  }
  return (o.require && wrong > 0) ? 1 : 0;
}

}  // namespace ceilnav::app
