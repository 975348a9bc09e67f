// stream::EdgeHoughFast == golden, exactly: the edge list of
// golden::find_edges_ref and the accumulator of golden::hough_ref on it (every
// cell), on seed 002 corridor renders and on random frames, in every edge
// mode and across the Hough configurations (theta sub-ranges, weight shift,
// unit weight, rho shift, rho bias, disabled) and shapes; vote and drop
// counts; buffers reused across frames of changing size; argument checks.
#include "stream/edge_hough_fast.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <span>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "golden/corridor/corridor.hpp"
#include "golden/corridor/render.hpp"
#include "golden/default_scene.hpp"
#include "golden/edge_ref.hpp"
#include "golden/hough_ref.hpp"

namespace ceilnav::stream {
namespace {

constexpr EdgeMode kAllModes[] = {EdgeMode::kHorizontal, EdgeMode::kVertical, EdgeMode::kSobel,
                                  EdgeMode::kReserved};

// Compares one frame (a CV_8UC1 view, any step) against golden; returns the
// golden edge count. `what` names the case in failure messages.
size_t expect_equals_golden(EdgeHoughFast& fast, const cv::Mat& img, const EdgeConfig& ec,
                            const HoughConfig& hc, const std::string& what) {
  const auto acc = fast.run(ec, hc, img.data, static_cast<uint32_t>(img.cols),
                            static_cast<uint32_t>(img.rows), img.step[0]);
  const std::vector<EdgeRecord> edges = golden::find_edges_ref(img, {ec.mode, ec.threshold});
  const std::span<const EdgeRecord> got = fast.edges();
  EXPECT_TRUE(std::equal(got.begin(), got.end(), edges.begin(), edges.end()))
      << what << ": edge lists differ (" << got.size() << " fast, " << edges.size() << " golden)";
  std::vector<golden::EdgePoint> points;
  for (const EdgeRecord& e : edges) points.push_back({e.x, e.y});
  const std::vector<uint64_t> cells = golden::hough_ref(fast.shape(), hc, points);
  EXPECT_TRUE(std::equal(acc.begin(), acc.end(), cells.begin(), cells.end()))
      << what << ": accumulators differ";
  // Every edge casts one vote per theta of the range: it lands or is dropped.
  const uint64_t thetas =
      hc.enable ? static_cast<uint64_t>(theta_range(fast.shape(), hc).count) : 0u;
  EXPECT_EQ(fast.votes() + fast.dropped(), edges.size() * thetas) << what;
  if (hc.unit_weight || !hc.enable) {
    uint64_t sum = 0;
    for (const uint64_t c : cells) sum += c;
    EXPECT_EQ(fast.votes(), sum) << what;
  }
  return edges.size();
}

HoughConfig full_range(uint16_t width, uint8_t rho_shift) {
  HoughConfig c;
  c.enable = true;
  c.width = width;
  c.rho_shift = rho_shift;
  return c;
}

TEST(EdgeHoughFast, CorridorRendersEqualGolden) {
  const host::CameraConfig camera = golden::default_camera();
  const golden::corridor::Corridor corridor = golden::corridor::default_corridor();
  golden::corridor::Pose turned = golden::corridor::default_pose();
  turned.x_m = 12.0;
  turned.pan_rad = -0.25;
  turned.swing_rad = 0.08;
  golden::corridor::RenderParams params;
  params.supersample = 4;
  EdgeHoughFast fast;
  size_t total_edges = 0;
  for (const golden::corridor::Pose& pose : {golden::corridor::default_pose(), turned}) {
    const cv::Mat img = golden::corridor::render_frame(camera, corridor, pose, params);
    ASSERT_EQ(img.cols, 640);
    ASSERT_EQ(img.rows, 480);
    std::vector<HoughConfig> configs;
    configs.push_back(full_range(640, 5));  // the benchmark's: every vote lands
    HoughConfig c = full_range(640, 3);     // 8-pixel bins: far rhos dropped
    c.theta_first = 10;
    c.theta_count = 7;
    c.weight_shift = 3;
    configs.push_back(c);
    c = full_range(320, 4);
    c.unit_weight = true;
    c.theta_first = 40;  // to the end of the range
    configs.push_back(c);
    c = full_range(640, 5);
    c.enable = false;
    configs.push_back(c);
    for (const EdgeMode mode : kAllModes) {
      for (const uint16_t t : {uint16_t{5}, uint16_t{12}, uint16_t{40}}) {
        const uint16_t threshold = mode == EdgeMode::kSobel ? static_cast<uint16_t>(4 * t) : t;
        for (size_t k = 0; k < configs.size(); ++k) {
          total_edges +=
              expect_equals_golden(fast, img, {true, mode, threshold}, configs[k],
                                   "mode " + std::to_string(static_cast<int>(mode)) + " t " +
                                       std::to_string(threshold) + " config " + std::to_string(k));
        }
      }
    }
  }
  EXPECT_GT(total_edges, 100000u);  // the frames have edges in every mode
}

// A frame of flat blocks, steps and noise: edge points of every magnitude.
cv::Mat random_frame(std::mt19937_64& rng, int w, int h) {
  cv::Mat img(h, w, CV_8UC1);
  std::uniform_int_distribution<int> level(0, 255);
  std::uniform_int_distribution<int> noise(-6, 6);
  std::bernoulli_distribution change(0.15);
  const bool noisy = std::bernoulli_distribution(0.5)(rng);
  int v = level(rng);
  for (int y = 0; y < h; ++y) {
    auto* r = img.ptr<uint8_t>(y);
    for (int x = 0; x < w; ++x) {
      if (change(rng)) v = level(rng);
      const int p = y > 0 && std::bernoulli_distribution(0.5)(rng) ? img.ptr<uint8_t>(y - 1)[x] : v;
      r[x] = static_cast<uint8_t>(std::clamp(p + (noisy ? noise(rng) : 0), 0, 255));
    }
  }
  return img;
}

HoughConfig random_config(std::mt19937_64& rng, int w) {
  auto u = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  HoughConfig c;
  c.enable = u(0, 9) != 0;
  c.unit_weight = u(0, 3) == 0;
  c.weight_shift = static_cast<uint8_t>(u(0, 15));
  c.rho_shift = static_cast<uint8_t>(u(0, 7));
  c.theta_first = static_cast<uint8_t>(u(0, 3) == 0 ? u(0, 255) : u(0, 30));
  c.theta_count = static_cast<uint8_t>(u(0, 3) == 0 ? 0 : u(0, 255));
  c.width = static_cast<uint16_t>(u(0, 3) == 0 ? u(0, 4095) : w);
  return c;
}

TEST(EdgeHoughFast, RandomFramesEveryModeAndConfig) {
  std::mt19937_64 rng(20261127);
  auto u = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  const HoughShape shapes[] = {HoughShape{}, HoughShape{8, 1, 9, 12}, HoughShape{4, 2, 8, 16},
                               HoughShape{2, 60, 3, 16}};
  for (const HoughShape& shape : shapes) {
    EdgeHoughFast fast(shape);  // reused: frames grow and shrink
    for (int i = 0; i < 150; ++i) {
      const int w = u(0, 7) == 0 ? u(100, 400) : u(1, 40);
      const int h = u(0, 7) == 0 ? u(50, 200) : u(1, 40);
      // Half the frames are a window of a wider buffer (step > width).
      const cv::Mat buffer = random_frame(rng, w + (u(0, 1) != 0 ? u(1, 9) : 0), h);
      const cv::Mat img = buffer.colRange(0, w);
      const EdgeMode mode = kAllModes[u(0, 3)];
      const auto threshold = static_cast<uint16_t>(
          u(0, 15) == 0 ? u(0, 4095) : u(0, mode == EdgeMode::kSobel ? 300 : 60));
      expect_equals_golden(
          fast, img, {true, mode, threshold}, random_config(rng, w),
          "frame " + std::to_string(i) + " " + std::to_string(w) + "x" + std::to_string(h));
    }
  }
}

// x and y up to 2047 with the widest bias and rho bins (the largest sums),
// every theta at a 1-degree step.
TEST(EdgeHoughFast, LargestCoordinatesAndSums) {
  std::mt19937_64 rng(7);
  EdgeHoughFast fast(HoughShape{8, 1, 12, 16});
  for (const auto& [w, h] : {std::pair{2048, 3}, std::pair{3, 2048}}) {
    const cv::Mat img = random_frame(rng, w, h);
    for (const uint8_t rho_shift : {uint8_t{0}, uint8_t{7}}) {
      for (const uint16_t width : {uint16_t{0}, uint16_t{2048}, uint16_t{4095}}) {
        for (const EdgeMode mode : {EdgeMode::kHorizontal, EdgeMode::kVertical}) {
          expect_equals_golden(fast, img, {true, mode, 3}, full_range(width, rho_shift),
                               std::to_string(w) + "x" + std::to_string(h));
        }
      }
    }
  }
}

// A wide frame with edges in its last columns, then a narrower one: nothing
// of the first frame's row buffers may appear in the second's edges.
TEST(EdgeHoughFast, ShrinkingFrameReusesBuffersCleanly) {
  EdgeHoughFast fast;
  cv::Mat wide(4, 24, CV_8UC1, cv::Scalar(0));
  for (int y = 0; y < 4; ++y) {
    for (int x = 17; x < 24; x += 2) wide.at<uint8_t>(y, x) = 200;
  }
  EXPECT_EQ(expect_equals_golden(fast, wide, {true, EdgeMode::kHorizontal, 10}, full_range(24, 0),
                                 "wide"),
            28u);
  const cv::Mat narrow(4, 17, CV_8UC1, cv::Scalar(9));
  EXPECT_EQ(expect_equals_golden(fast, narrow, {true, EdgeMode::kHorizontal, 10}, full_range(17, 0),
                                 "narrow"),
            0u);
  EXPECT_EQ(fast.votes(), 0u);
}

TEST(EdgeHoughFast, RejectsBadArguments) {
  EXPECT_THROW(EdgeHoughFast(HoughShape{4, 7, 6, 16}), std::invalid_argument);  // 7 !| 180
  EXPECT_THROW(EdgeHoughFast(HoughShape{4, 4, 13, 16}), std::invalid_argument);
  EdgeHoughFast fast;
  const std::vector<uint8_t> px(2049 * 2, 0);
  const EdgeConfig ec{true, EdgeMode::kHorizontal, 8};
  EXPECT_THROW(fast.find_edges(ec, px.data(), 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(fast.find_edges(ec, px.data(), 2049, 1, 2049), std::invalid_argument);
  EXPECT_THROW(fast.find_edges(ec, px.data(), 1, 2049, 1), std::invalid_argument);
  EXPECT_THROW(fast.find_edges(ec, px.data(), 8, 2, 7), std::invalid_argument);  // stride < width
  fast.find_edges(ec, px.data(), 8, 2, 8);
  HoughConfig hc = full_range(8, 0);
  hc.weight_shift = 16;
  EXPECT_THROW(fast.vote(hc), std::invalid_argument);
  hc = full_range(8, 8);
  EXPECT_THROW(fast.vote(hc), std::invalid_argument);
  hc = full_range(4096, 0);
  EXPECT_THROW(fast.vote(hc), std::invalid_argument);
  hc.enable = false;  // a disabled frame votes nothing, whatever else it says
  const auto acc = fast.vote(hc);
  EXPECT_TRUE(std::all_of(acc.begin(), acc.end(), [](uint64_t c) { return c == 0; }));
}

}  // namespace
}  // namespace ceilnav::stream
