// The histogram correction table (seed 000): when the navigator reprograms the
// LUT from a histogram, under each ThresholdPolicy, on rendered frames whose
// exposure steps between frames.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/auto_threshold.hpp"
#include "host/navigator.hpp"

namespace ceilnav::host {
namespace {

// A lit ceiling (background 60 at nominal exposure) and a modest tape return,
// so that a threshold chosen at one exposure is wrong at x2 or x0.5.
cv::Mat frame_at(double exposure, int i) {
  const CameraConfig cam = golden::default_camera();
  golden::RenderParams p = golden::default_render_params();
  p.background_grey = 60.0 * exposure;
  p.tape_gain = 300.0 * exposure;
  p.noise_seed = 77u + static_cast<uint64_t>(i);
  const golden::CameraPose pose{0.4 * i, 0.1, 0.05};
  return golden::render_frame(cam, golden::single_tape_scene(cam.tape_width_m), pose, p);
}

Navigator navigator(ThresholdPolicy policy) {
  NavigatorOptions o;
  o.threshold_policy = policy;
  return Navigator(golden::default_camera(), drivers::make_device(), o);
}

const std::vector<double> kExposures{1.0, 1.0, 2.0, 2.0, 0.5, 0.5, 1.0};

TEST(ThresholdPolicy, FirstFrameKeepsItsSettings) {
  Navigator nav = navigator(ThresholdPolicy::first_frame);
  const FrameOutcome first = nav.process(frame_at(kExposures[0], 0));
  EXPECT_EQ(first.passes, 2);  // no earlier histogram: the first frame is run twice
  for (size_t i = 1; i < kExposures.size(); ++i) {
    const FrameOutcome r = nav.process(frame_at(kExposures[i], static_cast<int>(i)));
    EXPECT_EQ(r.passes, 1) << i;
    EXPECT_EQ(r.settings, first.settings) << i;
  }
}

TEST(ThresholdPolicy, PreviousFrameFollowsTheExposureOneFrameLate) {
  Navigator nav = navigator(ThresholdPolicy::previous_frame);
  ThresholdSettings expected;
  for (size_t i = 0; i < kExposures.size(); ++i) {
    const cv::Mat f = frame_at(kExposures[i], static_cast<int>(i));
    const FrameOutcome r = nav.process(f);
    const ThresholdSettings own = choose_threshold(r.results.histogram);
    if (i == 0) {
      EXPECT_EQ(r.passes, 2);
      EXPECT_EQ(r.settings, own);
    } else {
      EXPECT_EQ(r.passes, 1) << i;
      EXPECT_EQ(r.settings, expected) << i;  // the previous frame's table
    }
    expected = own;
  }
  // The table follows the exposure: background and threshold at x2 are above
  // those at x0.5 (frames 3 and 5 were processed with frames 2 and 4's tables).
  Navigator probe = navigator(ThresholdPolicy::previous_frame);
  const ThresholdSettings hi = choose_threshold(probe.process(frame_at(2.0, 2)).results.histogram);
  const ThresholdSettings lo = choose_threshold(probe.process(frame_at(0.5, 4)).results.histogram);
  EXPECT_GT(hi.background_grey, lo.background_grey + 40.0);
  EXPECT_GT(hi.threshold, lo.threshold + 40);
}

TEST(ThresholdPolicy, RerunProcessesAStepTwiceWithItsOwnTable) {
  Navigator nav = navigator(ThresholdPolicy::previous_frame_rerun);
  for (size_t i = 0; i < kExposures.size(); ++i) {
    const FrameOutcome r = nav.process(frame_at(kExposures[i], static_cast<int>(i)));
    const bool step = i == 0 || kExposures[i] != kExposures[i - 1];
    EXPECT_EQ(r.passes, step ? 2 : 1) << i;
    EXPECT_EQ(r.settings, choose_threshold(r.results.histogram)) << i;
    EXPECT_EQ(r.pose.status, Status::ok) << i;
  }
}

// The seed's one-pass table on a lit ceiling whose exposure steps by x2 and
// x0.5: after a step up the previous table thresholds below the new ceiling
// (the mask is mostly ceiling). Such frames must not be ok with a wrong pose;
// those that are ok are right.
TEST(ThresholdPolicy, OnePassTableNeverClaimsAWrongPose) {
  const CameraConfig cam = golden::default_camera();
  const golden::CeilingScene scene = golden::single_tape_scene(cam.tape_width_m);
  Navigator nav = navigator(ThresholdPolicy::previous_frame);
  // `ceilnav exposure`'s cycle: steps of x2, x0.5, x1.41 and x0.71.
  const double r2 = std::sqrt(2.0), h2 = std::sqrt(0.5);
  const std::vector<double> exposures{1.0, 2.0, 1.0, 0.5, 1.0, r2, 2.0, r2, 1.0, h2, 0.5, h2,
                                      1.0, 2.0, 1.0, 0.5, 1.0, r2, 2.0, r2, 1.0, h2, 0.5, h2};
  const std::vector<golden::DrivePose> drive =
      golden::default_drive(static_cast<int>(exposures.size()));
  int ok = 0, rejected_after_step_up = 0;
  for (size_t i = 0; i < exposures.size(); ++i) {
    const golden::CameraPose& pose = drive[i].pose;
    golden::RenderParams p = golden::default_render_params();
    p.background_grey = 60.0 * exposures[i];
    p.tape_gain = 300.0 * exposures[i];
    p.noise_seed = 1000003u + i;
    const FrameOutcome r = nav.process(golden::render_frame(cam, scene, pose, p));
    if (r.pose.status == Status::ok) {
      ++ok;
      const golden::FrameTruth t = golden::truth_for(cam, scene, pose);
      EXPECT_LT(std::abs(std::remainder(r.pose.yaw_rad - t.yaw_rad, 2.0 * M_PI)), 0.5 * M_PI / 180)
          << i;
      EXPECT_LT(std::abs(r.pose.offset_m - t.offset_m), 0.02) << i;
    } else if (i > 0 && exposures[i] > exposures[i - 1]) {
      ++rejected_after_step_up;
    }
  }
  EXPECT_GT(ok, 0);                      // the table does work between steps
  EXPECT_GT(rejected_after_step_up, 0);  // and a step up does defeat it
}

}  // namespace
}  // namespace ceilnav::host
