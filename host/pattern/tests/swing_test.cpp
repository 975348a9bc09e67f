// The camera's swing per frame (seed 003 eq. 70): from the world's up as the
// bars measure it (host::pattern::swing_from_up), against renders with a
// known swing.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "golden/pattern/pattern.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/pattern/tests/pattern_runs.hpp"
#include "host/pattern/world_fix.hpp"

namespace ceilnav::host::pattern {
namespace {

namespace gp = golden::pattern;
constexpr double kDeg = std::numbers::pi / 180.0;

using test_support::study_camera;

// The renderer's swing is recovered exactly from its own rotation, whatever
// the camera's tilt (looking up or down at the target) and heading.
TEST(Swing, FromUpIsTheRenderersSwingAtAnyTilt) {
  for (const double swing : {-30.0, -8.0, 0.0, 0.5, 12.0, 44.0, 170.0}) {
    for (const Eigen::Vector3d& target :
         {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 1.5, 0), Eigen::Vector3d(1, -2, 0.3)}) {
      const gp::PatternView v = gp::look_at(Eigen::Vector3d(0.7, 0.2, 3.0), target, swing * kDeg);
      EXPECT_NEAR(swing_from_up(v.rotation.col(1)) / kDeg, swing, 1e-9) << swing;
    }
  }
  EXPECT_TRUE(std::isnan(swing_from_up(Eigen::Vector3d(0, 0, 1))));
  EXPECT_TRUE(std::isnan(swing_from_up(Eigen::Vector3d(NAN, -1, 0))));
}

// Rendered frames (lens distortion, noise 3, blur 0.5) with the camera swung
// by a known angle while the host assumes it level: the swing of the bars'
// measured up is the true swing within 0.05 deg (measured: 0.0003-0.012 deg; the up
// as a whole within 0.2 deg in BarsMeasureTheCamerasUp), and beta within 0.5 deg.
TEST(Swing, RenderedSwingIsMeasuredByTheBars) {
  const CameraConfig cam = study_camera();
  const CameraModel model(cam);
  const gp::Radiometry r;
  struct View {
    double d, th, be, swing;
  };
  for (const View w :
       {View{1.5, 30.0, 90.0, -12.0}, View{2.0, 45.0, -60.0, -4.0}, View{2.5, 20.0, 150.0, 3.0},
        View{3.0, 60.0, -120.0, 8.0}, View{2.0, 35.0, 60.0, 0.0}}) {
    const gp::PatternView v = gp::spherical_view(w.d, w.th * kDeg, w.be * kDeg, w.swing * kDeg);
    gp::PatternRenderParams p;
    p.noise_sigma_grey = 3.0;
    p.blur_sigma_px = 0.5;
    const cv::Mat grey = gp::render_pattern(cam, {}, r, 23, v, p);
    const cv::Mat cls = gp::classify(grey, gp::class_lut(r));
    const FrameMoments m = class_moments(cls.ptr<uint8_t>(0), cls.cols, cls.rows, cls.step[0]);
    PoseOptions po;  // up_cam: level, no swing
    BarcodeOptions bo;
    bo.bar_contrast = r.level(gp::PixelClass::background) - r.level(gp::PixelClass::bar);
    bo.min_bar_run_weight = gp::bar_run_min_weight(r);
    const PatternAnalysis a =
        analyse_pattern(test_support::device_runs(grey, r), m, model, cam.image_width,
                        cam.image_height, po, bo, gp::disc_coverage_model(r, 3.0, 0.5, true));
    ASSERT_EQ(a.code.identity, 23) << w.swing;
    ASSERT_TRUE(a.conic_bars.up_cam.has_value()) << w.swing;
    EXPECT_NEAR(swing_from_up(*a.conic_bars.up_cam) / kDeg, w.swing, 0.05)
        << w.d << " " << w.th << " " << w.be << " " << w.swing;
    EXPECT_NEAR(std::remainder(a.conic_bars.beta_rad / kDeg - w.be, 360.0), 0.0, 0.5) << w.swing;
  }
}

}  // namespace
}  // namespace ceilnav::host::pattern
