// The photometric self-calibration on histograms built from the model it
// inverts (docs/pattern.md §2): levels black + scale * albedo with normal
// noise, the camera's rounding and its clipping to 0..255.
#include <gtest/gtest.h>

#include <cmath>

#include "host/pattern/photometry.hpp"

namespace ceilnav::host::pattern {
namespace {

double phi(double z) {
  return 0.5 * std::erfc(-z / std::sqrt(2.0));
}

// Adds n pixels of level mu, noise sigma, as the camera delivers them.
void add_level(std::array<double, 256>& h, double n, double mu, double sigma) {
  for (int g = 0; g < 256; ++g) {
    const double lo = g == 0 ? -1e9 : (g - 0.5 - mu) / sigma;
    const double hi = g == 255 ? 1e9 : (g + 0.5 - mu) / sigma;
    h[static_cast<std::size_t>(g)] += n * (phi(hi) - phi(lo));
  }
}

struct Camera {
  double black, scale;
};

// A pattern frame's histogram: mostly wall, a disc, bar cores, a side wall
// and some partly inked bar pixels between the bars and the wall.
std::array<uint32_t, 256> frame_histogram(const Camera& c, double sigma = 3.0) {
  const PatternAlbedos a;
  std::array<double, 256> h{};
  add_level(h, 200000.0, c.black + c.scale * a.wall, sigma);
  add_level(h, 8000.0, c.black + c.scale * a.disc, sigma);
  add_level(h, 1500.0, c.black + c.scale * a.bar, sigma);
  add_level(h, 600.0, c.black + c.scale * a.shadow, sigma);
  for (int k = 1; k < 10; ++k) {  // partly inked bar pixels, 10 .. 90 % ink
    add_level(h, 60.0, c.black + c.scale * (a.wall * k / 10.0), sigma);
  }
  std::array<uint32_t, 256> out{};
  for (std::size_t g = 0; g < 256; ++g) out[g] = static_cast<uint32_t>(std::lround(h[g]));
  return out;
}

TEST(Photometry, LevelFromBandCountsInvertsTheBandProbabilities) {
  for (double mu : {58.2, 61.0, 63.9, 66.4}) {
    const double sigma = 3.0;
    const int lo = 56, mid = 63, hi = 70;
    auto p = [&](double x) { return phi((x - mu) / sigma); };
    const double n_lo = 1e4 * (p(mid - 0.5) - p(lo - 0.5));
    const double n_hi = 1e4 * (p(hi - 0.5) - p(mid - 0.5));
    EXPECT_NEAR(level_from_band_counts(n_lo, n_hi, lo, mid, hi, sigma), mu, 1e-6) << mu;
  }
  EXPECT_TRUE(std::isnan(level_from_band_counts(0.0, 10.0, 56, 63, 70, 3.0)));
}

TEST(Photometry, NominalCameraCalibratesToItsLevels) {
  PhotometryOptions o;
  const PhotometricCalibration c = calibrate_photometry(frame_histogram({4.0, 250.0}), {}, o);
  ASSERT_TRUE(c.ok()) << to_string(c.status);
  EXPECT_FALSE(c.disc_clipped);
  EXPECT_FALSE(c.bar_clipped);
  EXPECT_NEAR(c.black, 4.0, 1.0);
  EXPECT_NEAR(c.scale, 250.0, 2.5);
}

TEST(Photometry, GainAndOffsetWithinTheRangeAreFound) {
  PhotometryOptions o;
  // gain 0.8 offset +15: both levels in view; gain 1.2 offset +15: the disc
  // clipped (wall given, as the band counts around the disc measure it);
  // gain 0.8 offset -15: the bars clipped.
  struct Case {
    double gain, offset;
    bool disc_clipped, bar_clipped;
  };
  for (const Case& k : {Case{0.8, 15.0, false, false}, Case{1.2, 15.0, true, false},
                        Case{0.8, -15.0, false, true}, Case{1.0, 0.0, false, false}}) {
    const Camera cam{4.0 + k.offset, 250.0 * k.gain};
    const double wall = cam.black + cam.scale * 0.18;
    const PhotometricCalibration c = calibrate_photometry(
        frame_histogram(cam), {}, o, k.disc_clipped || k.bar_clipped ? wall : -1.0);
    ASSERT_TRUE(c.ok()) << k.gain << " " << k.offset << ": " << to_string(c.status);
    EXPECT_EQ(c.disc_clipped, k.disc_clipped) << k.gain << " " << k.offset;
    EXPECT_EQ(c.bar_clipped, k.bar_clipped) << k.gain << " " << k.offset;
    EXPECT_NEAR(c.gain(o), k.gain, 0.012) << k.gain << " " << k.offset;
    EXPECT_NEAR(c.offset(o), k.offset, 1.0) << k.gain << " " << k.offset;
    if (k.disc_clipped) continue;
    // With the wall measured around the disc: the disc and that wall.
    const PhotometricCalibration w = calibrate_photometry(frame_histogram(cam), {}, o, wall);
    ASSERT_TRUE(w.ok()) << k.gain << " " << k.offset << ": " << to_string(w.status);
    EXPECT_NEAR(w.gain(o), k.gain, 0.012) << k.gain << " " << k.offset;
    EXPECT_NEAR(w.offset(o), k.offset, 1.0) << k.gain << " " << k.offset;
  }
}

TEST(Photometry, BeyondTheRangeIsRefused) {
  PhotometryOptions o;
  // Gain 0.6 and offset +30 are measured and refused; gain 0.4 (the disc
  // darker than the nominal disc threshold) and offset +60 (the disc
  // clipped, the bars brighter than the nominal wall) are not calibrated
  // either; gain 1.2 with offset -15 clips both the bars and the disc: one
  // level, two unknowns.
  EXPECT_EQ(calibrate_photometry(frame_histogram({4.0, 150.0}), {}, o).status,
            PhotometryStatus::out_of_range);
  EXPECT_EQ(calibrate_photometry(frame_histogram({34.0, 250.0}), {}, o, 79.0).status,
            PhotometryStatus::out_of_range);
  EXPECT_FALSE(calibrate_photometry(frame_histogram({4.0, 100.0}), {}, o).ok());
  EXPECT_FALSE(calibrate_photometry(frame_histogram({64.0, 250.0}), {}, o).ok());
  EXPECT_EQ(calibrate_photometry(frame_histogram({-11.0, 300.0}), {}, o, 43.0).status,
            PhotometryStatus::clipped);
  // Nothing brighter than the wall.
  std::array<double, 256> h{};
  add_level(h, 300000.0, 49.0, 3.0);
  std::array<uint32_t, 256> wall_only{};
  for (std::size_t g = 0; g < 256; ++g) wall_only[g] = static_cast<uint32_t>(std::lround(h[g]));
  EXPECT_EQ(calibrate_photometry(wall_only, {}, o).status, PhotometryStatus::no_disc);
}

}  // namespace
}  // namespace ceilnav::host::pattern
