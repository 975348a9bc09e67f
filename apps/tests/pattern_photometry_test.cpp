// Pattern frames rendered with a camera gain, offset and vignetting the host
// is not told, through the device and the host with the photometric
// self-calibration (sim/pattern_analysis.hpp, docs/pattern.md §2): at the
// corners of the calibrated range the pose meets the bars (D within 0.3 %,
// theta within 0.3 deg) with status ok; beyond it the frame is not ok.
#include <gtest/gtest.h>

#include <cmath>

#include "apps/commands.hpp"
#include "sim/pattern_analysis.hpp"

namespace ceilnav::app {
namespace {

namespace gp = golden::pattern;
namespace hp = host::pattern;

struct Frame {
  double d, theta_deg, beta_deg;
  int identity;
};
// Two of the study's views whose code is fully visible.
constexpr Frame kFrames[] = {{2.0, 30.0, -90.0, 12}, {3.0, 22.5, 90.0, 33}};

struct Result {
  bool ok;
  double d_err_pct, theta_err_deg;
  hp::PhotometricCalibration cal;
};

Result analyse(const Frame& f, const gp::CameraPhotometry& photometry, uint64_t seed) {
  const host::CameraConfig camera = scaled_camera(640, 480, true);
  const host::CameraModel model(camera);
  const gp::PatternGeometry g;
  const gp::Radiometry nominal;
  const gp::PatternView v = gp::spherical_view(f.d, f.theta_deg * kDeg, f.beta_deg * kDeg);
  gp::PatternRenderParams p;
  p.noise_sigma_grey = 3.0;
  p.blur_sigma_px = 0.5;
  p.noise_seed = seed;
  p.photometry = photometry;
  const cv::Mat grey = gp::render_pattern(camera, g, nominal, f.identity, v, p);
  drivers::Device device;
  hp::PoseOptions po = sim::pose_options_for(g);
  po.up_cam = v.rotation.col(1);
  const sim::PatternFrameAnalysis a = sim::analyse_pattern_frame(device, grey, nominal, model, po);
  Result r;
  r.ok = a.conic_bars.status == hp::PatternStatus::ok && a.code.status == hp::PatternStatus::ok &&
         a.code.identity == f.identity;
  r.d_err_pct = 100.0 * (a.conic_bars.d_m - f.d) / f.d;
  r.theta_err_deg = a.conic_bars.theta_rad / kDeg - f.theta_deg;
  r.cal = a.photometry;
  return r;
}

TEST(PatternPhotometry, NominalCameraCalibratesToTheNominalLevels) {
  const Result r = analyse(kFrames[0], {}, 1);
  ASSERT_TRUE(r.cal.ok());
  EXPECT_NEAR(r.cal.black, 4.0, 1.5);
  EXPECT_NEAR(r.cal.scale, 250.0, 2.5);
  EXPECT_TRUE(r.ok);
  EXPECT_LE(std::abs(r.d_err_pct), 0.3);
  EXPECT_LE(std::abs(r.theta_err_deg), 0.3);
}

TEST(PatternPhotometry, CornersOfTheRangeMeetTheBars) {
  // Gain 0.8 / 1.2, offset -15 / +15, vignetting 0 / 20 % at the corner:
  // the bars clipped (offset -15), the disc clipped (gain 1.2 or offset
  // +15 at gain 1), both in view.
  const gp::CameraPhotometry corners[] = {
      {0.8, -15.0, 0.2}, {0.8, 15.0, 0.0}, {1.2, 0.0, 0.2}, {1.0, -15.0, 0.2}, {1.0, 15.0, 0.0}};
  uint64_t seed = 10;
  for (const gp::CameraPhotometry& c : corners) {
    for (const Frame& f : kFrames) {
      const Result r = analyse(f, c, ++seed);
      const std::string what = "gain " + std::to_string(c.gain) + " offset " +
                               std::to_string(c.offset_grey) + " vignetting " +
                               std::to_string(c.vignetting) + " D " + std::to_string(f.d);
      EXPECT_TRUE(r.cal.ok()) << what << ": " << hp::to_string(r.cal.status);
      EXPECT_TRUE(r.ok) << what;
      EXPECT_LE(std::abs(r.d_err_pct), 0.3) << what;
      EXPECT_LE(std::abs(r.theta_err_deg), 0.3) << what;
    }
  }
}

TEST(PatternPhotometry, BeyondTheRangeIsNeverOk) {
  // Gain 0.4 (contrast too low), offset +60, and gain 1.2 with offset -15
  // (bars and disc both clipped: one level for two unknowns).
  const gp::CameraPhotometry beyond[] = {{0.4, 0.0, 0.0}, {1.0, 60.0, 0.0}, {1.2, -15.0, 0.0}};
  uint64_t seed = 100;
  for (const gp::CameraPhotometry& c : beyond) {
    for (const Frame& f : kFrames) {
      const Result r = analyse(f, c, ++seed);
      EXPECT_FALSE(r.cal.ok()) << c.gain << " " << c.offset_grey;
      EXPECT_FALSE(r.ok) << c.gain << " " << c.offset_grey;
    }
  }
  // Offset -40 at a steep near view: the wall near black and the side wall
  // large, which a wrong split takes for the wall (refused as inconsistent).
  const Result steep = analyse({1.0, 60.0, 90.0, 48}, {1.0, -40.0, 0.0}, 200);
  EXPECT_FALSE(steep.cal.ok()) << hp::to_string(steep.cal.status);
  EXPECT_FALSE(steep.ok);
}

TEST(PatternPhotometry, RendererAppliesGainOffsetAndVignetting) {
  // A flat scene (far wall only, no blur or noise): the frame's centre is
  // black + offset + gain * wall, its corner lower by the vignetting.
  const host::CameraConfig camera = scaled_camera(64, 48, false);
  const gp::Radiometry r;
  gp::PatternRenderParams p;
  p.noise_sigma_grey = 0.0;
  p.blur_sigma_px = 0.0;
  const gp::PatternView v = gp::look_at({0.0, 0.0, 3.0}, {2.9, 1.4, -0.05}, 0.0);  // wall corner
  const cv::Mat base = gp::render_pattern(camera, {}, r, 0, v, p);
  p.photometry = {1.2, 10.0, 0.2};
  const cv::Mat shot = gp::render_pattern(camera, {}, r, 0, v, p);
  for (const auto& [x, y] : {std::pair{32, 24}, std::pair{0, 0}, std::pair{63, 47}}) {
    const double signal = base.at<uint8_t>(y, x) - r.black_level;
    const double f = gp::vignetting_factor(p.photometry, 64, 48, x, y);
    EXPECT_NEAR(shot.at<uint8_t>(y, x), r.black_level + 10.0 + 1.2 * f * signal, 1.0)
        << x << "," << y;
  }
  EXPECT_NEAR(gp::vignetting_factor(p.photometry, 64, 48, 0, 0), 0.8, 1e-12);
  EXPECT_NEAR(gp::vignetting_factor(p.photometry, 64, 48, 31.5, 23.5), 1.0, 1e-12);
  p.photometry.vignetting = 1.0;
  EXPECT_THROW(gp::render_pattern(camera, {}, r, 0, v, p), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::app
