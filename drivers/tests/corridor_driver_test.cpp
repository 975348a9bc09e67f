// host::Driver::read_corridor on the C++ device (ModelBus, co-simulated
// cycle-exact with the RTL): a rendered 640 x 480 corridor frame through the
// LUT remap, the edge block and the hough voter gives golden::hough_ref on
// golden::find_edges_ref of the remapped frame, cell for cell, with the
// counters; measures the cycles from the frame's EOF beat to the hough
// publication (STATUS.HOUGH_PENDING falling) and the host reads per frame
// (docs/blocks/ceilnav_top.md, "Corridor readout").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/corridor_results.hpp"
#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "common/pipeline_config.hpp"
#include "drivers/model_bus.hpp"
#include "golden/default_scene.hpp"
#include "golden/edge_ref.hpp"
#include "golden/hough_ref.hpp"
#include "golden/renderer.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "host/driver.hpp"

namespace ceilnav {
namespace {

// Edges of the EOF beat and of the hough publication, bus reads.
class CorridorWatch : public drivers::SimObserver {
 public:
  explicit CorridorWatch(const drivers::ModelBus& bus) : bus_(bus) {}
  void on_edge(uint64_t edge, const drivers::SimInputs& in,
               const drivers::SimOutputs& out) override {
    const stream::VideoBeat& v = in.s_axis_video;
    if (v.tvalid && v.tlast) last_eol = edge;  // the EOF beat is the frame's last EOL
    if (bus_.top().pipeline().hough_done()) done = edge - 1;  // done is high after its edge
    if (in.s_axil.arvalid && out.s_axil.arready) ++reads;
  }
  uint64_t last_eol = 0;
  uint64_t done = 0;
  uint64_t reads = 0;

 private:
  const drivers::ModelBus& bus_;
};

TEST(CorridorDriver, RenderedFrameAccumulatorEqualsGoldenAndEofToReadyCycles) {
  host::CameraConfig cam = golden::default_camera();  // 640 x 480
  const auto scene = golden::default_corridor(cam);
  std::vector<cv::Mat> frames;
  for (const auto& d : golden::default_drive(30)) {
    if (frames.size() >= 2) break;
    if (d.pose.x_m < 8.0) continue;
    frames.push_back(golden::render_frame(cam, scene, d.pose, golden::default_render_params()));
  }
  ASSERT_EQ(frames.size(), 2u);
  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(cam.image_width);
  cfg.height = static_cast<uint16_t>(cam.image_height);
  for (unsigned g = 0; g < 256; ++g) {
    cfg.lut[g] = stream::lut_entry(static_cast<uint8_t>(g), g > 128, 0);
  }
  stream::EdgeConfig edge;
  edge.enable = true;
  edge.mode = stream::EdgeMode::kSobel;
  edge.threshold = 100;
  stream::HoughConfig hough;
  hough.enable = true;
  hough.weight_shift = 4;
  hough.rho_shift = 5;  // 32-pixel bins: 64 bins cover rho in [-640, 1408)
  hough.width = cfg.width;

  drivers::ModelBus bus;
  host::Driver driver(bus);
  driver.identify();
  CorridorWatch watch(bus);
  bus.set_observer(&watch);
  const stream::HoughShape shape;
  for (size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat& img = frames[i];
    driver.configure(cfg);
    driver.configure_corridor(edge, hough);
    ASSERT_TRUE(driver.has_corridor());
    bus.queue_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], drivers::FrameFeed{});
    driver.read_frame();
    const uint64_t reads_before = watch.reads;
    const stream::CorridorReadout c = driver.read_corridor();
    const uint64_t readout_reads = watch.reads - reads_before;

    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(img, cfg.lut, remap, mask);
    const std::vector<stream::EdgeRecord> pts =
        golden::find_edges_ref(remap, {edge.mode, edge.threshold});
    const std::vector<uint32_t> want = golden::hough_cells_ref(shape, hough, pts);
    EXPECT_TRUE(c.valid);
    EXPECT_TRUE(c.consistent);
    EXPECT_EQ(c.frame_count, i + 1);
    EXPECT_EQ(c.edges_emitted(), pts.size());
    EXPECT_EQ(c.edges_dropped(), 0u);
    EXPECT_EQ(c.counters.edges, pts.size());
    EXPECT_EQ(c.edge, edge);
    EXPECT_EQ(c.cells.size(), static_cast<size_t>(shape.n_theta()) * shape.rho_bins());
    EXPECT_TRUE(c.cells == want) << "frame " << i << ": accumulator differs from golden";
    EXPECT_GT(*std::max_element(c.cells.begin(), c.cells.end()), 0u);
    ASSERT_GT(watch.done, watch.last_eol);
    const uint64_t eof_to_ready = watch.done - watch.last_eol;
    std::printf(
        "[corridor] frame %zu, %dx%d: %zu edge points (%.2f %% of the pixels), EOF -> hough "
        "published %llu cycles, %u stall cycles since reset, %llu bus reads in read_corridor\n",
        i, img.cols, img.rows, pts.size(),
        100.0 * static_cast<double>(pts.size()) / static_cast<double>(img.total()),
        static_cast<unsigned long long>(eof_to_ready), c.hough_stalls,
        static_cast<unsigned long long>(readout_reads));
    RecordProperty("eof_to_hough_published_cycles_" + std::to_string(i),
                   std::to_string(eof_to_ready));
    // The readout reads the cells once and a fixed set of words around them.
    EXPECT_LE(readout_reads, c.cells.size() + 16);
  }
}

TEST(CorridorDriver, TapeDeviceHasNoCorridor) {
  drivers::SimBusOptions opt;
  opt.device_config = regs::kConfigTape;
  drivers::ModelBus bus(opt);
  host::Driver driver(bus);
  driver.identify();
  driver.configure(stream::PipelineConfig{});
  EXPECT_FALSE(driver.has_corridor());
  EXPECT_THROW(driver.configure_corridor(stream::EdgeConfig{}, stream::HoughConfig{}),
               std::runtime_error);
  EXPECT_THROW(driver.read_corridor(), std::runtime_error);
}

}  // namespace
}  // namespace ceilnav
