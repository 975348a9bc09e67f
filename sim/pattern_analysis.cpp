// One pattern frame through the device and the host maths.
#include "sim/pattern_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace ceilnav::sim {
namespace gp = golden::pattern;
namespace hp = host::pattern;

namespace {

// One pass of the frame through the device programmed for `radiometry`, and
// the host's analysis of what it returns.
stream::FrameResults analyse_pass(drivers::Device& device, const cv::Mat& grey,
                                  const gp::Radiometry& radiometry, const host::CameraModel& model,
                                  const hp::PoseOptions& pose_options, PatternFrameAnalysis& a) {
  uint64_t cycles = 0;
  a.runs.clear();
  const stream::FrameResults res =
      device.process(grey, gp::device_config(grey.cols, grey.rows, radiometry), a.runs, cycles);
  ++a.passes;
  if (!res.valid) throw std::runtime_error("pattern: the device rejected the frame");
  a.moments = hp::device_moments(res.class_moments);
  a.radiometry = radiometry;
  hp::BarcodeOptions bo;
  // A bar's full ink: the wall less the bar as the camera delivers it.
  bo.bar_contrast = radiometry.observed_level(gp::PixelClass::background) -
                    radiometry.observed_level(gp::PixelClass::bar);
  bo.radius_m = pose_options.radius_m;
  bo.min_bar_run_weight = gp::bar_run_min_weight(radiometry);
  static_cast<hp::PatternAnalysis&>(a) = hp::analyse_pattern(
      a.runs, a.moments, model, grey.cols, grey.rows, pose_options, bo,
      gp::disc_coverage_model(radiometry, pose_options.noise_grey, pose_options.psf_sigma_px,
                              pose_options.blur_on_pixels));
  return res;
}

// The wall's level around the disc: the frame streams with a LUT whose
// classes are two grey bands of equal width either side of the wall level
// `w0`, no mask (no runs), and the class window on the disc's bounding box
// grown to take in the dark rim (1.1 R) but not the bars (from 1.16 R): 1.08
// x the disc's extent; the
// class moments' pixel counts in the two bands give the level
// (hp::level_from_band_counts), again about it while it moves by more than
// sigma. NaN without a disc or a level, or with one more than 5 grey + 3
// sigma from w0. docs/pattern.md.
double local_wall_level(drivers::Device& device, const cv::Mat& grey,
                        const gp::Radiometry& radiometry, const hp::ClassMoments& disc, double w0,
                        double sigma, int& passes) {
  if (disc.m00 < 50) return std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(disc.m00);
  const double cx = static_cast<double>(disc.m10) / n, cy = static_cast<double>(disc.m01) / n;
  const double sx = std::sqrt(std::max(0.0, static_cast<double>(disc.m20) / n - cx * cx));
  const double sy = std::sqrt(std::max(0.0, static_cast<double>(disc.m02) / n - cy * cy));
  constexpr double kGrow = 1.08;
  auto clamp_to = [](double v, int hi) {
    return static_cast<uint16_t>(std::clamp(static_cast<int>(std::lround(v)), 0, hi));
  };
  stream::PipelineConfig cfg = gp::device_config(grey.cols, grey.rows, radiometry);
  cfg.class_window = {
      clamp_to(cx - 2.0 * kGrow * sx, grey.cols), clamp_to(cx + 2.0 * kGrow * sx + 1.0, grey.cols),
      clamp_to(cy - 2.0 * kGrow * sy, grey.rows), clamp_to(cy + 2.0 * kGrow * sy + 1.0, grey.rows)};
  const int delta = std::max(2, static_cast<int>(std::lround(2.5 * sigma)));
  // The histogram's wall, where w0 comes from, reads at most 5 grey low
  // (20 % vignetting, §2); a level farther off than that and the noise is
  // another population (the side wall at a steep view), not the wall.
  const double start = w0, reach = 5.0 + 3.0 * sigma;
  double level = std::numeric_limits<double>::quiet_NaN();
  for (int pass = 0; pass < 3; ++pass) {
    const int mid = std::clamp(static_cast<int>(std::lround(w0)), delta, 255 - delta);
    for (int g = 0; g < 256; ++g) {
      uint8_t cls = stream::kClassBackground;
      if (g >= mid - delta && g < mid) cls = stream::kClassShadow;
      if (g >= mid && g < mid + delta) cls = stream::kClassBar;
      cfg.lut[static_cast<std::size_t>(g)] = stream::lut_entry(0, false, cls);
    }
    std::vector<stream::RunRecord> runs;
    uint64_t cycles = 0;
    const stream::FrameResults res = device.process(grey, cfg, runs, cycles);
    ++passes;
    if (!res.valid) return std::numeric_limits<double>::quiet_NaN();
    level = hp::level_from_band_counts(
        static_cast<double>(res.class_moments.of(stream::kClassShadow)[stream::kM00]),
        static_cast<double>(res.class_moments.of(stream::kClassBar)[stream::kM00]), mid - delta,
        mid, mid + delta, sigma);
    if (!std::isfinite(level) || std::abs(level - start) > reach) {
      return std::numeric_limits<double>::quiet_NaN();
    }
    if (std::abs(level - mid) <= sigma) break;
    w0 = level;
  }
  return level;
}

void mark_uncalibrated(PatternFrameAnalysis& a) {
  for (hp::PatternPose* p : {&a.conic, &a.moment, &a.projection, &a.conic_bars}) {
    p->status = hp::PatternStatus::uncalibrated;
  }
  if (a.code.status == hp::PatternStatus::ok) a.code.status = hp::PatternStatus::uncalibrated;
}

}  // namespace

hp::PhotometryOptions photometry_options_for(const gp::Radiometry& r, double noise_grey) {
  hp::PhotometryOptions o;
  o.noise_grey = noise_grey;
  o.nominal_black = r.black_level;
  o.nominal_scale = r.gain;
  return o;
}

gp::Radiometry calibrated_radiometry(const gp::Radiometry& nominal,
                                     const hp::PhotometricCalibration& c) {
  gp::Radiometry r = nominal;
  r.black_level = c.black;
  r.gain = c.scale;
  return r;
}

PatternFrameAnalysis analyse_pattern_frame(drivers::Device& device, const cv::Mat& grey,
                                           const gp::Radiometry& radiometry,
                                           const host::CameraModel& model,
                                           const hp::PoseOptions& pose_options,
                                           bool self_calibrate) {
  PatternFrameAnalysis a;
  const stream::FrameResults first = analyse_pass(device, grey, radiometry, model, pose_options, a);
  if (!self_calibrate) return a;
  const gp::Radiometry nominal = radiometry;
  hp::PatternAlbedos albedos;
  albedos.bar = nominal.albedo_bar;
  albedos.wall = nominal.albedo_wall;
  albedos.shadow = nominal.albedo_shadow;
  albedos.disc = nominal.albedo_disc;
  hp::PhotometryOptions po = photometry_options_for(nominal, pose_options.noise_grey);
  po.disc_radius_px = std::sqrt(static_cast<double>(a.moments[hp::kDisc].m00) / std::numbers::pi);
  hp::PhotometricCalibration cal = hp::calibrate_photometry(first.histogram.bins, albedos, po);
  if (cal.status != hp::PhotometryStatus::no_disc) {
    // The wall's level around the disc (its edge lies between the two).
    const double sigma = std::max(0.5, pose_options.noise_grey);
    const double wall = local_wall_level(device, grey, nominal, a.moments[hp::kDisc],
                                         cal.level(albedos.wall), sigma, a.passes);
    if (std::isfinite(wall))
      cal = hp::calibrate_photometry(first.histogram.bins, albedos, po, wall);
  }
  if (cal.status == hp::PhotometryStatus::no_disc &&
      a.moments[hp::kDisc].m00 < pose_options.min_disc_pixels) {
    a.photometry = cal;
    return a;  // nothing brighter than the wall: no pose either way
  }
  if (cal.ok()) {
    const gp::Radiometry calibrated = calibrated_radiometry(nominal, cal);
    try {
      gp::device_config(grey.cols, grey.rows, calibrated);  // levels the device can take
    } catch (const std::invalid_argument&) {
      cal.status = hp::PhotometryStatus::low_contrast;
    }
    if (cal.ok()) {
      PatternFrameAnalysis b;
      b.passes = a.passes;
      analyse_pass(device, grey, calibrated, model, pose_options, b);
      b.photometry = cal;
      return b;
    }
  }
  a.photometry = cal;
  mark_uncalibrated(a);
  return a;
}

hp::PoseOptions pose_options_for(const gp::PatternGeometry& g) {
  hp::PoseOptions o;
  o.radius_m = g.radius_m;
  o.thickness_m = g.thickness_m;
  o.rim_m = g.rim_m;
  return o;
}

}  // namespace ceilnav::sim
