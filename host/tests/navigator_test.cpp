// The whole chain on rendered frames with known pose: renderer -> device model
// (threshold from the device histogram, LUT, runs) -> host pose maths.
#include "host/navigator.hpp"
#include "drivers/device.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "golden/renderer.hpp"
#include "golden/scene.hpp"

namespace ceilnav::host {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

CameraConfig camera(int width, int height, double pitch_deg, bool distortion) {
  CameraConfig c;
  c.image_width = width;
  c.image_height = height;
  const double s = width / 640.0;
  c.camera_matrix = {520.0 * s, 0.0,       (width - 1) / 2.0 + 2.0 * s,
                     0.0,       518.0 * s, (height - 1) / 2.0 - 1.5 * s,
                     0.0,       0.0,       1.0};
  if (distortion) c.distortion_coefficients = {-0.08, 0.015, 0.0004, -0.0003, 0.0};
  c.camera_pitch_deg = pitch_deg;
  c.camera_height_m = 0.5;
  c.ceiling_height_m = 2.8;
  c.tape_width_m = 0.05;
  return c;
}

struct Errors {
  double yaw_ss = 0, off_ss = 0, yaw_max = 0, off_max = 0;
  int n = 0, failed = 0;
  void add(double ey, double eo) {
    yaw_ss += ey * ey;
    off_ss += eo * eo;
    yaw_max = std::max(yaw_max, std::abs(ey));
    off_max = std::max(off_max, std::abs(eo));
    ++n;
  }
  double yaw_rms_deg() const { return std::sqrt(yaw_ss / std::max(1, n)) / kDeg; }
  double off_rms_mm() const { return 1e3 * std::sqrt(off_ss / std::max(1, n)); }
};

// One frame per (pitch, yaw, offset) of the sweep; noise 3, blur 0.7.
Errors sweep(int width, int height, const std::vector<double>& pitches, bool distortion,
             uint64_t seed) {
  Errors e;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const golden::CeilingScene scene = golden::single_tape_scene(0.05);
  for (double pitch : pitches) {
    for (int k = 0; k < 3; ++k) {
      const CameraConfig cam = camera(width, height, pitch, distortion);
      const golden::CameraPose pose{2.0 * k, 0.5 * u(rng), 15.0 * kDeg * u(rng)};
      golden::RenderParams rp;
      rp.tape_gain = 1200.0;
      rp.noise_sigma_grey = 3.0;
      rp.blur_sigma_px = 0.7;
      rp.noise_seed = seed + static_cast<uint64_t>(k);
      const cv::Mat frame = golden::render_frame(cam, scene, pose, rp);
      const golden::FrameTruth truth = golden::truth_for(cam, scene, pose);
      Navigator nav(cam, drivers::make_device());
      const FrameOutcome r = nav.process(frame);
      if (r.pose.status != Status::ok) {
        ++e.failed;
        continue;
      }
      EXPECT_TRUE(std::isfinite(r.pose.yaw_rad) && std::isfinite(r.pose.offset_m));
      e.add(r.pose.yaw_rad - truth.yaw_rad, r.pose.offset_m - truth.offset_m);
      if (pitch >= 89.999) {
        EXPECT_TRUE(r.zenith.has_value());
        EXPECT_FALSE(r.pose.vp_finite);
      } else {
        EXPECT_TRUE(truth.vp_finite);
        // The vanishing point follows from yaw and pitch; its pixel error
        // scales with the distance from the image centre.
        EXPECT_NEAR(r.pose.vp_v_px, truth.vp_v_px, 1e-6 * std::abs(truth.vp_v_px) + 1e-6);
        EXPECT_NEAR(r.pose.vp_u_px, truth.vp_u_px, 0.5 + 0.002 * std::abs(truth.vp_u_px));
      }
    }
  }
  return e;
}

TEST(NavigatorRendered, PitchSweep20To70And90At640x480) {
  const Errors e = sweep(640, 480, {20, 30, 40, 50, 60, 70, 90}, true, 101);
  EXPECT_EQ(e.failed, 0);
  std::printf("640x480: %d frames, yaw RMS %.4f deg (max %.4f), offset RMS %.3f mm (max %.3f)\n",
              e.n, e.yaw_rms_deg(), e.yaw_max / kDeg, e.off_rms_mm(), 1e3 * e.off_max);
  EXPECT_LE(e.yaw_rms_deg(), 0.02);
  EXPECT_LE(e.off_rms_mm(), 1.0);
}

TEST(NavigatorRendered, ResolutionSweep) {
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{320, 240}, {800, 600}, {1280, 960}}) {
    const Errors e = sweep(w, h, {25, 45, 65, 90}, w != 800, 200 + static_cast<uint64_t>(w));
    EXPECT_EQ(e.failed, 0) << w << "x" << h;
    std::printf("%dx%d: %d frames, yaw RMS %.4f deg, offset RMS %.3f mm\n", w, h, e.n,
                e.yaw_rms_deg(), e.off_rms_mm());
    // 320x240 has half the pixels per metre of tape: twice the bound.
    const double scale = w < 640 ? 2.0 : 1.0;
    EXPECT_LE(e.yaw_rms_deg(), 0.02 * scale) << w << "x" << h;
    EXPECT_LE(e.off_rms_mm(), 1.0 * scale) << w << "x" << h;
  }
}

TEST(NavigatorRendered, ZenithMomentsAgreeWithTheCentreLine) {
  const CameraConfig cam = camera(640, 480, 90.0, false);
  const golden::CeilingScene scene = golden::single_tape_scene(0.05);
  const golden::CameraPose pose{1.0, 0.12, 7.0 * kDeg};
  golden::RenderParams rp;
  rp.tape_gain = 1200.0;
  rp.noise_sigma_grey = 2.0;
  const cv::Mat frame = golden::render_frame(cam, scene, pose, rp);
  Navigator nav(cam, drivers::make_device());
  const FrameOutcome r = nav.process(frame);
  ASSERT_EQ(r.pose.status, Status::ok);
  ASSERT_TRUE(r.zenith.has_value());
  ASSERT_EQ(r.zenith->status, Status::ok);
  // Moments of a finite, clipped band: bound from docs/host_maths.md, loose.
  EXPECT_NEAR(r.zenith->yaw_rad, 7.0 * kDeg, 0.2 * kDeg);
  EXPECT_NEAR(r.zenith->offset_m, 0.12, 0.01);
  EXPECT_NEAR(r.pose.yaw_rad, 7.0 * kDeg, 0.02 * kDeg);
  EXPECT_NEAR(r.pose.offset_m, 0.12, 0.001);
}

TEST(NavigatorRendered, ClockedModelGivesTheFastPathResultsUnderGapsAndBackPressure) {
  const CameraConfig cam = camera(320, 240, 40.0, true);
  golden::CorridorOptions corridor;
  corridor.second_tape = true;
  corridor.second_tape_y_m = 0.8;
  const golden::CeilingScene scene = golden::corridor_scene(0.05, corridor);
  drivers::DeviceOptions clocked_opt;
  clocked_opt.backend = drivers::Backend::model;
  clocked_opt.gap_probability = 0.3;
  clocked_opt.backpressure_probability = 0.6;
  clocked_opt.seed = 9;
  Navigator fast(cam, drivers::make_device()), clocked(cam, drivers::make_device(clocked_opt));
  for (int i = 0; i < 4; ++i) {
    golden::RenderParams rp;
    rp.noise_seed = 50u + static_cast<uint64_t>(i);
    const cv::Mat frame = golden::render_frame(cam, scene, {4.0 + 1.5 * i, 0.1, 0.05 * i}, rp);
    const FrameOutcome a = fast.process(frame);
    const FrameOutcome b = clocked.process(frame);
    EXPECT_EQ(a.runs, b.runs) << "frame " << i;
    EXPECT_EQ(a.results.histogram, b.results.histogram);
    EXPECT_EQ(a.results.moments, b.results.moments);
    EXPECT_EQ(a.settings, b.settings);
    EXPECT_EQ(a.passes, b.passes);
    EXPECT_EQ(a.pose.status, b.pose.status);
    EXPECT_EQ(a.pose.yaw_rad, b.pose.yaw_rad);
    EXPECT_GT(b.cycles, static_cast<uint64_t>(frame.total()));  // gaps cost cycles
  }
}

TEST(NavigatorRendered, NoTapeBlackAndSaturatedFramesGiveAStatusAndTheNextFrameIsRight) {
  const CameraConfig cam = camera(320, 240, 45.0, false);
  Navigator nav(cam, drivers::make_device());
  const cv::Mat black(240, 320, CV_8UC1, cv::Scalar(0));
  const cv::Mat white(240, 320, CV_8UC1, cv::Scalar(255));
  cv::Mat noise(240, 320, CV_8UC1);
  cv::randn(noise, 20, 3);
  for (const cv::Mat* m : std::vector<const cv::Mat*>{&black, &white, &noise}) {
    const FrameOutcome r = nav.process(*m);
    EXPECT_NE(r.pose.status, Status::ok);
    EXPECT_TRUE(std::isfinite(r.pose.yaw_rad) && std::isfinite(r.pose.offset_m));
  }
  const golden::CeilingScene scene = golden::single_tape_scene(0.05);
  golden::RenderParams rp;
  rp.tape_gain = 1200.0;
  const golden::CameraPose pose{0.0, -0.2, -5.0 * kDeg};
  const FrameOutcome good = nav.process(golden::render_frame(cam, scene, pose, rp));
  ASSERT_EQ(good.pose.status, Status::ok);
  EXPECT_NEAR(good.pose.yaw_rad, -5.0 * kDeg, 0.05 * kDeg);
  EXPECT_NEAR(good.pose.offset_m, -0.2, 0.003);
  EXPECT_THROW(nav.process(cv::Mat(10, 10, CV_8UC1)), std::invalid_argument);
}

TEST(NavigationPose, CentreLineFirstThenTheZenithMoments) {
  FrameOutcome out;
  out.pose.status = Status::ok;
  out.pose.method = "runs_centre_line";
  out.zenith = TapePose{};
  out.zenith->status = Status::ok;
  out.zenith->method = "zenith_moments";
  EXPECT_EQ(&navigation_pose(out), &out.pose);
  out.pose.status = Status::too_few_points;
  EXPECT_EQ(&navigation_pose(out), &*out.zenith);
  out.zenith->status = Status::inconsistent;
  EXPECT_EQ(&navigation_pose(out), &out.pose);
  out.zenith.reset();
  EXPECT_EQ(&navigation_pose(out), &out.pose);
}

}  // namespace
}  // namespace ceilnav::host
