// The driver over the C++ device model (ModelBus) reads exactly what
// Pipeline::process_frame computes: histogram, moments, runs, counters; with
// both run sinks, random AXI-Lite timing, video gaps and run back-pressure.
#include "host/driver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "ceilnav/regs.hpp"
#include "common/version.hpp"
#include "drivers/model_bus.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/pipeline.hpp"

namespace ceilnav::drivers {
namespace {

using host::Bus;
using host::BusError;
using host::Driver;
using host::DriverOptions;
using host::FrameReadout;
using host::RunSink;

cv::Mat random_image(std::mt19937& rng, int w, int h) {
  cv::Mat img(h, w, CV_8UC1);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) img.at<uint8_t>(y, x) = static_cast<uint8_t>(byte(rng));
  }
  return img;
}

stream::PipelineConfig random_config(std::mt19937& rng, int w, int h) {
  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(w);
  cfg.height = static_cast<uint16_t>(h);
  std::uniform_int_distribution<int> byte(0, 255);
  if (byte(rng) < 128) {
    cfg.lut = stream::threshold_lut(static_cast<uint8_t>(60 + byte(rng) / 2));
  } else {
    for (stream::LutEntry& e : cfg.lut) {
      e = stream::lut_entry(static_cast<uint8_t>(byte(rng)), byte(rng) > 150);
    }
  }
  cfg.background_level = static_cast<uint8_t>(byte(rng) / 4);
  cfg.min_run_length = static_cast<uint16_t>(1 + byte(rng) % 3);
  cfg.max_runs_per_row = static_cast<uint16_t>(1 + byte(rng) % 12);
  cfg.hist_source_remap = byte(rng) < 128;
  return cfg;
}

struct Case {
  RunSink sink = RunSink::kStream;
  double axi_delay = 0.0;
  double gap = 0.0;
  double tready_low = 0.0;
};

// Frames through Driver + ModelBus against Pipeline::process_frame on an
// identically configured reference, frame by frame. Returns the runs seen.
size_t check_frames(const Case& c, const std::vector<cv::Mat>& frames,
                    const std::vector<stream::PipelineConfig>& configs, uint64_t seed) {
  SimBusOptions opt;
  opt.seed = seed;
  opt.axi_timing = {c.axi_delay, c.axi_delay};
  opt.run_tready_low_probability = c.tready_low;
  ModelBus bus(opt);
  DriverOptions dopt;
  dopt.run_sink = c.sink;
  Driver driver(bus, dopt);
  EXPECT_EQ(driver.identify(), version_word());
  stream::Pipeline ref;
  size_t runs_seen = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const cv::Mat& img = frames[k];
    const std::string what = "frame " + std::to_string(k);
    driver.configure(configs[k]);
    ref.set_config(configs[k]);
    std::vector<stream::RunRecord> ref_runs;
    stream::FrameResults expected =
        ref.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], &ref_runs);
    bus.queue_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], {c.gap, 64});
    const FrameReadout got = driver.read_frame();

    if (c.gap > 0.0) {
      EXPECT_GT(got.results.cycles_in_frame, expected.cycles_in_frame) << what;
      expected.cycles_in_frame = got.results.cycles_in_frame;
    }
    if (c.sink == RunSink::kRegisters || c.tready_low > 0.0) {
      // process_frame models a consumer that never stalls.
      EXPECT_GE(got.results.run_stats.fifo_high_water, expected.run_stats.fifo_high_water);
      expected.run_stats.fifo_high_water = got.results.run_stats.fifo_high_water;
    }
    EXPECT_EQ(got.results.histogram, expected.histogram) << what;
    EXPECT_EQ(got.results.moments, expected.moments) << what;
    EXPECT_EQ(got.results.run_stats, expected.run_stats) << what;
    EXPECT_EQ(got.results.errors, expected.errors) << what;
    EXPECT_EQ(got.results, expected) << what;
    EXPECT_EQ(got.runs, ref_runs) << what;
    runs_seen += got.runs.size();
    EXPECT_TRUE(got.trailer_seen) << what;
    EXPECT_EQ(got.trailer_run_count, std::min<size_t>(ref_runs.size(), 0xFFFF)) << what;
    EXPECT_EQ(got.trailer_flags,
              expected.run_stats.runs_dropped_row_limit != 0 ? stream::kTrailerRowLimitHit : 0)
        << what;
    EXPECT_EQ(got.frame_count, k + 1) << what;
    EXPECT_EQ(got.eof_to_irq_cycles, static_cast<uint32_t>(stream::CeilnavTop::kEofToIntrCycles))
        << what;
    EXPECT_EQ(got.intr_state, stream::CeilnavTop::kIntrFrameDone) << what;
    EXPECT_TRUE(got.consistent) << what;
  }
  EXPECT_EQ(bus.top().pipeline().error_counters().frames_ok, frames.size());
  return runs_seen;
}

TEST(Driver, IdentifyRejectsAnotherDevice) {
  ModelBus bus;
  Driver driver(bus);
  EXPECT_EQ(driver.identify(), version_word());
  // A bus whose ID register reads something else.
  class WrongId : public ModelBus {
   public:
    uint32_t read32(uint32_t addr) override {
      return addr == regs::id::kOffset ? 0x12345678u : ModelBus::read32(addr);
    }
  } wrong;
  Driver other(wrong);
  EXPECT_THROW(other.identify(), std::runtime_error);
}

TEST(Driver, SlverrThrowsBusError) {
  ModelBus bus;
  EXPECT_THROW(bus.read32(0x3FC), BusError);
  EXPECT_THROW(bus.write32(regs::id::kOffset, 1), BusError);
  EXPECT_NO_THROW(bus.write32(regs::width::kOffset, 100));
  EXPECT_EQ(bus.read32(regs::width::kOffset), 100u);
}

TEST(Driver, NoFrameTimesOut) {
  ModelBus bus;
  DriverOptions opt;
  opt.irq_timeout_cycles = 500;
  Driver driver(bus, opt);
  driver.configure(stream::PipelineConfig{});
  EXPECT_THROW(driver.read_frame(), std::runtime_error);
}

std::vector<cv::Mat> random_frames(std::mt19937& rng, int n, int w, int h,
                                   std::vector<stream::PipelineConfig>& configs) {
  std::vector<cv::Mat> frames;
  for (int i = 0; i < n; ++i) {
    frames.push_back(random_image(rng, w, h));
    configs.push_back(random_config(rng, w, h));
  }
  return frames;
}

TEST(Driver, ModelBusEqualsProcessFrameRandomFramesStreamSink) {
  std::mt19937 rng(101);
  std::vector<stream::PipelineConfig> configs;
  const std::vector<cv::Mat> frames = random_frames(rng, 3, 48, 32, configs);
  EXPECT_GT(check_frames({RunSink::kStream, 0.0, 0.0, 0.0}, frames, configs, 1), 100u);
  EXPECT_GT(check_frames({RunSink::kStream, 0.3, 0.2, 0.4}, frames, configs, 2), 100u);
}

TEST(Driver, ModelBusEqualsProcessFrameRandomFramesRegisterSink) {
  std::mt19937 rng(102);
  std::vector<stream::PipelineConfig> configs;
  const std::vector<cv::Mat> frames = random_frames(rng, 3, 48, 32, configs);
  EXPECT_GT(check_frames({RunSink::kRegisters, 0.0, 0.0, 0.0}, frames, configs, 3), 100u);
  EXPECT_GT(check_frames({RunSink::kRegisters, 0.3, 0.2, 0.0}, frames, configs, 4), 100u);
}

// The tape device (no class_moments): the driver reads FEATURES, never
// touches CLASS_WIN_* / CLASS_MOM_* (they answer SLVERR there, which would
// throw), and reads everything else exactly; the class moments stay 0.
TEST(Driver, TapeDeviceSkipsTheAbsentBlock) {
  std::mt19937 rng(103);
  std::vector<stream::PipelineConfig> configs;
  const std::vector<cv::Mat> frames = random_frames(rng, 2, 48, 32, configs);
  SimBusOptions opt;
  opt.device_config = regs::kConfigTape;
  ModelBus bus(opt);
  Driver driver(bus);
  EXPECT_EQ(driver.identify(), version_word());
  EXPECT_THROW(bus.read32(regs::class_mom_lo::kArray.at(0)), BusError);
  stream::Pipeline ref(regs::kRunFifoDepth, /*has_class_moments=*/false);
  for (size_t k = 0; k < frames.size(); ++k) {
    const cv::Mat& img = frames[k];
    driver.configure(configs[k]);
    EXPECT_FALSE(driver.has_class_moments());
    ref.set_config(configs[k]);
    std::vector<stream::RunRecord> ref_runs;
    const stream::FrameResults expected =
        ref.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], &ref_runs);
    bus.queue_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], {0.0, 64});
    const FrameReadout got = driver.read_frame();
    EXPECT_EQ(got.results.histogram, expected.histogram) << k;
    EXPECT_EQ(got.results.moments, expected.moments) << k;
    EXPECT_EQ(got.results.class_moments, stream::ClassMomentResults{}) << k;
    EXPECT_EQ(got.results.run_stats, expected.run_stats) << k;
    EXPECT_EQ(got.runs, ref_runs) << k;
  }
  // The full device reports its class_moments.
  ModelBus full;
  Driver full_driver(full);
  full_driver.configure(configs[0]);
  EXPECT_TRUE(full_driver.has_class_moments());
}

TEST(Driver, ModelBusEqualsProcessFrameRenderedFrames) {
  host::CameraConfig cam;
  cam.image_width = 160;
  cam.image_height = 120;
  cam.camera_matrix = {130.0, 0.0, 80.0, 0.0, 129.5, 59.0, 0.0, 0.0, 1.0};
  cam.distortion_coefficients = {-0.08, 0.015, 0.0004, -0.0003, 0.0};
  cam.camera_pitch_deg = 60.0;
  cam.camera_height_m = 0.5;
  cam.ceiling_height_m = 2.8;
  cam.tape_width_m = 0.05;
  const golden::CeilingScene scene = golden::single_tape_scene(0.05);
  golden::RenderParams rp;
  rp.tape_gain = 1200.0;
  rp.noise_sigma_grey = 3.0;
  std::vector<cv::Mat> frames;
  std::vector<stream::PipelineConfig> configs;
  for (int k = 0; k < 3; ++k) {
    rp.noise_seed = static_cast<uint64_t>(k + 1);
    frames.push_back(golden::render_frame(cam, scene, {1.0 * k, 0.1 * k, 0.05 * k}, rp));
    stream::PipelineConfig cfg;
    cfg.width = 160;
    cfg.height = 120;
    cfg.lut = stream::threshold_lut(static_cast<uint8_t>(40 + 10 * k));
    cfg.background_level = 20;
    cfg.min_run_length = 2;
    cfg.max_runs_per_row = 4;
    cfg.hist_source_remap = k == 1;
    configs.push_back(cfg);
  }
  EXPECT_GT(check_frames({RunSink::kStream, 0.2, 0.1, 0.2}, frames, configs, 5), 100u);
  EXPECT_GT(check_frames({RunSink::kRegisters, 0.2, 0.1, 0.0}, frames, configs, 6), 100u);
}

}  // namespace
}  // namespace ceilnav::drivers
