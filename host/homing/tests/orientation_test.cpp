// The major orientation (golden::orientation_histogram_ref's histogram, the
// host's peak): synthetic gratings at known angles, the four directions of
// a grid in one bin, the folding and the circular interpolation across
// 0 / 90 deg, the histogram's bins, and bad input.
#include "host/homing/orientation.hpp"

#include "golden/orientation_ref.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace ceilnav::host::homing {
using golden::orientation_histogram_ref;
using golden::OrientationParams;
namespace {

// A smooth grating whose intensity varies along the direction `deg` (image
// angle: clockwise from +u): its gradients point along deg or deg + 180.
cv::Mat grating(double deg, double period_px = 23.0) {
  cv::Mat img(240, 320, CV_8UC1);
  const double a = deg * std::numbers::pi / 180.0;
  for (int v = 0; v < img.rows; ++v) {
    for (int u = 0; u < img.cols; ++u) {
      const double s = u * std::cos(a) + v * std::sin(a);
      img.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(
          128.0 + 90.0 * std::sin(2.0 * std::numbers::pi * s / period_px));
    }
  }
  return img;
}

TEST(OrientationRef, GratingsAtKnownAngles) {
  for (double deg : {0.0, 7.3, 22.5, 40.0, 44.6, -12.0, -44.0, 63.0, 101.5, 170.0}) {
    const double got = major_orientation_deg(orientation_histogram_ref(grating(deg)));
    double want = std::fmod(deg, 90.0);
    if (want < -45.0) want += 90.0;
    if (want >= 45.0) want -= 90.0;
    double diff = std::remainder(got - want, 90.0);
    EXPECT_LT(std::abs(diff), 0.2) << deg << " -> " << got;
  }
}

// A tile grid: thin dark lines (Gaussian profile, sigma 1.2 px) every 31 px
// along two perpendicular directions.
cv::Mat grid_of_lines(double deg) {
  cv::Mat img(240, 320, CV_8UC1);
  const double a = deg * std::numbers::pi / 180.0;
  for (int v = 0; v < img.rows; ++v) {
    for (int u = 0; u < img.cols; ++u) {
      const double s = u * std::cos(a) + v * std::sin(a), t = -u * std::sin(a) + v * std::cos(a);
      const double ds = std::remainder(s, 31.0), dt = std::remainder(t, 31.0);
      const double line = std::max(std::exp(-ds * ds / 2.88), std::exp(-dt * dt / 2.88));
      img.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(200.0 - 120.0 * line);
    }
  }
  return img;
}

TEST(OrientationRef, AGridVotesItsFourDirectionsTogether) {
  const cv::Mat grid = grid_of_lines(17.0);
  const std::vector<double> h = orientation_histogram_ref(grid);
  // Thin lines (sigma 1.2 px) carry the high frequencies where the 3 x 3
  // Sobel's angle is least isotropic: within 1 deg (the templates it picks
  // are 10 - 11.25 deg apart).
  EXPECT_NEAR(major_orientation_deg(h), 17.0, 1.0);
  // One direction alone, and its perpendicular alone: the same peak.
  EXPECT_NEAR(major_orientation_deg(orientation_histogram_ref(grating(17.0))), 17.0, 0.2);
  EXPECT_NEAR(major_orientation_deg(orientation_histogram_ref(grating(107.0))), 17.0, 0.2);
}

// A grating at exactly 30 deg: the peak in bin 30 (bins centred on whole
// degrees) and 90 % of the votes within a bin of it (the 3 x 3 Sobel's
// angle varies along the grating's phase), nothing at or below the
// magnitude floor.
TEST(OrientationRef, BinsAreCentredOnTheirAngle) {
  const std::vector<double> h = orientation_histogram_ref(grating(30.0, 41.0));
  double total = 0.0;
  for (double v : h) total += v;
  EXPECT_EQ(std::max_element(h.begin(), h.end()) - h.begin(), 30);
  EXPECT_GT((h[29] + h[30] + h[31]) / total, 0.9);
  OrientationParams high;
  high.min_magnitude = 1e6;
  for (double v : orientation_histogram_ref(grating(30.0), high)) EXPECT_EQ(v, 0.0);
}

TEST(OrientationRef, InterpolationWrapsAcrossTheFold) {
  std::vector<double> h(90, 0.0);
  h[89] = 10.0;
  h[0] = 10.0;  // the peak between bins 89 and 0 (centred on 89 and 0 deg): -0.5 deg
  h[1] = 1.0;
  h[88] = 1.0;
  EXPECT_NEAR(major_orientation_deg(h), -0.5, 1e-9);
  EXPECT_TRUE(std::isnan(major_orientation_deg(std::vector<double>(90, 0.0))));
  EXPECT_NEAR(orientation_difference_deg(40.0, -40.0), -10.0, 1e-12);
  EXPECT_NEAR(orientation_difference_deg(-44.0, 44.0), 2.0, 1e-12);
  EXPECT_THROW(orientation_histogram_ref(cv::Mat(2, 2, CV_8UC1, cv::Scalar(0))),
               std::invalid_argument);
  OrientationParams bad;
  bad.bins = 0;
  EXPECT_THROW(orientation_histogram_ref(grating(0.0), bad), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::host::homing
