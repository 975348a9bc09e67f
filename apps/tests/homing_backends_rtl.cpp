// The orientation readout (drivers::Device::set_orientation / orientation(),
// through host::Driver::read_orientation on the bus backends) of the homing
// device: each rendered ceiling frame's histogram and counters are the same
// on the fast, model and rtl backends, and equal to
// golden::orientation_histogram_fixed of the LUT-remapped frame, with random
// gaps, back-pressure and AXI-Lite stalls on the bus backends.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "ceilnav/regs.hpp"
#include "common/camera_config.hpp"
#include "common/pipeline_config.hpp"
#include "drivers/device.hpp"
#include "drivers/rtl_backend.hpp"
#include "golden/ceiling/ceiling_file.hpp"
#include "golden/ceiling/render.hpp"
#include "golden/orientation_ref.hpp"
#include "golden/thresh_lut_ref.hpp"

namespace ceilnav::app {
namespace {

namespace gc = golden::ceiling;

constexpr int kW = 320;
constexpr int kH = 240;

// The built-in homing world seen from four robot poses about its first site,
// under the return lighting.
std::vector<cv::Mat> ceiling_frames() {
  const gc::CeilingFile world = gc::default_homing_world();
  host::CameraConfig cam;
  cam.image_width = kW;
  cam.image_height = kH;
  cam.camera_matrix = {250.0, 0.0, 159.5, 0.0, 250.0, 119.5, 0.0, 0.0, 1.0};
  const gc::SitePose& s = world.sites.front();
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 4; ++i) {
    gc::RenderParams rp;
    rp.noise_seed = 11u + static_cast<uint64_t>(i);
    const gc::Pose pose =
        gc::camera_pose(world.camera, s.x_m + 0.2 * i, s.y_m - 0.1 * i, s.yaw_rad + 0.4 * i);
    frames.push_back(gc::render_frame(cam, world.ceiling, world.lighting_at_return(), pose, rp));
  }
  return frames;
}

TEST(HomingBackends, OrientationEqualOnEveryBackendAndGolden) {
  const std::vector<cv::Mat> frames = ceiling_frames();
  stream::PipelineConfig cfg;
  cfg.width = kW;
  cfg.height = kH;
  for (unsigned g = 0; g < 256; ++g) {
    cfg.lut[g] = stream::lut_entry(static_cast<uint8_t>(std::min(255u, g * 3 / 2)), g > 200, 0);
  }
  drivers::DeviceOptions fast_opt;
  fast_opt.device_config = regs::kConfigHoming;
  drivers::DeviceOptions model_opt = fast_opt;
  model_opt.backend = drivers::Backend::model;
  model_opt.gap_probability = 0.2;
  model_opt.backpressure_probability = 0.5;
  model_opt.seed = 29;
  drivers::DeviceOptions rtl_opt = model_opt;
  rtl_opt.backend = drivers::Backend::rtl;
  rtl_opt.bus_factory = drivers::rtl_bus_factory();
  ASSERT_TRUE(static_cast<bool>(rtl_opt.bus_factory)) << "this build has no RTL backend";
  drivers::Device fast(fast_opt);
  drivers::Device model(model_opt);
  drivers::Device rtl(rtl_opt);

  uint32_t published = 0;
  std::vector<uint32_t> last;
  for (size_t i = 0; i < frames.size(); ++i) {
    // Frame 2 with the block disabled: nothing is published.
    const host::OrientationControl ori{i != 2, static_cast<uint16_t>(i == 3 ? 0 : 24)};
    for (drivers::Device* d : {&fast, &model, &rtl}) d->set_orientation(ori);
    if (ori.enable) ++published;
    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(frames[i], cfg.lut, remap, mask);
    const std::vector<uint32_t> want =
        ori.enable ? golden::orientation_histogram_fixed(remap, {90, ori.threshold}) : last;
    last = want;
    std::vector<stream::RunRecord> runs;
    uint64_t cycles = 0;
    const stream::FrameResults fr = fast.process(frames[i], cfg, runs, cycles);
    const host::OrientationReadout f = fast.orientation();
    const stream::FrameResults mr = model.process(frames[i], cfg, runs, cycles);
    const host::OrientationReadout m = model.orientation();
    const stream::FrameResults rr = rtl.process(frames[i], cfg, runs, cycles);
    const host::OrientationReadout r = rtl.orientation();
    std::printf("frame %zu: %u votes, rtl backend %llu cycles for the frame and its readout\n", i,
                r.votes, static_cast<unsigned long long>(cycles));
    for (const host::OrientationReadout* o : {&f, &m, &r}) {
      EXPECT_TRUE(o->valid) << "frame " << i;
      EXPECT_TRUE(o->consistent) << "frame " << i;
      EXPECT_EQ(o->frames, published) << "frame " << i;
      EXPECT_EQ(o->skipped, 0u) << "frame " << i;
      EXPECT_EQ(o->votes, f.votes) << "frame " << i;
      EXPECT_TRUE(o->bins == want) << "frame " << i << ": histogram differs from golden";
    }
    EXPECT_GT(f.votes, 5000u) << "frame " << i;
    EXPECT_EQ(fr.histogram, mr.histogram) << "frame " << i;
    EXPECT_EQ(fr.histogram, rr.histogram) << "frame " << i;
    EXPECT_EQ(fr.moments, rr.moments) << "frame " << i;
  }
}

TEST(HomingBackends, DevicesWithoutTheBlockRefuseIt) {
  drivers::DeviceOptions full;  // the full configuration: no orientation block
  drivers::Device fast(full);
  EXPECT_THROW(fast.set_orientation({}), std::runtime_error);
  full.backend = drivers::Backend::model;
  drivers::Device model(full);
  EXPECT_THROW(model.set_orientation({}), std::runtime_error);
  EXPECT_FALSE(fast.orientation().valid);
}

}  // namespace
}  // namespace ceilnav::app
