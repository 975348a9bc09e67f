// BlockNcc against cv::matchTemplate (TM_CCOEFF_NORMED): every offset's
// score, by the dot product and by the spectra, on smoothed noise with a
// flat patch (nil variance: scored 0, no evidence), at the coarse search's and the refinement's
// sizes, and templates that are not zero-mean.
#include "host/homing/ncc.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace ceilnav::host::homing {
namespace {

cv::Mat smoothed_noise(int rows, int cols, uint64_t seed) {
  cv::Mat noise(rows, cols, CV_32FC1), out;
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, out, cv::Size(0, 0), 1.5);
  return out;
}

void expect_as_match_template(const cv::Mat& image, const cv::Mat& tmpl, bool expect_flat = false) {
  int flat = 0;
  cv::Mat want;
  cv::matchTemplate(image, tmpl, want, cv::TM_CCOEFF_NORMED);
  BlockNcc ncc(image, tmpl.cols);
  ASSERT_EQ(ncc.cols(), want.cols);
  ASSERT_EQ(ncc.rows(), want.rows);
  const NccTemplate prepared = ncc_template(tmpl);
  const cv::Mat all = ncc.scores(prepared);
  ASSERT_EQ(all.size(), want.size());
  double worst_dot = 0.0, worst_dft = 0.0;
  for (int y = 0; y < want.rows; ++y) {
    for (int x = 0; x < want.cols; ++x) {
      // A block flatter than BlockNcc::kMinRms scores 0 (cv::matchTemplate:
      // 0 or +-1 by its quotient's rounding).
      cv::Scalar mean, rms;
      cv::meanStdDev(image(cv::Rect(x, y, tmpl.cols, tmpl.rows)), mean, rms);
      if (rms[0] < BlockNcc::kMinRms) {
        EXPECT_EQ(ncc.score(prepared, x, y), 0.0);
        EXPECT_EQ(all.at<float>(y, x), 0.0f);
        ++flat;
        continue;
      }
      worst_dot = std::max(worst_dot, std::abs(ncc.score(prepared, x, y) - want.at<float>(y, x)));
      worst_dft = std::max(
          worst_dft, std::abs(static_cast<double>(all.at<float>(y, x) - want.at<float>(y, x))));
    }
  }
  EXPECT_LT(worst_dot, 1e-4) << image.size() << " " << tmpl.size();
  if (expect_flat) {
    EXPECT_GT(flat, 0);
  }
  EXPECT_LT(worst_dft, 1e-4) << image.size() << " " << tmpl.size();
}

TEST(BlockNcc, ScoresAsMatchTemplate) {
  // The coarse search's sizes (an area of the quarter level, a 24 px
  // template) with a flat corner, and the refinement's (a 108 px window,
  // a 96 px template).
  cv::Mat area = smoothed_noise(97, 131, 1);
  area(cv::Rect(0, 0, 40, 30)).setTo(200.0);
  cv::Mat tmpl = smoothed_noise(24, 24, 2);
  area(cv::Rect(70, 50, 24, 24)).copyTo(tmpl(cv::Rect(0, 0, 24, 24)));
  expect_as_match_template(area, tmpl, true);
  expect_as_match_template(area, smoothed_noise(24, 24, 3) + 1000.0, true);
  const cv::Mat win = smoothed_noise(108, 108, 4);
  expect_as_match_template(win, win(cv::Rect(5, 7, 96, 96)).clone());
  expect_as_match_template(win, smoothed_noise(96, 96, 5));
}

TEST(BlockNcc, FindsTheTemplatesPlace) {
  const cv::Mat image = smoothed_noise(80, 90, 6);
  const cv::Mat tmpl = image(cv::Rect(33, 21, 16, 16)).clone();
  BlockNcc ncc(image, 16);
  const NccTemplate prepared = ncc_template(tmpl);
  EXPECT_NEAR(ncc.score(prepared, 33, 21), 1.0, 1e-5);
  double best = 0.0;
  cv::Point at;
  cv::minMaxLoc(ncc.scores(prepared), nullptr, &best, nullptr, &at);
  EXPECT_EQ(at, cv::Point(33, 21));
  EXPECT_NEAR(best, 1.0, 1e-4);
}

TEST(BlockNcc, RejectsAnImageSmallerThanTheTemplate) {
  EXPECT_THROW(BlockNcc(cv::Mat::zeros(10, 30, CV_32FC1), 12), std::invalid_argument);
  EXPECT_THROW(BlockNcc(cv::Mat::zeros(30, 30, CV_8UC1), 12), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::host::homing
