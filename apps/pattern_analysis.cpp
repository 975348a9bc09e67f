// One pattern frame through the device and the host maths.
#include "apps/pattern_analysis.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace ceilnav::app {
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
  const stream::FrameResults first =
      analyse_pass(device, grey, radiometry, model, pose_options, a);
  if (!self_calibrate) return a;
  const gp::Radiometry nominal = radiometry;
  hp::PatternAlbedos albedos;
  albedos.bar = nominal.albedo_bar;
  albedos.wall = nominal.albedo_wall;
  albedos.shadow = nominal.albedo_shadow;
  albedos.disc = nominal.albedo_disc;
  hp::PhotometricCalibration cal = hp::calibrate_photometry(
      first.histogram.bins, albedos, photometry_options_for(nominal, pose_options.noise_grey));
  if (std::getenv("CEILNAV_PHOTO_DEBUG")) {
    std::fprintf(stderr, "cal %s black %.2f scale %.2f disc %.1f bar %.1f wall %.1f shadow %.1f clip %d%d it %d\n",
                 hp::to_string(cal.status).c_str(), cal.black, cal.scale, cal.disc_grey, cal.bar_grey,
                 cal.wall_grey, cal.shadow_grey, cal.disc_clipped, cal.bar_clipped, cal.iterations);
  }
  if (cal.status == hp::PhotometryStatus::no_disc) {
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

}  // namespace ceilnav::app
