#include "host/tape_pose.hpp"
#include "host/auto_threshold.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/core.hpp>

#include "golden/renderer.hpp"
#include "golden/run_scanner_ref.hpp"
#include "golden/scene.hpp"

namespace ceilnav::host {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

CameraConfig make_config(int w, int h, bool distorted, double pitch_deg) {
  CameraConfig c;
  c.image_width = w;
  c.image_height = h;
  const double f = 0.8 * w;
  c.camera_matrix = {f, 0.0, 0.5 * w - 0.5 + 2.5, 0.0, f, 0.5 * h - 0.5 - 1.5, 0.0, 0.0, 1.0};
  if (distorted) c.distortion_coefficients = {-0.25, 0.08, 8e-4, -6e-4, -0.01};
  c.camera_pitch_deg = pitch_deg;
  c.camera_height_m = 0.5;
  c.ceiling_height_m = 3.0;
  c.tape_width_m = 0.05;
  return c;
}

// Independent projection for the analytic tests, from the rotation of BRIEF §5.
struct Projector {
  Eigen::Matrix3d r;
  Eigen::Vector3d centre;  // camera centre relative to the tape's (x = 0, y = 0, floor)
  const CameraConfig& cfg;
  const CameraModel cam;
  Projector(const CameraConfig& c, double yaw, double offset_m) : cfg(c), cam(c) {
    const double p = c.camera_pitch_deg * kDeg;
    const double sp = std::sin(p), cp = std::cos(p), sy = std::sin(yaw), cy = std::cos(yaw);
    r << sy, -cy, 0.0, sp * cy, sp * sy, -cp, cp * cy, cp * sy, sp;
    centre = {0.0, offset_m, c.camera_height_m};
  }
  // Normalised coordinates of world point (x, y_line, ceiling); z_cam > 0 required.
  bool normalised(double x, double y_line, Eigen::Vector2d& xy) const {
    const Eigen::Vector3d pc = r * (Eigen::Vector3d(x, y_line, cfg.ceiling_height_m) - centre);
    if (pc.z() <= 1e-9) return false;
    xy = pc.head<2>() / pc.z();
    return true;
  }
  // The (distorted) pixel column where the line y = y_line crosses pixel row
  // `row`, by solving for the world x along the line.
  bool column_at_row(double y_line, int row, double& u) const {
    // y_norm(x) is linear-fractional in x: y = (A x + B) / (C x + D).
    const Eigen::Vector3d p0 = r * (Eigen::Vector3d(0.0, y_line, cfg.ceiling_height_m) - centre);
    const Eigen::Vector3d dx = r.col(0);
    double target = (row - cam.cy()) / cam.fy();
    for (int it = 0; it < 60; ++it) {
      // (p0.y + x dx.y) = target (p0.z + x dx.z)
      const double den = dx.y() - target * dx.z();
      if (std::abs(den) < 1e-15) return false;
      const double x = (target * p0.z() - p0.y()) / den;
      Eigen::Vector2d xy;
      if (!normalised(x, y_line, xy)) return false;
      const Eigen::Vector2d px = cam.distort_to_pixel(xy);
      const double err = px.y() - row;
      u = px.x();
      if (std::abs(err) < 1e-11) return true;
      target -= err / cam.fy();
    }
    return false;
  }
};

// Exact runs: the centre of each row on the centre line y = y_line, as if the
// run sums were taken from a perfectly symmetric profile. sum_w = 2^30 keeps the
// quantisation of sum_xw / sum_w at 1e-9 px.
void add_line_runs(const Projector& pr, double y_line, int half_width_px,
                   std::vector<stream::RunRecord>& runs) {
  const int w = pr.cfg.image_width;
  for (int row = 0; row < pr.cfg.image_height; ++row) {
    double u = 0.0;
    if (!pr.column_at_row(y_line, row, u)) continue;
    if (u < half_width_px + 2 || u > w - half_width_px - 3) continue;
    stream::RunRecord rr;
    rr.row = static_cast<uint16_t>(row);
    const int ui = static_cast<int>(std::lround(u));
    rr.x_start = static_cast<uint16_t>(ui - half_width_px);
    rr.x_end = static_cast<uint16_t>(ui + half_width_px);
    rr.sum_w = 1u << 30;
    rr.sum_xw = static_cast<uint64_t>(std::llround(u * static_cast<double>(1u << 30)));
    runs.push_back(rr);
  }
}

void sort_runs(std::vector<stream::RunRecord>& runs) {
  std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) {
    return a.row != b.row ? a.row < b.row : a.x_start < b.x_start;
  });
}

TEST(TapePose, PoseFromCentreLineInvertsProjection) {
  for (double pitch_deg : {20.0, 45.0, 70.0, 90.0}) {
    const CameraConfig c = make_config(640, 480, false, pitch_deg);
    for (double yaw_deg : {-15.0, 0.0, 11.0}) {
      for (double off : {-0.5, 0.0, 0.37}) {
        const Projector pr(c, yaw_deg * kDeg, off);
        Eigen::Vector2d a, b;
        ASSERT_TRUE(pr.normalised(3.0, 0.0, a));
        ASSERT_TRUE(pr.normalised(8.0, 0.0, b));
        const Eigen::Vector3d l =
            Eigen::Vector3d(a.x(), a.y(), 1).cross(Eigen::Vector3d(b.x(), b.y(), 1));
        double yaw = 0, offset = 0;
        for (double s : {1.0, -1.0}) {  // the line's scale and sign do not matter
          ASSERT_EQ(pose_from_centre_line(s * 3.7 * l, pitch_deg * kDeg, c.ceiling_above_camera_m(),
                                          80 * kDeg, yaw, offset),
                    Status::ok);
          EXPECT_NEAR(yaw, yaw_deg * kDeg, 1e-12);
          EXPECT_NEAR(offset, off, 1e-12);
        }
      }
    }
  }
}

TEST(TapePose, PoseFromCentreLineDegenerate) {
  double yaw = 7.0, offset = 7.0;
  // A line parallel to the horizon (y = const).
  EXPECT_EQ(pose_from_centre_line({0.0, 1.0, -0.2}, 45 * kDeg, 2.5, 80 * kDeg, yaw, offset),
            Status::degenerate);
  EXPECT_EQ(pose_from_centre_line({1e-3, 1.0, -0.2}, 45 * kDeg, 2.5, 80 * kDeg, yaw, offset),
            Status::degenerate);
  EXPECT_EQ(pose_from_centre_line({NAN, 1.0, -0.2}, 45 * kDeg, 2.5, 80 * kDeg, yaw, offset),
            Status::degenerate);
  EXPECT_EQ(yaw, 7.0);
  EXPECT_EQ(offset, 7.0);
}

struct SweepStats {
  int cases = 0;
  double max_yaw_err = 0, max_off_err = 0;
};

// (a) analytic: exact run centres from the projection; the maths must invert it.
TEST(TapePose, AnalyticSweepRecoversPoseExactly) {
  SweepStats st;
  for (auto [w, h] : {std::pair{320, 240}, std::pair{640, 480}, std::pair{1280, 960}}) {
    for (bool distorted : {false, true}) {
      for (double pitch_deg : {20.0, 30.0, 45.0, 60.0, 70.0, 90.0}) {
        const CameraConfig c = make_config(w, h, distorted, pitch_deg);
        const CameraModel cam(c);
        for (double yaw_deg : {-15.0, -6.0, 0.0, 4.5, 15.0}) {
          for (double off : {-0.5, -0.21, 0.0, 0.3, 0.5}) {
            const Projector pr(c, yaw_deg * kDeg, off);
            std::vector<stream::RunRecord> runs;
            add_line_runs(pr, 0.0, 2, runs);
            TapePoseOptions opt;
            opt.max_width_factor = 0.0;  // synthetic runs have a fixed width
            const TapePose p = estimate_tape_pose(runs, cam, c, opt);
            ASSERT_EQ(p.status, Status::ok)
                << w << " " << distorted << " " << pitch_deg << " " << yaw_deg << " " << off;
            ++st.cases;
            st.max_yaw_err = std::max(st.max_yaw_err, std::abs(p.yaw_rad - yaw_deg * kDeg));
            st.max_off_err = std::max(st.max_off_err, std::abs(p.offset_m - off));
            EXPECT_NEAR(p.yaw_rad, yaw_deg * kDeg, 1e-9);
            EXPECT_NEAR(p.offset_m, off, 1e-9);
            EXPECT_LT(p.residual_rms_px, 1e-6);
            // The chain's end rows inside the image are dropped (partly covered).
            const int ends = (runs.front().row > 0) + (runs.back().row + 1 < h);
            EXPECT_EQ(p.points_used, p.points_total - ends);
            EXPECT_DOUBLE_EQ(p.pitch_rad, pitch_deg * kDeg);
            if (pitch_deg < 90.0) {
              ASSERT_TRUE(p.vp_finite);
              const Eigen::Vector2d vp =
                  cam.ideal_pixel({std::tan(yaw_deg * kDeg) / std::cos(pitch_deg * kDeg),
                                   std::tan(pitch_deg * kDeg)});
              EXPECT_NEAR(p.vp_u_px, vp.x(), 1e-6);
              EXPECT_NEAR(p.vp_v_px, vp.y(), 1e-6);
            } else {
              EXPECT_FALSE(p.vp_finite);
            }
          }
        }
      }
    }
  }
  std::printf("analytic: %d cases, max |yaw err| %.3g rad, max |offset err| %.3g m\n", st.cases,
              st.max_yaw_err, st.max_off_err);
}

// The edge lines of exact runs recover the pitch (edges at +-half width of the
// tape image: build them from the projected tape edges).
TEST(TapePose, PitchFromExactEdges) {
  for (double pitch_deg : {25.0, 45.0, 65.0, 90.0}) {
    const CameraConfig c = make_config(1280, 960, false, pitch_deg);
    const CameraModel cam(c);
    const Projector pr(c, 8 * kDeg, 0.2);
    // Runs whose bounds are the edges rounded to the pixel grid would only give
    // the pitch to ~0.5 px; instead use a wide tape so that quantisation is small.
    std::vector<stream::RunRecord> runs;
    const double half = 0.15;
    for (int row = 0; row < c.image_height; ++row) {
      double ul = 0, uc = 0, ur = 0;
      if (!pr.column_at_row(half, row, ul) || !pr.column_at_row(0.0, row, uc) ||
          !pr.column_at_row(-half, row, ur))
        continue;
      if (ul < 3 || ur > c.image_width - 4) continue;
      stream::RunRecord rr;
      rr.row = static_cast<uint16_t>(row);
      rr.x_start = static_cast<uint16_t>(std::lround(ul + 0.5));
      rr.x_end = static_cast<uint16_t>(std::lround(ur - 0.5));
      rr.sum_w = 1u << 30;
      rr.sum_xw = static_cast<uint64_t>(std::llround(uc * static_cast<double>(1u << 30)));
      runs.push_back(rr);
    }
    TapePoseOptions opt;
    opt.max_width_factor = 0.0;
    const TapePose p = estimate_tape_pose(runs, cam, c, opt);
    ASSERT_EQ(p.status, Status::ok);
    EXPECT_NEAR(p.yaw_rad, 8 * kDeg, 1e-9);
    if (pitch_deg == 90.0 && !p.pitch_est_valid) {
      // The edges are parallel up to quantisation: the intersection may lie
      // beyond 90 deg, which no camera pitch can be; such an estimate is not reported.
      continue;
    }
    ASSERT_TRUE(p.pitch_est_valid) << pitch_deg;
    EXPECT_LE(p.pitch_est_rad, 90.0 * kDeg);
    EXPECT_NEAR(p.pitch_est_rad, pitch_deg * kDeg, 0.5 * kDeg) << pitch_deg;
    std::printf("pitch %.0f deg from edges quantised to pixels: %.3f deg\n", pitch_deg,
                p.pitch_est_rad / kDeg);
    EXPECT_NEAR(p.yaw_rad, 8 * kDeg, 1e-9);
  }
}

TEST(TapePose, StatusesNeverNaN) {
  const CameraConfig c = make_config(640, 480, false, 45.0);
  const CameraModel cam(c);
  EXPECT_EQ(estimate_tape_pose({}, cam, c).status, Status::no_tape);
  const Projector pr(c, 0.1, 0.1);
  std::vector<stream::RunRecord> runs;
  add_line_runs(pr, 0.0, 2, runs);
  // Six rows of tape: shorter than min_row_span_px in rows and columns, a
  // speck -> no_tape.
  std::vector<stream::RunRecord> few(runs.begin() + 40, runs.begin() + 46);
  EXPECT_EQ(estimate_tape_pose(few, cam, c).status, Status::no_tape);
  // Forty rows of a tape cut by the left image border (runs 0..3): tape-like,
  // but no run centre is usable -> too_few_points.
  std::vector<stream::RunRecord> cut(runs.begin() + 40, runs.begin() + 80);
  for (auto& r : cut) {
    r.x_start = 0;
    r.x_end = 3;
    r.sum_xw = static_cast<uint64_t>(r.sum_w) * 2u;
  }
  EXPECT_EQ(estimate_tape_pose(cut, cam, c).status, Status::too_few_points);
  // All runs on one row: no slope.
  std::vector<stream::RunRecord> one_row;
  for (uint16_t i = 0; i < 20; ++i)
    one_row.push_back(
        {100, static_cast<uint16_t>(10 + 20 * i), static_cast<uint16_t>(14 + 20 * i), 100, 0});
  for (auto& r : one_row) r.sum_xw = 100ull * (r.x_start + 2u);
  EXPECT_NE(estimate_tape_pose(one_row, cam, c).status, Status::ok);
  // Fuzz: random runs; whatever the status, nothing is NaN or inf.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> row(0, 479), x(0, 639), len(0, 60);
  std::uniform_int_distribution<uint32_t> wsum(0, 50000);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<stream::RunRecord> rr;
    const int nr = trial % 60;
    for (int k = 0; k < nr; ++k) {
      stream::RunRecord r;
      r.row = static_cast<uint16_t>(row(rng));
      r.x_start = static_cast<uint16_t>(x(rng));
      r.x_end = static_cast<uint16_t>(std::min(639, r.x_start + len(rng)));
      r.sum_w = wsum(rng);
      r.sum_xw = static_cast<uint64_t>(r.sum_w) * (r.x_start + (r.x_end - r.x_start) / 2u);
      rr.push_back(r);
    }
    sort_runs(rr);
    const TapePose p = estimate_tape_pose(rr, cam, c);
    EXPECT_TRUE(std::isfinite(p.yaw_rad) && std::isfinite(p.offset_m) &&
                std::isfinite(p.pitch_est_rad) && std::isfinite(p.vp_u_px) &&
                std::isfinite(p.vp_v_px) && std::isfinite(p.residual_rms_px) &&
                std::isfinite(p.yaw_sigma_rad) && p.line_norm.allFinite());
    if (p.status != Status::ok) {
      EXPECT_EQ(p.yaw_rad, 0.0);
      EXPECT_EQ(p.offset_m, 0.0);
    }
  }
}

// Other tapes, a T-branch (very wide runs) and noise runs must not bias the fit.
TEST(TapePose, RobustToOtherTapesBranchAndNoise) {
  const CameraConfig c = make_config(640, 480, true, 40.0);
  const CameraModel cam(c);
  const double yaw = -9 * kDeg, off = 0.23;
  const Projector pr(c, yaw, off);
  std::vector<stream::RunRecord> runs;
  add_line_runs(pr, 0.0, 2, runs);
  // A second, shorter tape 0.9 m to the right (visible only in part of the image).
  std::vector<stream::RunRecord> other;
  add_line_runs(pr, -0.9, 2, other);
  other.resize(other.size() / 3);
  runs.insert(runs.end(), other.begin(), other.end());
  // T-branch: 12 rows where the run is 60 px wide and off-centre.
  for (auto& r : runs) {
    if (r.row >= 150 && r.row < 162 && r.x_start > 0) {
      r.x_end = static_cast<uint16_t>(std::min(630, r.x_end + 60));
      r.sum_xw += static_cast<uint64_t>(r.sum_w) * 25u;
    }
  }
  // Noise: isolated short runs.
  std::mt19937_64 rng(3);
  for (int k = 0; k < 40; ++k) {
    stream::RunRecord r;
    r.row = static_cast<uint16_t>(rng() % 480);
    r.x_start = static_cast<uint16_t>(rng() % 600);
    r.x_end = static_cast<uint16_t>(r.x_start + 1);
    r.sum_w = 30;
    r.sum_xw = 30u * (r.x_start + 1u);
    runs.push_back(r);
  }
  sort_runs(runs);
  const TapePose p = estimate_tape_pose(runs, cam, c);
  ASSERT_EQ(p.status, Status::ok);
  EXPECT_NEAR(p.yaw_rad, yaw, 1e-9);
  EXPECT_NEAR(p.offset_m, off, 1e-9);
  EXPECT_LT(p.points_used, p.points_total);
}

// Runs need not arrive in (row, x_start) order: a shuffled list gives the
// same chains, inliers and pose (the sums run in input order: equal up to
// rounding).
TEST(TapePose, RunOrderDoesNotMatter) {
  const CameraConfig c = make_config(640, 480, true, 40.0);
  const CameraModel cam(c);
  const Projector pr(c, 7 * kDeg, -0.12);
  std::vector<stream::RunRecord> runs;
  add_line_runs(pr, 0.0, 2, runs);
  std::vector<stream::RunRecord> other;
  add_line_runs(pr, 0.8, 2, other);
  other.resize(other.size() / 2);
  runs.insert(runs.end(), other.begin(), other.end());
  sort_runs(runs);
  const TapePose sorted = estimate_tape_pose(runs, cam, c);
  ASSERT_EQ(sorted.status, Status::ok);
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 3; ++trial) {
    std::shuffle(runs.begin(), runs.end(), rng);
    const TapePose p = estimate_tape_pose(runs, cam, c);
    ASSERT_EQ(p.status, Status::ok);
    EXPECT_EQ(p.points_used, sorted.points_used);
    EXPECT_EQ(p.points_total, sorted.points_total);
    EXPECT_NEAR(p.yaw_rad, sorted.yaw_rad, 1e-12);
    EXPECT_NEAR(p.offset_m, sorted.offset_m, 1e-12);
    EXPECT_NEAR(p.residual_rms_px, sorted.residual_rms_px, 1e-9);
    // (The pitch estimate samples every k-th inlier in input order: it moves.)
  }
}

// Two tapes with equal support: the one nearest the principal point wins.
TEST(TapePose, TieGoesToTapeNearestImageCentre) {
  const CameraConfig c = make_config(640, 480, false, 90.0);
  const CameraModel cam(c);
  for (double cam_y : {0.3, 0.7}) {
    // Tapes at Y = 0 and Y = 1; the camera at cam_y sees both full length.
    const Projector pr(c, 0.0, cam_y);
    std::vector<stream::RunRecord> runs;
    add_line_runs(pr, 0.0, 2, runs);
    add_line_runs(pr, 1.0, 2, runs);
    sort_runs(runs);
    TapePoseOptions opt;
    opt.max_width_factor = 0.0;
    const TapePose p = estimate_tape_pose(runs, cam, c, opt);
    ASSERT_EQ(p.status, Status::ok);
    const double expected = cam_y < 0.5 ? cam_y : cam_y - 1.0;
    EXPECT_NEAR(p.offset_m, expected, 1e-9) << cam_y;
  }
}

// Zenith mode: moments of an ideal band (no distortion) from the mask.
stream::MomentResults band_moments(const CameraConfig& c, double yaw, double off, double tape_w) {
  const Projector pr(c, yaw, off);
  stream::MomentResults m;
  const CameraModel cam(c);
  for (int v = 0; v < c.image_height; ++v) {
    for (int u = 0; u < c.image_width; ++u) {
      // Back-project the pixel centre to the ceiling and test the band |Y| <= w/2.
      const Eigen::Vector2d xy = cam.normalise(u, v);
      const Eigen::Vector3d ray = pr.r.transpose() * Eigen::Vector3d(xy.x(), xy.y(), 1.0);
      if (ray.z() <= 0) continue;
      const double t = (c.ceiling_height_m - pr.centre.z()) / ray.z();
      const double y = pr.centre.y() + t * ray.y();
      if (std::abs(y) > 0.5 * tape_w) continue;
      const uint64_t x = static_cast<uint64_t>(u), yy = static_cast<uint64_t>(v);
      m.mask[stream::kM00] += 1;
      m.mask[stream::kM10] += x;
      m.mask[stream::kM01] += yy;
      m.mask[stream::kM20] += x * x;
      m.mask[stream::kM11] += x * yy;
      m.mask[stream::kM02] += yy * yy;
    }
  }
  return m;
}

TEST(TapePose, ZenithFromMoments) {
  const CameraConfig c = make_config(640, 480, false, 90.0);
  const CameraModel cam(c);
  const double tape_w = 0.05;  // 16 px wide at c = 2.5 m, f = 512
  for (double yaw_deg : {-15.0, -5.0, 0.0, 10.0}) {
    for (double off : {-0.3, 0.0, 0.2}) {
      const stream::MomentResults m = band_moments(c, yaw_deg * kDeg, off, tape_w);
      const TapePose p = zenith_pose_from_moments(m, cam, c);
      ASSERT_EQ(p.status, Status::ok);
      // Bound of docs/host_maths.md: clipping of the band by the image rows
      // tilts the principal axis by <= (w/H)^2 |sin psi cos psi|, plus pixel
      // sampling of the band edges.
      const double w_px = tape_w * c.fx() / c.ceiling_above_camera_m();
      const double bound = std::pow(w_px / c.image_height, 2) + 2e-4;
      EXPECT_NEAR(p.yaw_rad, yaw_deg * kDeg, bound) << yaw_deg << " " << off;
      EXPECT_NEAR(p.offset_m, off, 2e-3) << yaw_deg << " " << off;
      // The pixel-quantisation covariance (host_maths.md section 5) covers
      // the errors; along the image's columns the normal's focal length is fx.
      const double sigma_off = std::sqrt(p.covariance(1, 1));
      EXPECT_LE(std::abs(p.offset_m - off), 3.0 * sigma_off) << yaw_deg << " " << off;
      EXPECT_LE(std::abs(p.yaw_rad - yaw_deg * kDeg), 3.0 * std::sqrt(p.covariance(0, 0)) + bound);
      if (yaw_deg == 0.0) {
        EXPECT_NEAR(sigma_off, c.ceiling_above_camera_m() / c.fx() / std::sqrt(24.0), 1e-12);
      }
    }
  }
  stream::MomentResults empty;
  EXPECT_EQ(zenith_pose_from_moments(empty, cam, c).status, Status::no_tape);
  // A square blob: isotropic.
  stream::MomentResults sq;
  for (uint64_t v = 200; v < 240; ++v) {
    for (uint64_t u = 300; u < 340; ++u) {
      sq.mask[stream::kM00] += 1;
      sq.mask[stream::kM10] += u;
      sq.mask[stream::kM01] += v;
      sq.mask[stream::kM20] += u * u;
      sq.mask[stream::kM11] += u * v;
      sq.mask[stream::kM02] += v * v;
    }
  }
  EXPECT_EQ(zenith_pose_from_moments(sq, cam, c).status, Status::degenerate);
}

}  // namespace
}  // namespace ceilnav::host

namespace ceilnav::host {
namespace {

// Threshold and weights from the frame's histogram by the host's own rule
// (host/auto_threshold.hpp), runs from the golden run finder.
std::vector<stream::RunRecord> runs_of_frame(const cv::Mat& grey) {
  stream::HistogramResults hist;
  for (int r = 0; r < grey.rows; ++r) {
    const uint8_t* p = grey.ptr<uint8_t>(r);
    for (int c = 0; c < grey.cols; ++c) ++hist.bins[p[c]];
  }
  const ThresholdSettings t = choose_threshold(hist);
  cv::Mat mask = grey >= t.threshold;
  golden::RunScanParams p{t.background_level, 2, 16};
  return golden::find_runs_ref(grey, mask, p);
}

struct RenderedCase {
  double pitch_deg, yaw_deg, offset_m, noise, blur;
};

struct RenderedStats {
  int n = 0, failed = 0, runs = 0;
  double yaw_ss = 0, off_ss = 0, pitch_err_sum = 0, pitch_err_max = 0;
  double yaw_rms_deg() const { return std::sqrt(yaw_ss / std::max(1, n)) / kDeg; }
  double off_rms_mm() const { return 1e3 * std::sqrt(off_ss / std::max(1, n)); }
};

RenderedStats run_rendered(const std::vector<RenderedCase>& cases, bool distorted) {
  RenderedStats st;
  uint64_t seed = 11;
  for (const RenderedCase& rc : cases) {
    CameraConfig c = make_config(640, 480, distorted, rc.pitch_deg);
    c.camera_matrix[0] = c.camera_matrix[4] = 500.0;
    const CameraModel cam(c);
    const golden::CeilingScene scene = golden::single_tape_scene(c.tape_width_m);
    const golden::CameraPose pose{0.0, rc.offset_m, rc.yaw_deg * kDeg};
    golden::RenderParams rp;
    rp.noise_sigma_grey = rc.noise;
    rp.blur_sigma_px = rc.blur;
    rp.noise_seed = seed++;
    const cv::Mat frame = golden::render_frame(c, scene, pose, rp);
    const golden::FrameTruth truth = golden::truth_for(c, scene, pose);
    const std::vector<stream::RunRecord> runs = runs_of_frame(frame);
    const TapePose p = estimate_tape_pose(runs, cam, c);
    st.runs += static_cast<int>(runs.size());
    if (p.status != Status::ok) {
      ++st.failed;
      continue;
    }
    ++st.n;
    const double ey = p.yaw_rad - truth.yaw_rad, eo = p.offset_m - truth.offset_m;
    st.yaw_ss += ey * ey;
    st.off_ss += eo * eo;
    if (std::getenv("CEILNAV_VERBOSE") != nullptr) {
      std::printf(
          "  p %4.0f y %6.1f o %5.2f n %.0f b %.1f: yaw err %+.4f deg off err %+.3f mm used %d/%d "
          "rms %.3f px\n",
          rc.pitch_deg, rc.yaw_deg, rc.offset_m, rc.noise, rc.blur, ey / kDeg, eo * 1e3,
          p.points_used, p.points_total, p.residual_rms_px);
    }
    if (p.pitch_est_valid) {
      const double ep = p.pitch_est_rad - truth.pitch_rad;
      st.pitch_err_sum += ep;
      st.pitch_err_max = std::max(st.pitch_err_max, std::abs(ep));
    }
  }
  return st;
}

std::vector<RenderedCase> rendered_sweep() {
  std::vector<RenderedCase> cases;
  int k = 0;
  for (double pitch : {20.0, 30.0, 40.0, 50.0, 60.0}) {
    for (double yaw : {-15.0, -6.0, 0.0, 9.0, 15.0}) {
      const double offs[] = {-0.5, -0.15, 0.0, 0.3, 0.5};
      const double off = offs[(k++) % 5];
      const double noise = (k % 2) ? 5.0 : 2.0;
      const double blur = (k % 3) ? 1.0 : 0.5;
      cases.push_back({pitch, yaw, off, noise, blur});
    }
  }
  return cases;
}

// (b) rendered frames, 640x480, pitch 20-60, yaw +-15, offset +-0.5 m, noise
// <= 5 grey, blur <= 1 px. The project's bar: yaw RMS <= 0.02 deg, offset RMS
// <= 1 mm.
TEST(TapePoseRendered, SweepMeetsAccuracyBar) {
  const RenderedStats st = run_rendered(rendered_sweep(), false);
  std::printf(
      "rendered (no distortion): %d frames ok, %d failed, yaw RMS %.4f deg, offset RMS %.3f mm, "
      "pitch_est mean err %.3f deg max %.3f deg; %.0f runs/frame\n",
      st.n, st.failed, st.yaw_rms_deg(), st.off_rms_mm(),
      st.pitch_err_sum / std::max(1, st.n) / kDeg, st.pitch_err_max / kDeg, st.runs / 25.0);
  EXPECT_EQ(st.failed, 0);
  EXPECT_LE(st.yaw_rms_deg(), 0.02);
  EXPECT_LE(st.off_rms_mm(), 1.0);
}

TEST(TapePoseRendered, SweepWithDistortionMeetsAccuracyBar) {
  const RenderedStats st = run_rendered(rendered_sweep(), true);
  std::printf(
      "rendered (distortion): %d frames ok, %d failed, yaw RMS %.4f deg, offset RMS %.3f mm; "
      "%.0f runs/frame\n",
      st.n, st.failed, st.yaw_rms_deg(), st.off_rms_mm(), st.runs / 25.0);
  EXPECT_EQ(st.failed, 0);
  EXPECT_LE(st.yaw_rms_deg(), 0.02);
  EXPECT_LE(st.off_rms_mm(), 1.0);
}

}  // namespace
}  // namespace ceilnav::host
