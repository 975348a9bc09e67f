#include "host/pattern/disc_evidence.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "golden/pattern/pattern.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/pattern/tests/pattern_runs.hpp"

namespace ceilnav::host::pattern {
namespace {

namespace gp = golden::pattern;
constexpr double kDeg = std::numbers::pi / 180.0;

using test_support::study_camera;

struct Frame {
  FrameMoments m{};
  std::vector<stream::RunRecord> disc_runs;
  std::optional<Ellipse> moments_ellipse;
};

Frame frame_of(const cv::Mat& grey, const CameraModel& model) {
  const gp::Radiometry r;
  const cv::Mat cls = gp::classify(grey, gp::class_lut(r));
  Frame f;
  f.m = class_moments(cls.ptr<uint8_t>(0), cls.cols, cls.rows, cls.step[0]);
  f.disc_runs = split_disc_runs(test_support::device_runs(grey, r), f.m[kDisc]).first;
  f.moments_ellipse = ellipse_from_moments(f.m[kDisc], model);
  return f;
}

// Rendered discs near and far, steep, off the axis and cut by the border:
// their runs are one per row and end near the moments' ellipse, so the fits
// run on them as before.
TEST(DiscEvidence, RenderedDiscsPass) {
  const CameraConfig cam = study_camera();
  const CameraModel model(cam);
  struct View {
    double d, th, be, yaw;
  };
  for (const View w :
       {View{1.0, 0.0, 90.0, 0.0}, View{1.0, 60.0, -90.0, 0.0}, View{3.0, 45.0, 60.0, 0.0},
        View{5.0, 75.0, -160.0, 0.0}, View{1.5, 75.0, 160.0, 0.0}, View{2.0, 30.0, 20.0, 25.0}}) {
    gp::PatternView v = gp::spherical_view(w.d, w.th * kDeg, w.be * kDeg);
    // Turn the camera about its up axis: the disc off the image's centre.
    v.rotation = v.rotation * Eigen::AngleAxisd(w.yaw * kDeg, Eigen::Vector3d::UnitY()).matrix();
    gp::PatternRenderParams p;
    p.noise_sigma_grey = 3.0;
    p.blur_sigma_px = 0.5;
    const cv::Mat grey = gp::render_pattern(cam, {}, gp::Radiometry{}, 12, v, p);
    const Frame f = frame_of(grey, model);
    ASSERT_TRUE(f.moments_ellipse) << w.d << " " << w.th;
    EXPECT_TRUE(one_run_per_row(f.disc_runs, cam.image_height)) << w.d << " " << w.th;
    EXPECT_TRUE(
        runs_fit_ellipse(f.disc_runs, *f.moments_ellipse, model, cam.image_width, cam.image_height))
        << w.d << " " << w.th << " " << w.be << " " << w.yaw;
  }
}

// A bright square: convex, one run per row, but its corners lie 0.13 of its
// side outside its moments' ellipse and its sides 0.077 inside.
TEST(DiscEvidence, SquareIsNotAnEllipse) {
  const CameraConfig cam = study_camera();
  const CameraModel model(cam);
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(49));
  cv::rectangle(grey, cv::Rect(220, 140, 200, 200), cv::Scalar(249), cv::FILLED);
  const Frame f = frame_of(grey, model);
  ASSERT_TRUE(f.moments_ellipse);
  EXPECT_TRUE(one_run_per_row(f.disc_runs, 480));
  EXPECT_FALSE(runs_fit_ellipse(f.disc_runs, *f.moments_ellipse, model, 640, 480));
  // The whole analysis leaves the coverage fit out and claims no pose.
  const gp::Radiometry r;
  PoseOptions po;
  po.up_cam = Eigen::Vector3d(0.0, -1.0, 0.0);
  BarcodeOptions bo;
  const PatternAnalysis a =
      analyse_pattern(test_support::device_runs(grey, r), f.m, model, 640, 480, po, bo,
                      gp::disc_coverage_model(r, 3.0, 0.5, true));
  EXPECT_FALSE(a.fit);
  EXPECT_NE(a.code.status, PatternStatus::ok);
}

// Bright stripes: several runs on each row are not one convex region; nor
// are more runs than the image has rows.
TEST(DiscEvidence, ManyRunsPerRowAreNotOneRegion) {
  const CameraConfig cam = study_camera();
  const CameraModel model(cam);
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(49));
  for (int x = 260; x < 380; x += 20) {
    cv::rectangle(grey, cv::Rect(x, 180, 10, 120), cv::Scalar(249), cv::FILLED);
  }
  const Frame f = frame_of(grey, model);
  ASSERT_GT(f.disc_runs.size(), 240u);
  EXPECT_FALSE(one_run_per_row(f.disc_runs, 480));
  ASSERT_TRUE(f.moments_ellipse);
  EXPECT_FALSE(runs_fit_ellipse(f.disc_runs, *f.moments_ellipse, model, 640, 480));
  std::vector<stream::RunRecord> too_many(481, stream::RunRecord{10, 1, 2, 0, 0});
  for (std::size_t i = 0; i < too_many.size(); ++i)
    too_many[i].row = static_cast<uint16_t>(i % 480);
  EXPECT_FALSE(one_run_per_row(too_many, 480));
  EXPECT_FALSE(one_run_per_row({}, 480));
}

}  // namespace
}  // namespace ceilnav::host::pattern
