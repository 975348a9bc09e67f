// The corridor readout (drivers::Device::set_corridor / corridor(), through
// host::Driver::read_corridor on the bus backends): the hough accumulator of
// each frame is the same on the fast, model and rtl backends, and equal to
// golden::hough_ref on golden::find_edges_ref of the LUT-remapped frame,
// with random gaps, back-pressure and AXI-Lite stalls on the bus backends.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <opencv2/core.hpp>

#include "common/corridor_results.hpp"
#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "common/pipeline_config.hpp"
#include "drivers/device.hpp"
#include "drivers/rtl_backend.hpp"
#include "golden/default_scene.hpp"
#include "golden/edge_ref.hpp"
#include "golden/hough_ref.hpp"
#include "golden/renderer.hpp"
#include "golden/thresh_lut_ref.hpp"

namespace ceilnav::app {
namespace {

constexpr int kW = 160;
constexpr int kH = 120;

// Rendered corridor frames (the default scene, three poses of the drive).
std::vector<cv::Mat> corridor_frames() {
  host::CameraConfig cam = golden::default_camera();
  cam.image_width = kW;
  cam.image_height = kH;
  cam.camera_matrix = {130.0, 0.0, 80.3, 0.0, 129.6, 59.6, 0.0, 0.0, 1.0};
  const auto scene = golden::default_corridor(cam);
  std::vector<cv::Mat> frames;
  for (const auto& d : golden::default_drive(30)) {
    if (frames.size() >= 3) break;
    if (d.pose.x_m < 8.0) continue;
    frames.push_back(golden::render_frame(cam, scene, d.pose, golden::default_render_params()));
  }
  return frames;
}

TEST(CorridorBackends, AccumulatorEqualOnEveryBackendAndGolden) {
  const std::vector<cv::Mat> frames = corridor_frames();
  ASSERT_EQ(frames.size(), 3u);
  stream::PipelineConfig cfg;
  cfg.width = kW;
  cfg.height = kH;
  for (unsigned g = 0; g < 256; ++g) {
    cfg.lut[g] = stream::lut_entry(static_cast<uint8_t>(255 - g), g < 90, 0);  // inverted remap
  }
  stream::EdgeConfig edge;
  edge.enable = true;
  edge.mode = stream::EdgeMode::kSobel;
  edge.threshold = 120;
  stream::HoughConfig hough;
  hough.enable = true;
  hough.weight_shift = 2;
  hough.rho_shift = 3;
  hough.width = kW;

  drivers::DeviceOptions model_opt;
  model_opt.backend = drivers::Backend::model;
  model_opt.gap_probability = 0.2;
  model_opt.backpressure_probability = 0.5;
  model_opt.seed = 23;
  drivers::DeviceOptions rtl_opt = model_opt;
  rtl_opt.backend = drivers::Backend::rtl;
  rtl_opt.bus_factory = drivers::rtl_bus_factory();
  ASSERT_TRUE(static_cast<bool>(rtl_opt.bus_factory)) << "this build has no RTL backend";
  drivers::Device fast;
  drivers::Device model(model_opt);
  drivers::Device rtl(rtl_opt);
  for (drivers::Device* d : {&fast, &model, &rtl}) d->set_corridor(edge, hough);

  const stream::HoughShape shape;
  for (size_t i = 0; i < frames.size(); ++i) {
    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(frames[i], cfg.lut, remap, mask);
    const std::vector<stream::EdgeRecord> pts =
        golden::find_edges_ref(remap, {edge.mode, edge.threshold});
    const std::vector<uint32_t> want = golden::hough_cells_ref(shape, hough, pts);
    ASSERT_GT(pts.size(), 200u) << "frame " << i;
    std::vector<stream::RunRecord> runs;
    uint64_t cycles = 0;
    fast.process(frames[i], cfg, runs, cycles);
    const stream::CorridorReadout f = fast.corridor();
    model.process(frames[i], cfg, runs, cycles);
    const stream::CorridorReadout m = model.corridor();
    rtl.process(frames[i], cfg, runs, cycles);
    const stream::CorridorReadout r = rtl.corridor();
    std::printf("frame %zu: %zu edges, rtl backend %llu cycles for the frame and its readout\n", i,
                pts.size(), static_cast<unsigned long long>(cycles));
    for (const stream::CorridorReadout* c : {&f, &m, &r}) {
      EXPECT_TRUE(c->valid) << "frame " << i;
      EXPECT_EQ(c->shape.lanes, shape.lanes);
      EXPECT_EQ(c->shape.theta_step, shape.theta_step);
      EXPECT_EQ(c->shape.rho_bits, shape.rho_bits);
      EXPECT_EQ(c->shape.acc_bits, shape.acc_bits);
      EXPECT_EQ(c->frame_count, i + 1);
      EXPECT_EQ(c->edges_emitted(), pts.size()) << "frame " << i;
      EXPECT_EQ(c->edges_dropped(), 0u);
      EXPECT_FALSE(c->edge_overflow());
      EXPECT_EQ(c->counters.edges, pts.size());
      EXPECT_TRUE(c->consistent);
      EXPECT_TRUE(c->cells == want) << "frame " << i << ": accumulator differs from golden";
    }
    EXPECT_EQ(f.counters, m.counters) << "frame " << i;
    EXPECT_EQ(f.counters, r.counters) << "frame " << i;
    EXPECT_EQ(f.hough_stalls, 0u);  // the fast backend has no clock
    EXPECT_GT(r.hough_stalls, 0u);  // the voter throttles the edge stream
  }
}

}  // namespace
}  // namespace ceilnav::app
