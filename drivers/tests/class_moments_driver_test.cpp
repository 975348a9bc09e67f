// host::Driver reads class_moments (CLASS_MOM_LO/HI) into
// FrameResults::class_moments: through ModelBus (the C++ device, co-simulated
// cycle-exact with the RTL) they equal cv::moments of each class mask inside
// the class window the driver programmed, and Pipeline::process_frame.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "common/pipeline_config.hpp"
#include "drivers/model_bus.hpp"
#include "golden/class_moments_ref.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "host/driver.hpp"
#include "stream/pipeline.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav {
namespace {

TEST(ClassMomentsDriver, DriverReadsClassMomentsEqualToCvMoments) {
  std::mt19937 rng(601);
  std::vector<cv::Mat> frames;
  for (const std::string& name : stream::test::photo_names()) {
    const auto img = stream::test::load_photo(name, 640, 480);
    if (!img) continue;
    cv::Mat small;
    cv::resize(*img, small, cv::Size(200, 150), 0, 0, cv::INTER_AREA);
    frames.push_back(small);
    if (frames.size() == 3) break;
  }
  ASSERT_GE(frames.size(), 2u) << "opencv-doc photos missing";

  drivers::ModelBus bus;
  host::Driver driver(bus);
  driver.identify();
  stream::Pipeline ref;
  std::uniform_int_distribution<int> xs(0, 210);
  std::uniform_int_distribution<int> ys(0, 160);
  for (size_t k = 0; k < frames.size(); ++k) {
    const cv::Mat& img = frames[k];
    stream::PipelineConfig cfg;
    cfg.width = 200;
    cfg.height = 150;
    // Classes in grey bands; a different band width and window per frame.
    const auto band = static_cast<unsigned>(40 + 13 * k);
    for (unsigned g = 0; g < 256; ++g) {
      cfg.lut[g] =
          stream::lut_entry(static_cast<uint8_t>(g), g > 128, static_cast<uint8_t>((g / band) % 4));
    }
    if (k > 0) {
      cfg.class_window = {static_cast<uint16_t>(xs(rng)), static_cast<uint16_t>(xs(rng)),
                          static_cast<uint16_t>(ys(rng)), static_cast<uint16_t>(ys(rng))};
      if (cfg.class_window.x1 < cfg.class_window.x0) {
        std::swap(cfg.class_window.x0, cfg.class_window.x1);
      }
      if (cfg.class_window.y1 < cfg.class_window.y0) {
        std::swap(cfg.class_window.y0, cfg.class_window.y1);
      }
    }
    const std::string what = "frame " + std::to_string(k);
    driver.configure(cfg);
    ref.set_config(cfg);
    const stream::FrameResults want =
        ref.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], nullptr);
    bus.queue_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], {0.05, 64});
    const host::FrameReadout got = driver.read_frame();
    const stream::ClassMomentResults golden =
        golden::class_moments_ref(golden::lut_class_ref(img, cfg.lut), cfg.class_window);
    EXPECT_EQ(got.results.class_moments, golden) << what;
    EXPECT_EQ(got.results.class_moments, want.class_moments) << what;
    EXPECT_EQ(got.results.moments, want.moments) << what;
    if (k == 0) {  // whole frame: every class present in the photo
      for (int c = 1; c <= stream::kMomentClasses; ++c) {
        EXPECT_GT(golden.of(c)[stream::kM00], 0u) << what << " class " << c;
      }
    }
  }
}

}  // namespace
}  // namespace ceilnav
