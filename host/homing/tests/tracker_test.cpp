// Seed 004's template tracking on rendered structured ceilings
// (golden/ceiling): the orientation's sign against the heading, a site
// recorded under a grille found again from offsets and headings all round
// (the site point's pixel against its projection, gamma against the turn),
// the fast mode, a lighting change between recording and return, and no
// `ok` on a ceiling without the site or on the real-image corpus.
#include "host/homing/tracker.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "golden/ceiling/ceiling.hpp"
#include "golden/ceiling/render.hpp"
#include "golden/orientation_ref.hpp"
#include "host/homing/orientation.hpp"
#include "real_corpus.hpp"

namespace ceilnav::host::homing {
namespace {

namespace gc = golden::ceiling;
constexpr double kDeg = std::numbers::pi / 180.0;

struct Frame {
  cv::Mat grey;
  OrientationHistogram histogram;
};

Frame render(const gc::Ceiling& c, const gc::Pose& p, const gc::Lighting& l = {},
             uint64_t seed = 1) {
  gc::RenderParams rp;
  rp.noise_seed = seed;
  Frame f;
  f.grey = gc::render_frame(CameraConfig{}, c, l, p, rp);
  f.histogram = golden::orientation_histogram_ref(f.grey);
  return f;
}

gc::Pose pose(double x, double y, double yaw_deg) {
  gc::Pose p;
  p.x_m = x;
  p.y_m = y;
  p.height_m = 0.5;
  p.yaw_rad = yaw_deg * kDeg;
  return p;
}

// The camera looks up, so the image is the ceiling seen from below, turned
// by the heading: a grid along X at heading yaw appears at the image angle
// -yaw (mod 90; clockwise positive on the screen). The 3 x 3 Sobel's angle
// on the sharp lamp and grille edges is off by up to 1.9 deg here (the
// orientation only picks templates 10 - 11.25 deg apart; the matching
// refines it).
TEST(Tracker, TheGridTurnsAgainstTheHeading) {
  const gc::Ceiling c = gc::office_ceiling();
  for (double yaw_deg : {0.0, 10.0, 33.0, -20.0, 100.0}) {
    const double got = major_orientation_deg(render(c, pose(0.3, 0.2, yaw_deg)).histogram);
    EXPECT_LT(std::abs(std::remainder(got + yaw_deg, 90.0)), 2.5) << yaw_deg << " -> " << got;
  }
}

// turned_template samples the patch bilinearly at exact coordinates (the
// refinement's sub-pixel shifts are finer than cv::warpAffine's 1 / 32 px):
// whole-pixel shifts and quarter turns move pixels as cv::warpAffine does,
// a half-pixel shift averages neighbours, a shift far beyond the patch
// repeats its edge, and any turn agrees with cv::warpAffine to within the
// effect of its rounding (1 / 64 px each way times the steepest slope).
cv::Mat warp_affine_reference(const cv::Mat& patch, double gamma_deg, int side, double sx,
                              double sy) {
  const double c_in = 0.5 * (patch.cols - 1), c_out = 0.5 * (side - 1);
  cv::Mat m = cv::getRotationMatrix2D(
      cv::Point2f(static_cast<float>(c_in), static_cast<float>(c_in)), -gamma_deg, 1.0);
  m.at<double>(0, 2) += c_out - c_in + sx;
  m.at<double>(1, 2) += c_out - c_in + sy;
  cv::Mat out;
  cv::warpAffine(patch, out, m, cv::Size(side, side), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

TEST(Tracker, TurnedTemplateIsBilinearAtExactCoordinates) {
  Site s;
  cv::Mat noise(41, 41, CV_32FC1);
  cv::RNG rng(5);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, s.patch, cv::Size(0, 0), 1.5);
  cv::Mat gx, gy;
  cv::Sobel(s.patch, gx, CV_32F, 1, 0, 3, 0.125);
  cv::Sobel(s.patch, gy, CV_32F, 0, 1, 3, 0.125);
  double slope_x = 0.0, slope_y = 0.0;
  cv::minMaxLoc(cv::abs(gx), nullptr, &slope_x);
  cv::minMaxLoc(cv::abs(gy), nullptr, &slope_y);
  const int side = 25;  // centres 20 and 12: out(u, v) = patch(u + 8, v + 8) unturned
  for (double gamma : {0.0, 90.0, 180.0, -90.0}) {
    for (const auto& [sx, sy] : {std::pair{0.0, 0.0}, {2.0, -1.0}, {-3.0, 4.0}}) {
      EXPECT_LT(cv::norm(turned_template(s, gamma, side, sx, sy),
                         warp_affine_reference(s.patch, gamma, side, sx, sy), cv::NORM_INF),
                1e-3)
          << gamma << " " << sx << " " << sy;
    }
  }
  const cv::Mat half = turned_template(s, 0.0, side, 0.5, 0.0);
  const cv::Mat far = turned_template(s, 0.0, side, 100.0, 0.0);
  for (int v = 0; v < side; ++v) {
    for (int u = 0; u < side; ++u) {
      EXPECT_NEAR(half.at<float>(v, u),
                  0.5f * (s.patch.at<float>(v + 8, u + 7) + s.patch.at<float>(v + 8, u + 8)), 1e-3);
      EXPECT_EQ(far.at<float>(v, u), s.patch.at<float>(v + 8, 0));
    }
  }
  const double bound = (slope_x + slope_y) / 64.0 + 1e-3;
  for (double gamma : {30.0, -17.3, 133.0}) {
    for (const auto& [sx, sy] : {std::pair{0.0, 0.0}, {0.3, -0.7}, {-6.2, 3.9}}) {
      const cv::Mat got = turned_template(s, gamma, side, sx, sy);
      const cv::Mat want = warp_affine_reference(s.patch, gamma, side, sx, sy);
      EXPECT_LT(cv::norm(got, want, cv::NORM_INF), bound) << gamma << " " << sx << " " << sy;
      // The opposite turn is far off: the bound tells the turn's sense.
      EXPECT_GT(cv::norm(got, warp_affine_reference(s.patch, -gamma, side, sx, sy), cv::NORM_INF),
                20.0 * bound)
          << gamma;
    }
  }
}

// The site: beside the office ceiling's grille at (1.5, 0.3) and its smoke
// detector (1.83, 0.11), heading 0. A patch centred on the square grille
// alone would read the same at every quarter turn (the tracker says
// `ambiguous` there, SymmetricSiteIsAmbiguous).
struct Recorded {
  gc::Ceiling ceiling = gc::office_ceiling();
  gc::Pose at = pose(1.65, 0.15, 0.0);
  Site site;
  Recorded() {
    const Frame f = render(ceiling, at);
    site = record_site(f.grey, f.histogram, CameraConfig{});
  }
};

TEST(Tracker, FindsTheSiteFromOffsetsAndHeadingsAllRound) {
  const Recorded r;
  std::printf("site: self-similarity %.3f, rotational %.3f, orientation %.2f deg\n",
              r.site.self_similarity, r.site.rotational_similarity, r.site.major_orientation_deg);
  const SiteTracker tracker(r.site);
  const CameraConfig cam;
  double worst_px = 0.0, worst_deg = 0.0;
  int n = 0;
  for (double yaw : {0.0, 7.0, 35.0, 95.0, 170.0, -100.0, -44.0}) {
    for (const auto& [dx, dy] : {std::pair{0.0, 0.0}, {0.25, -0.1}, {-0.4, 0.3}, {0.1, 0.45}}) {
      const gc::Pose p = pose(r.at.x_m + dx, r.at.y_m + dy, yaw);
      const Frame f = render(r.ceiling, p, {}, static_cast<uint64_t>(++n));
      const TrackResult t = tracker.track(f.grey, f.histogram);
      const auto want = gc::project(cam, r.ceiling, p, r.at.x_m, r.at.y_m);
      ASSERT_TRUE(want.has_value());
      const double e_px = std::hypot(t.x_px - want->x(), t.y_px - want->y());
      const double e_deg = std::abs(std::remainder(t.gamma_deg + yaw, 360.0));
      EXPECT_EQ(t.status, TrackStatus::ok) << yaw << " " << dx << " " << dy;
      EXPECT_LT(e_px, 0.1) << yaw << " " << dx << " " << dy;
      EXPECT_LT(e_deg, 0.15) << yaw << " " << dx << " " << dy;
      worst_px = std::max(worst_px, e_px);
      worst_deg = std::max(worst_deg, e_deg);
    }
  }
  std::printf("%d frames: worst %.3f px, %.3f deg\n", n, worst_px, worst_deg);
}

// A search near a prediction smooths and reduces only the part of the
// frame it reaches; the site found is the whole frame's (the same smoothed
// pixels, the coarse level's to pyrDown's float rounding, so the same
// coarse peak and refinement), also where the reach meets the frame's edge.
TEST(Tracker, ASearchNearAPredictionFindsWhatTheWholeFrameDoes) {
  const Recorded r;
  const SiteTracker whole(r.site);
  TrackerOptions near_options;
  near_options.search_radius_px = 60.0;
  const SiteTracker near(r.site, near_options);
  const CameraConfig cam;
  int n = 0;
  for (const gc::Pose& p : {pose(1.9, 0.05, 35.0), pose(2.6, 0.15, 0.0), pose(0.35, 1.05, 0.0),
                            pose(1.65, -0.85, 20.0), pose(2.55, 0.9, -30.0)}) {
    const Frame f = render(r.ceiling, p, {}, static_cast<uint64_t>(40 + n++));
    const auto at = gc::project(cam, r.ceiling, p, r.at.x_m, r.at.y_m);
    ASSERT_TRUE(at.has_value());
    const TrackResult a = whole.track(f.grey, f.histogram);
    const TrackResult b =
        near.track(f.grey, f.histogram, cv::Point2d(at->x() + 7.0, at->y() - 5.0));
    std::printf("site at (%.1f, %.1f): %s\n", at->x(), at->y(), to_string(b.status));
    EXPECT_EQ(a.status, TrackStatus::ok);
    EXPECT_EQ(b.status, TrackStatus::ok);
    EXPECT_NEAR(a.x_px, b.x_px, 1e-6);
    EXPECT_NEAR(a.y_px, b.y_px, 1e-6);
    EXPECT_NEAR(a.gamma_deg, b.gamma_deg, 1e-6);
    EXPECT_NEAR(a.score, b.score, 1e-6);
  }
}

TEST(Tracker, FastModeAndALightingChange) {
  const Recorded r;
  const SiteTracker tracker(r.site);
  gc::Lighting dim;
  dim.gain = 0.7;
  dim.gradient_x_per_m = 0.08;
  dim.lamp_gain = 0.8;
  const gc::Pose p = pose(r.at.x_m + 0.2, r.at.y_m - 0.15, 4.0);
  const Frame f = render(r.ceiling, p, dim, 7);
  const auto want = gc::project(CameraConfig{}, r.ceiling, p, r.at.x_m, r.at.y_m);
  for (const std::optional<double> prediction :
       {std::optional<double>(), std::optional<double>(-1.0)}) {
    const TrackResult t = tracker.track(f.grey, f.histogram, std::nullopt, prediction);
    EXPECT_EQ(t.status, TrackStatus::ok);
    EXPECT_LT(std::hypot(t.x_px - want->x(), t.y_px - want->y()), 0.1);
    EXPECT_LT(std::abs(std::remainder(t.gamma_deg + 4.0, 360.0)), 0.15);
  }
}

TEST(Tracker, SymmetricSiteIsAmbiguous) {
  const gc::Ceiling c = gc::office_ceiling();
  const gc::Pose at = pose(1.5, 0.3, 0.0);  // centred on the square grille
  const Frame rec = render(c, at);
  const Site site = record_site(rec.grey, rec.histogram, CameraConfig{});
  EXPECT_GT(site.rotational_similarity, 0.95);
  const SiteTracker tracker(site);
  const Frame f = render(c, pose(1.6, 0.25, 35.0), {}, 3);
  EXPECT_EQ(tracker.track(f.grey, f.histogram).status, TrackStatus::ambiguous);
}

TEST(Tracker, NoSiteNoOk) {
  const Recorded r;
  const SiteTracker tracker(r.site);
  // The same office ceiling elsewhere (no grille in view) and another ceiling.
  int claimed = 0, frames = 0;
  for (const gc::Pose& p : {pose(-1.5, -0.9, 0.0), pose(4.5, 0.9, 30.0), pose(-6.0, 2.0, -60.0)}) {
    const Frame f = render(r.ceiling, p);
    claimed += tracker.track(f.grey, f.histogram).status == TrackStatus::ok;
    ++frames;
  }
  const gc::Ceiling hall = gc::hall_ceiling();
  for (double x : {0.0, 1.2, 5.0}) {
    const Frame f = render(hall, pose(x, 0.0, 15.0));
    claimed += tracker.track(f.grey, f.histogram).status == TrackStatus::ok;
    ++frames;
  }
  for (const test_support::RealFrame& rf : test_support::load_real_corpus()) {
    claimed += tracker.track(rf.grey, golden::orientation_histogram_ref(rf.grey)).status ==
               TrackStatus::ok;
    ++frames;
  }
  std::printf("no site: %d frames, %d ok\n", frames, claimed);
  EXPECT_EQ(claimed, 0);
}

}  // namespace
}  // namespace ceilnav::host::homing
