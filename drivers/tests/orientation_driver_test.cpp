// host::Driver::read_orientation on the C++ device in the homing configuration
// (ModelBus, co-simulated cycle-exact with the RTL by cosim_ceilnav_top_homing_test):
// gratings through the LUT remap and the orientation block give
// golden::orientation_histogram_fixed of the remapped frame, bin for bin, read
// through ORI_INDEX / ORI_DATA after the frame's FRAME_DONE.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "ceilnav/regs.hpp"
#include "common/pipeline_config.hpp"
#include "drivers/model_bus.hpp"
#include "golden/orientation_ref.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "host/driver.hpp"

namespace ceilnav {
namespace {

// A sine grating whose gradient points at `deg` degrees (image axes, y down).
cv::Mat grating(int w, int h, double deg, double period) {
  cv::Mat img(h, w, CV_8UC1);
  const double a = deg * M_PI / 180.0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double t = (x * std::cos(a) + y * std::sin(a)) * 2.0 * M_PI / period;
      img.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(128.0 + 90.0 * std::sin(t));
    }
  }
  return img;
}

TEST(OrientationDriver, HistogramThroughRegistersEqualsGoldenFixed) {
  constexpr int kW = 96;
  constexpr int kH = 72;
  stream::PipelineConfig cfg;
  cfg.width = kW;
  cfg.height = kH;
  // A non-identity remap (a contrast stretch): the block sees the remap.
  for (unsigned g = 0; g < 256; ++g) {
    cfg.lut[g] = stream::lut_entry(static_cast<uint8_t>(std::min(255u, g * 5 / 4)), g > 128, 0);
  }
  drivers::SimBusOptions opt;
  opt.device_config = regs::kConfigHoming;
  drivers::ModelBus bus(opt);
  host::Driver driver(bus);
  driver.identify();
  const std::vector<double> angles = {17.0, 63.0, 100.0};
  const std::vector<uint16_t> thresholds = {16, 200, 0};
  for (size_t i = 0; i < angles.size(); ++i) {
    const cv::Mat img = grating(kW, kH, angles[i], 9.0 + static_cast<double>(i));
    driver.configure(cfg);
    ASSERT_TRUE(driver.has_orientation());
    EXPECT_FALSE(driver.has_corridor());
    EXPECT_FALSE(driver.has_class_moments());
    driver.configure_orientation({true, thresholds[i]});
    bus.queue_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], drivers::FrameFeed{});
    driver.read_frame();
    const host::OrientationReadout o = driver.read_orientation();

    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(img, cfg.lut, remap, mask);
    const std::vector<uint32_t> want =
        golden::orientation_histogram_fixed(remap, {90, static_cast<int>(thresholds[i])});
    EXPECT_TRUE(o.valid);
    EXPECT_TRUE(o.consistent);
    EXPECT_EQ(o.frames, i + 1);
    EXPECT_EQ(o.skipped, 0u);
    EXPECT_GT(o.votes, 0u);
    EXPECT_LE(o.votes, static_cast<uint32_t>((kW - 2) * (kH - 2)));
    ASSERT_EQ(o.bins.size(), 90u);
    EXPECT_TRUE(o.bins == want) << "frame " << i << ": histogram differs from golden";
    // The peak is the grating's angle modulo 90 degrees (1-degree bins).
    const auto peak =
        static_cast<int>(std::max_element(o.bins.begin(), o.bins.end()) - o.bins.begin());
    const int expect = static_cast<int>(std::lround(std::fmod(angles[i], 90.0))) % 90;
    const int diff = std::abs(peak - expect);
    EXPECT_LE(std::min(diff, 90 - diff), 1) << "frame " << i << ": peak bin " << peak;
  }
  // Disabled: the frame is ignored, the published histogram stays.
  const host::OrientationReadout before = driver.read_orientation();
  driver.configure(cfg);
  driver.configure_orientation({false, 16});
  const cv::Mat img = grating(kW, kH, 40.0, 8.0);
  bus.queue_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], drivers::FrameFeed{});
  driver.read_frame();
  const host::OrientationReadout after = driver.read_orientation();
  EXPECT_EQ(after.frames, before.frames);
  EXPECT_EQ(after.bins, before.bins);
  EXPECT_EQ(after.votes, before.votes);
}

TEST(OrientationDriver, FullDeviceHasNoOrientation) {
  drivers::ModelBus bus;  // the full configuration
  host::Driver driver(bus);
  driver.identify();
  driver.configure(stream::PipelineConfig{});
  EXPECT_FALSE(driver.has_orientation());
  EXPECT_THROW(driver.configure_orientation({}), std::runtime_error);
  EXPECT_THROW(driver.read_orientation(), std::runtime_error);
}

}  // namespace
}  // namespace ceilnav
