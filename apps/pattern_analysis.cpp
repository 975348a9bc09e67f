// One pattern frame through the device and the host maths.
#include "apps/pattern_analysis.hpp"

#include <stdexcept>

namespace ceilnav::app {
namespace gp = golden::pattern;
namespace hp = host::pattern;

PatternFrameAnalysis analyse_pattern_frame(drivers::Device& device, const cv::Mat& grey,
                                           const gp::Radiometry& radiometry,
                                           const host::CameraModel& model,
                                           const hp::PoseOptions& pose_options) {
  PatternFrameAnalysis a;
  uint64_t cycles = 0;
  const stream::FrameResults res =
      device.process(grey, gp::device_config(grey.cols, grey.rows, radiometry), a.runs, cycles);
  if (!res.valid) throw std::runtime_error("pattern: the device rejected the frame");
  a.moments = hp::device_moments(res.class_moments);
  hp::BarcodeOptions bo;
  bo.bar_contrast =
      radiometry.level(gp::PixelClass::background) - radiometry.level(gp::PixelClass::bar);
  bo.radius_m = pose_options.radius_m;
  bo.min_bar_run_weight = gp::bar_run_min_weight(radiometry);
  static_cast<hp::PatternAnalysis&>(a) = hp::analyse_pattern(
      a.runs, a.moments, model, grey.cols, grey.rows, pose_options, bo,
      gp::disc_coverage_model(radiometry, pose_options.noise_grey, pose_options.psf_sigma_px,
                              pose_options.blur_on_pixels));
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
