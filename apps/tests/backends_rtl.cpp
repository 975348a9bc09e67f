// fast, model and rtl backends give the same frame results, runs and pose,
// bit for bit, on real photos and rendered frames, with random gaps,
// run-stream back-pressure and AXI-Lite stalls on the bus backends.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "drivers/rtl_backend.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {
namespace {

std::vector<cv::Mat> frames_320x240() {
  std::vector<cv::Mat> frames;
  for (const char* name : {"building.jpg", "fruits.jpg", "baboon.jpg"}) {
    const cv::Mat photo = cv::imread(std::string("/usr/share/doc/opencv-doc/examples/data/") + name,
                                     cv::IMREAD_GRAYSCALE);
    EXPECT_FALSE(photo.empty()) << name << " (Debian package opencv-doc)";
    if (!photo.empty()) frames.push_back(photo(cv::Rect(0, 0, 320, 240)).clone());
  }
  host::CameraConfig cam = golden::default_camera();
  cam.image_width = 320;
  cam.image_height = 240;
  cam.camera_matrix = {260.0, 0.0, 160.6, 0.0, 259.2, 119.3, 0.0, 0.0, 1.0};
  const auto scene = golden::default_corridor(cam);
  for (const auto& d : golden::default_drive(30)) {
    if (frames.size() >= 6) break;
    if (d.pose.x_m < 8.0) continue;  // near the T-branch and the first gap
    frames.push_back(golden::render_frame(cam, scene, d.pose, golden::default_render_params()));
  }
  return frames;
}

host::CameraConfig camera_320x240() {
  host::CameraConfig cam = golden::default_camera();
  cam.image_width = 320;
  cam.image_height = 240;
  cam.camera_matrix = {260.0, 0.0, 160.6, 0.0, 259.2, 119.3, 0.0, 0.0, 1.0};
  return cam;
}

void expect_same(const host::FrameOutcome& a, const host::FrameOutcome& b, const char* what,
                 size_t frame) {
  EXPECT_EQ(a.runs, b.runs) << what << " frame " << frame;
  EXPECT_EQ(a.results.histogram, b.results.histogram) << what << " frame " << frame;
  EXPECT_EQ(a.results.moments, b.results.moments) << what << " frame " << frame;
  EXPECT_EQ(a.results.errors, b.results.errors) << what << " frame " << frame;
  EXPECT_EQ(a.results.run_stats.runs_emitted, b.results.run_stats.runs_emitted) << what;
  EXPECT_EQ(a.settings, b.settings) << what << " frame " << frame;
  EXPECT_EQ(a.passes, b.passes) << what << " frame " << frame;
  EXPECT_EQ(a.pose.status, b.pose.status) << what << " frame " << frame;
  EXPECT_EQ(a.pose.yaw_rad, b.pose.yaw_rad) << what << " frame " << frame;
  EXPECT_EQ(a.pose.offset_m, b.pose.offset_m) << what << " frame " << frame;
}

TEST(Backends, FastModelAndRtlAgreeOnPhotosAndRenderedFrames) {
  const std::vector<cv::Mat> frames = frames_320x240();
  ASSERT_GE(frames.size(), 6u);
  const host::CameraConfig cam = camera_320x240();

  drivers::DeviceOptions model_opt;
  model_opt.backend = drivers::Backend::model;
  model_opt.gap_probability = 0.2;
  model_opt.backpressure_probability = 0.5;
  model_opt.seed = 17;
  drivers::DeviceOptions rtl_opt = model_opt;
  rtl_opt.backend = drivers::Backend::rtl;
  rtl_opt.bus_factory = drivers::rtl_bus_factory();
  ASSERT_TRUE(static_cast<bool>(rtl_opt.bus_factory)) << "this build has no RTL backend";

  host::Navigator fast(cam, drivers::make_device()), model(cam, drivers::make_device(model_opt)),
      rtl(cam, drivers::make_device(rtl_opt));
  int ok_frames = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    const host::FrameOutcome f = fast.process(frames[i]);
    const host::FrameOutcome m = model.process(frames[i]);
    const host::FrameOutcome r = rtl.process(frames[i]);
    expect_same(f, m, "model vs fast", i);
    expect_same(f, r, "rtl vs fast", i);
    EXPECT_GT(m.cycles, frames[i].total());  // gaps and bus traffic cost cycles
    ok_frames += f.pose.status == host::Status::ok ? 1 : 0;
  }
  EXPECT_GE(ok_frames, 3);  // the rendered frames give a pose
}

}  // namespace
}  // namespace ceilnav::app
