// The orientation block's fixed-point vote (fixedpoint/orientation.hpp) and
// histogram (golden::orientation_histogram_fixed) against the floating-point
// reference (golden::orientation_histogram_ref): every gradient a 3 x 3 Sobel
// can produce, exhaustively, for the angle and magnitude bounds of
// docs/blocks/orientation.md and the bin agreement away from the bin edges;
// then whole images, vote by vote and bin by bin.
#include "golden/orientation_ref.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "fixedpoint/orientation.hpp"

namespace ceilnav::golden {
namespace {

namespace fo = fp::orientation;

// The derived bounds (docs/blocks/orientation.md, "Bounds").
constexpr double kUnitDeg = 90.0 / fo::kAngleOne;
// Ratio rounding 2^-9 (atan' <= 1) in degrees, plus half a table unit.
const double kAngleBoundDeg = std::ldexp(1.0, -9) * 180.0 / std::numbers::pi + kUnitDeg / 2;
// The weight's ratio to L2 (before the rounding, which adds -3/8 .. +1/2):
// at least 1 / sqrt(1 + 1/16) = 0.97014 (m / M = 1/4), at most
// (7/8 + 2/7) / sqrt(1 + 16/49) = 1.00778 (m / M = 4/7).
const double kWeightLow = 1.0 / std::sqrt(1.0 + 1.0 / 16.0);
const double kWeightHigh = (7.0 / 8.0 + 2.0 / 7.0) / std::sqrt(1.0 + 16.0 / 49.0);
// cv::cartToPolar's angle error (float32 polynomial), bounded here and checked
// exhaustively below.
constexpr double kCartToPolarDeg = 0.01;

// Circular distance on [0, 90).
double fold_dist(double a, double b) {
  return std::abs(std::remainder(a - b, 90.0));
}

// Distance of a folded angle to the nearest bin edge (edges at (k + 1/2) 90 / bins).
double edge_dist(double folded, int bins) {
  const double per = 90.0 / bins;
  const double f = folded / per - 0.5;
  return std::abs(f - std::round(f)) * per;
}

// The float reference's bin of an angle in degrees (as orientation_histogram_ref).
int float_bin(double deg, int bins) {
  const double folded = std::fmod(deg, 90.0);
  return static_cast<int>(std::lround(folded / (90.0 / bins))) % bins;
}

TEST(OrientationFixed, DerivedBoundsHold) {
  EXPECT_NEAR(kAngleBoundDeg, 0.1229, 1e-4);
  EXPECT_NEAR(kWeightLow, 0.97014, 1e-5);
  EXPECT_NEAR(kWeightHigh, 1.00778, 1e-5);
  const auto& t = fo::atan_table();
  EXPECT_EQ(t[0], 0u);
  EXPECT_EQ(t[fo::kAtanEntries - 1], 2043u);  // atan(255/256) = 44.888 deg = 2042.9 units
  EXPECT_TRUE(std::is_sorted(t.begin(), t.end()));
  EXPECT_LT(t.back(), 1u << fo::kAtanBits);
}

// Every gradient (gx, gy) in [-1020, 1020]^2: the angle within kAngleBoundDeg
// of the exact folded atan2, the weight within its bounds, and the bin equal
// to the float reference's (cv::cartToPolar) except within the angle bounds
// of a bin edge. Also bounds cartToPolar itself.
TEST(OrientationFixed, EveryGradientExhaustively) {
  const int n = 2 * fo::kGradMax + 1;
  cv::Mat gx(n, n, CV_32F), gy(n, n, CV_32F);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      gx.at<float>(r, c) = static_cast<float>(c - fo::kGradMax);
      gy.at<float>(r, c) = static_cast<float>(r - fo::kGradMax);
    }
  }
  cv::Mat mag, ang;
  cv::cartToPolar(gx, gy, mag, ang, true);
  double worst_angle = 0, worst_cv = 0, worst_low = 2, worst_high = 0;
  uint64_t disagree[3] = {};  // bins 90, 64, 256
  const int bin_sets[3] = {90, 64, 256};
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const int x = c - fo::kGradMax, y = r - fo::kGradMax;
      if (x == 0 && y == 0) continue;
      double exact = std::atan2(y, x) * 180.0 / std::numbers::pi;
      if (exact < 0) exact += 360.0;
      const double exact_folded = std::fmod(exact, 90.0);
      const uint32_t phi = fo::folded_angle(x, y);
      ASSERT_LE(phi, fo::kAngleOne);
      const double err = fold_dist(phi * kUnitDeg, exact_folded);
      worst_angle = std::max(worst_angle, err);
      ASSERT_LE(err, kAngleBoundDeg) << x << ", " << y;
      const double cv_deg = ang.at<float>(r, c);
      worst_cv = std::max(worst_cv, fold_dist(std::fmod(cv_deg, 90.0), exact_folded));

      const double l2 = std::hypot(x, y);
      const uint32_t w = fo::weight(fo::fold(x, y));
      ASSERT_GE(w, kWeightLow * l2 - 0.5 - 1e-9 * l2) << x << ", " << y;
      // Attained at m / M = 4/7 (e.g. 756, 432: 877.5 + 1/2).
      ASSERT_LE(w, kWeightHigh * l2 + 0.5 + 1e-9 * l2) << x << ", " << y;
      if (l2 >= 512.0) {  // the ratio's extremes, where the rounding is small
        worst_low = std::min(worst_low, w / l2);
        worst_high = std::max(worst_high, w / l2);
      }

      for (int s = 0; s < 3; ++s) {
        const int bins = bin_sets[s];
        const auto fixed_bin = static_cast<int>(fo::bin_of(phi, static_cast<uint32_t>(bins)));
        const int ref_bin = float_bin(cv_deg, bins);
        if (fixed_bin != ref_bin) {
          ++disagree[s];
          ASSERT_LE(edge_dist(std::fmod(cv_deg, 90.0), bins), kAngleBoundDeg + kCartToPolarDeg)
              << x << ", " << y << " bins " << bins;
          const int d = std::abs(fixed_bin - ref_bin);
          ASSERT_EQ(std::min(d, bins - d), 1) << "a neighbour bin only";
        }
      }
    }
  }
  EXPECT_LE(worst_cv, kCartToPolarDeg);
  std::printf(
      "angle error %.4f deg (bound %.4f), cartToPolar %.4f deg, weight / L2 (L2 >= 512) in [%.5f, "
      "%.5f]\n",
      worst_angle, kAngleBoundDeg, worst_cv, worst_low, worst_high);
  std::printf("bin disagreements near edges: %llu (90 bins), %llu (64), %llu (256) of %d\n",
              static_cast<unsigned long long>(disagree[0]),
              static_cast<unsigned long long>(disagree[1]),
              static_cast<unsigned long long>(disagree[2]), n * n - 1);
  // The bounds are attained within a few percent (the analysis is tight).
  EXPECT_GT(worst_angle, 0.8 * kAngleBoundDeg);
  EXPECT_LT(worst_low, kWeightLow + 0.002);
  EXPECT_GT(worst_high, kWeightHigh - 0.002);
}

// Images: a smooth grating, a grid of thin lines, smoothed noise, raw noise.
cv::Mat grating(double deg, int w, int h, double period_px) {
  cv::Mat img(h, w, CV_8UC1);
  const double a = deg * std::numbers::pi / 180.0;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double s = u * std::cos(a) + v * std::sin(a);
      img.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(
          128.0 + 90.0 * std::sin(2.0 * std::numbers::pi * s / period_px));
    }
  }
  return img;
}

cv::Mat grid_of_lines(double deg, int w, int h) {
  cv::Mat img(h, w, CV_8UC1);
  const double a = deg * std::numbers::pi / 180.0;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const double s = u * std::cos(a) + v * std::sin(a), t = -u * std::sin(a) + v * std::cos(a);
      const double ds = std::remainder(s, 31.0), dt = std::remainder(t, 31.0);
      const double line = std::max(std::exp(-ds * ds / 2.88), std::exp(-dt * dt / 2.88));
      img.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(200.0 - 120.0 * line);
    }
  }
  return img;
}

cv::Mat noise(int w, int h, uint32_t seed, double blur) {
  cv::Mat img(h, w, CV_8UC1);
  std::mt19937 rng(seed);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) img.at<uint8_t>(v, u) = static_cast<uint8_t>(rng() & 0xFF);
  }
  if (blur > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), blur);
  return img;
}

// One image: vote by vote, the fixed vote agrees with the float one (same
// threshold) except near a bin edge (bin) or near the threshold (voting);
// the fixed histogram is the sum of its votes (and equals
// orientation_histogram_fixed), and every bin differs from the float bin by
// at most the sum of the per-vote bounds. Returns the number of votes.
int64_t check_image(const cv::Mat& img, int bins, int threshold) {
  cv::Mat gx, gy, mag, ang;
  cv::Sobel(img, gx, CV_32F, 1, 0, 3);
  cv::Sobel(img, gy, CV_32F, 0, 1, 3);
  cv::cartToPolar(gx, gy, mag, ang, true);
  const auto ref = orientation_histogram_ref(img, {bins, static_cast<double>(threshold)});
  const auto fixed = orientation_histogram_fixed(img, {bins, threshold});
  std::vector<uint64_t> sum(static_cast<size_t>(bins), 0);
  std::vector<double> allowed(static_cast<size_t>(bins), 0.0);
  int64_t votes = 0;
  for (int y = 1; y + 1 < img.rows; ++y) {
    for (int x = 1; x + 1 < img.cols; ++x) {
      const int ix = static_cast<int>(gx.at<float>(y, x)),
                iy = static_cast<int>(gy.at<float>(y, x));
      const double l2 = mag.at<float>(y, x);
      const double deg = ang.at<float>(y, x);
      const fo::Vote v =
          fo::vote(ix, iy, static_cast<uint32_t>(threshold), static_cast<uint32_t>(bins));
      const bool ref_votes = l2 > threshold;
      const auto rb = static_cast<size_t>(float_bin(deg, bins));
      if (v.valid) {
        ++votes;
        sum[v.bin] += v.weight;
      }
      if (v.valid != ref_votes) {
        // Only where the weight's bounds straddle the threshold.
        if (v.valid) {
          EXPECT_GE(kWeightHigh * l2 + 0.5 + 1e-3, threshold + 1) << x << ", " << y;
        } else {
          EXPECT_LE(kWeightLow * l2 - 0.5 - 1e-3, threshold) << x << ", " << y;
        }
        if (v.valid) allowed[v.bin] += v.weight;
        if (ref_votes) allowed[rb] += l2;
        continue;
      }
      if (!v.valid) continue;
      EXPECT_GE(v.weight, kWeightLow * l2 - 0.5 - 1e-3) << x << ", " << y;
      EXPECT_LE(v.weight, kWeightHigh * l2 + 0.5 + 1e-3) << x << ", " << y;
      const double weight_err = std::abs(v.weight - l2);
      if (v.bin != rb) {
        EXPECT_LE(edge_dist(std::fmod(deg, 90.0), bins), kAngleBoundDeg + kCartToPolarDeg);
        allowed[v.bin] += v.weight;
        allowed[rb] += l2;
      } else {
        allowed[rb] += weight_err;
      }
    }
  }
  for (size_t k = 0; k < static_cast<size_t>(bins); ++k) {
    EXPECT_EQ(fixed[k], sum[k]) << "bin " << k;  // no saturation at these sizes
    EXPECT_LE(std::abs(static_cast<double>(fixed[k]) - ref[k]), allowed[k] + 1e-6 * ref[k] + 1.0)
        << "bin " << k;
  }
  return votes;
}

size_t peak(const std::vector<uint32_t>& h) {
  return static_cast<size_t>(std::max_element(h.begin(), h.end()) - h.begin());
}

TEST(OrientationFixed, ImagesAgainstTheFloatReference) {
  for (double deg : {0.0, 7.3, 22.5, 40.0, 44.6, -12.0, 63.0, 101.5}) {
    const cv::Mat g = grating(deg, 320, 240, 23.0);
    EXPECT_GT(check_image(g, 90, 16), 50000) << deg;
    // The peak is the grating's angle's bin (folded, 1 degree bins).
    double folded = std::fmod(deg + 360.0, 90.0);
    const auto want = static_cast<size_t>(std::lround(folded) % 90);
    const size_t got = peak(orientation_histogram_fixed(g));
    EXPECT_TRUE(got == want || got == (want + 1) % 90 || got == (want + 89) % 90)
        << deg << ": peak " << got << ", want " << want;
    const cv::Mat grid = grid_of_lines(deg, 320, 240);
    EXPECT_GT(check_image(grid, 90, 16), 10000) << deg;
  }
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    EXPECT_GT(check_image(noise(160, 120, seed, 0.0), 90, 100), 5000);
    EXPECT_GT(check_image(noise(160, 120, seed, 1.5), 64, 8), 1000);
    EXPECT_GT(check_image(noise(97, 61, seed, 0.8), 256, 0), 1000);
  }
}

TEST(OrientationFixed, ThresholdAndBinsOfTheFixedHistogram) {
  const cv::Mat g = grating(30.0, 64, 48, 17.0);
  const auto all = orientation_histogram_fixed(g, {90, 0});
  const auto none = orientation_histogram_fixed(g, {90, 4095});
  uint64_t total = 0;
  for (uint32_t b : all) total += b;
  EXPECT_GT(total, 0u);
  for (uint32_t b : none) EXPECT_EQ(b, 0u);
  // A constant image votes nothing at threshold 0 (weight 0 is not > 0).
  const cv::Mat flat(10, 10, CV_8UC1, cv::Scalar(77));
  for (uint32_t b : orientation_histogram_fixed(flat, {90, 0})) EXPECT_EQ(b, 0u);
  EXPECT_EQ(orientation_histogram_fixed(g, {1, 0}).size(), 1u);
  EXPECT_EQ(orientation_histogram_fixed(g, {1, 0})[0], total);
  EXPECT_THROW(orientation_histogram_fixed(g, {0, 0}), std::invalid_argument);
  EXPECT_THROW(orientation_histogram_fixed(g, {257, 0}), std::invalid_argument);
  EXPECT_THROW(orientation_histogram_fixed(g, {90, 4096}), std::invalid_argument);
  EXPECT_THROW(orientation_histogram_fixed(g, {90, -1}), std::invalid_argument);
  EXPECT_THROW(orientation_histogram_fixed(cv::Mat(2, 5, CV_8UC1), {}), std::invalid_argument);
}

TEST(OrientationFixed, BinsSaturateAt32Bits) {
  EXPECT_EQ(fo::add_saturating(UINT32_MAX - 5, 5), UINT32_MAX);
  EXPECT_EQ(fo::add_saturating(UINT32_MAX - 5, 1403), UINT32_MAX);
  EXPECT_EQ(fo::add_saturating(UINT32_MAX, 1), UINT32_MAX);
  EXPECT_EQ(fo::add_saturating(7, 1403), 1410u);
}

}  // namespace
}  // namespace ceilnav::golden
