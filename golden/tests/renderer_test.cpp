// Tests of the scene renderer and its truth against independent references:
// cv::projectPoints, forward-projected (binned) dots, and the closed-form
// per-row integral of a tape under 1/r^2 falloff. Derivations: docs/renderer.md.
#include <gtest/gtest.h>

#include <unistd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "golden/renderer.hpp"
#include "golden/scene.hpp"

namespace ceilnav::golden {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

host::CameraConfig make_camera(double pitch_deg, bool distorted) {
  host::CameraConfig camera;
  camera.camera_matrix = {505.0, 0.0, 322.3, 0.0, 498.0, 236.8, 0.0, 0.0, 1.0};
  if (distorted) camera.distortion_coefficients = {-0.28, 0.09, 0.0012, -0.0008, -0.012};
  camera.camera_pitch_deg = pitch_deg;
  camera.camera_height_m = 0.5;
  camera.ceiling_height_m = 3.0;
  return camera;
}

RenderParams exact_params(int supersample) {
  RenderParams params;
  params.supersample = supersample;
  params.blur_sigma_px = 0.0;
  params.noise_sigma_grey = 0.0;
  return params;
}

// Ceiling point seen (to first order, ignoring distortion) at pixel (u, v).
Eigen::Vector3d ceiling_point_near_pixel(const host::CameraConfig& camera, const CameraPose& pose,
                                         double u, double v) {
  const Eigen::Matrix3d r = world_to_camera_rotation(pose.yaw_rad, pitch_rad(camera));
  const Eigen::Vector3d dir = r.transpose() * Eigen::Vector3d((u - camera.cx()) / camera.fx(),
                                                              (v - camera.cy()) / camera.fy(), 1.0);
  return camera_centre(camera, pose) + (camera.ceiling_above_camera_m() / dir.z()) * dir;
}

// ---------------------------------------------------------------------------

TEST(GoldenRenderer, RotationFollowsConventions) {
  for (double yaw : {-2.5, -0.3, 0.0, 0.7, 3.0}) {
    for (double pitch : {0.0, 20.0 * kDeg, 45.0 * kDeg, 90.0 * kDeg}) {
      const Eigen::Matrix3d r = world_to_camera_rotation(yaw, pitch);
      EXPECT_NEAR((r * r.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-15);
      EXPECT_NEAR(r.determinant(), 1.0, 1e-15);
      // The optical axis is the heading tilted up by the pitch.
      const Eigen::Vector3d forward(std::cos(pitch) * std::cos(yaw),
                                    std::cos(pitch) * std::sin(yaw), std::sin(pitch));
      EXPECT_NEAR((r.row(2).transpose() - forward).norm(), 0.0, 1e-15);
      // No roll: the image x axis is horizontal.
      EXPECT_EQ(r(0, 2), 0.0);
    }
  }
  // Zenith camera, yaw 0: ahead (+X) is image +v, left (+Y) is image -u.
  host::CameraConfig zenith = make_camera(90.0, false);
  const CameraPose pose{1.0, 2.0, 0.0};
  const auto ahead = project_point(zenith, pose, {2.0, 2.0, 3.0}, false);
  const auto left = project_point(zenith, pose, {1.0, 3.0, 3.0}, false);
  ASSERT_TRUE(ahead && left);
  EXPECT_NEAR(ahead->x(), zenith.cx(), 1e-9);
  EXPECT_GT(ahead->y(), zenith.cy() + 100.0);
  EXPECT_LT(left->x(), zenith.cx() - 100.0);
  EXPECT_NEAR(left->y(), zenith.cy(), 1e-9);
  // Pitched camera: positive offset (camera left of the tape) puts the tape
  // right of the image centre; a point behind the camera has no image.
  host::CameraConfig pitched = make_camera(45.0, false);
  const auto tape = project_point(pitched, {0.0, 0.4, 0.0}, {3.0, 0.0, 3.0}, false);
  ASSERT_TRUE(tape);
  EXPECT_GT(tape->x(), pitched.cx() + 10.0);
  EXPECT_FALSE(project_point(pitched, {0.0, 0.0, 0.0}, {-1.0, 0.0, 0.5}, false));
}

TEST(GoldenRenderer, ProjectPointEqualsOpenCv) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const bool distorted = trial % 2 == 1;
    host::CameraConfig camera = make_camera(20.0 + 70.0 * unit(rng), distorted);
    if (trial % 10 == 0) camera.camera_pitch_deg = 90.0;
    camera.camera_height_m = 0.2 + 1.3 * unit(rng);
    camera.ceiling_height_m = 2.5 + 2.5 * unit(rng);
    const CameraPose pose{-5.0 + 10.0 * unit(rng), -5.0 + 10.0 * unit(rng),
                          std::numbers::pi * (2.0 * unit(rng) - 1.0)};
    const Eigen::Matrix3d r = world_to_camera_rotation(pose.yaw_rad, pitch_rad(camera));
    const Eigen::Vector3d t = -r * camera_centre(camera, pose);

    cv::Mat rotation(3, 3, CV_64F), rvec, tvec(3, 1, CV_64F), k(3, 3, CV_64F), d(1, 5, CV_64F);
    for (int row = 0; row < 3; ++row) {
      tvec.at<double>(row) = t(row);
      for (int col = 0; col < 3; ++col) {
        rotation.at<double>(row, col) = r(row, col);
        k.at<double>(row, col) = camera.camera_matrix[static_cast<std::size_t>(3 * row + col)];
      }
    }
    for (int c = 0; c < 5; ++c) {
      d.at<double>(c) = camera.distortion_coefficients[static_cast<std::size_t>(c)];
    }
    cv::Rodrigues(rotation, rvec);
    cv::Mat back;
    cv::Rodrigues(rvec, back);
    ASSERT_LT(cv::norm(back - rotation, cv::NORM_INF), 1e-13) << "Rodrigues round trip";

    std::vector<cv::Point3d> points;
    std::vector<Eigen::Vector2d> ours;
    for (int p = 0; p < 20; ++p) {
      // A ceiling point or a point in the room, inside the field of view.
      const double u = -40.0 + 720.0 * unit(rng), v = -40.0 + 560.0 * unit(rng);
      Eigen::Vector3d world = ceiling_point_near_pixel(camera, pose, u, v);
      const Eigen::Vector3d c = camera_centre(camera, pose);
      if (p % 2 == 1) world = c + (0.2 + 0.8 * unit(rng)) * (world - c);
      if (!((r * (world - c)).z() > 0.0)) continue;
      const auto projected = project_point(camera, pose, world, distorted);
      ASSERT_TRUE(projected);
      points.emplace_back(world.x(), world.y(), world.z());
      ours.push_back(*projected);
    }
    if (points.empty()) continue;
    std::vector<cv::Point2d> theirs;
    cv::projectPoints(points, rvec, tvec, k, distorted ? d : cv::Mat::zeros(1, 5, CV_64F), theirs);
    for (std::size_t p = 0; p < points.size(); ++p) {
      EXPECT_NEAR(ours[p].x(), theirs[p].x, 1e-9) << "trial " << trial;
      EXPECT_NEAR(ours[p].y(), theirs[p].y, 1e-9) << "trial " << trial;
      ++compared;
    }
  }
  EXPECT_GT(compared, 4000);
}

TEST(GoldenRenderer, UndistortInvertsProjection) {
  const host::CameraConfig camera = make_camera(45.0, true);
  for (double u = -0.5; u <= 639.5; u += 31.9) {
    for (double v = -0.5; v <= 479.5; v += 23.9) {
      const auto xy = undistort_pixel(camera, {u, v});
      ASSERT_TRUE(xy);
      const Eigen::Vector2d xyd = distort_normalised(camera, *xy);
      EXPECT_NEAR(camera.fx() * xyd.x() + camera.cx(), u, 1e-9);
      EXPECT_NEAR(camera.fy() * xyd.y() + camera.cy(), v, 1e-9);
    }
  }
  // The renderer's local affine ray model is accurate to a small fraction of
  // a pixel for this (strong) distortion, and exact without distortion.
  const double affine_error_px = affine_undistortion_error_px(camera);
  std::printf("affine undistortion error: %.3g px\n", affine_error_px);
  EXPECT_GT(affine_error_px, 0.0);
  EXPECT_LT(affine_error_px, 5e-3);
  EXPECT_EQ(affine_undistortion_error_px(make_camera(45.0, false)), 0.0);
}

// ---------------------------------------------------------------------------
// Dots: small squares (~6 px across) at known ceiling points. The reference image of a dot is
// made by forward projection with project_point: the square is cut into
// M x M cells, each cell's image area (shoelace of its projected corners)
// times gain / r^2 is added to the pixel its projected centre falls in. This
// models the pixel box exactly (pixel locking included), independent of the
// renderer's inverse ray casting, up to mis-binned cells along pixel borders.

struct DotReference {
  std::map<std::pair<int, int>, double> bins;
  std::map<std::pair<int, int>, bool> edge;  // the dot's border passes through the pixel
  double mass = 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  int min_i = 1 << 30, max_i = -(1 << 30), min_j = 1 << 30, max_j = -(1 << 30);
};

DotReference reference_dot(const host::CameraConfig& camera, const CameraPose& pose,
                           const Eigen::Vector3d& centre, double side_m, double gain,
                           bool distorted, int cells) {
  DotReference ref;
  const int m = cells;
  std::vector<Eigen::Vector2d> nodes(static_cast<std::size_t>((m + 1) * (m + 1)));
  const double step = side_m / m;
  for (int b = 0; b <= m; ++b) {
    for (int a = 0; a <= m; ++a) {
      const Eigen::Vector3d p =
          centre + Eigen::Vector3d(-0.5 * side_m + a * step, -0.5 * side_m + b * step, 0.0);
      const auto uv = project_point(camera, pose, p, distorted);
      EXPECT_TRUE(uv);
      nodes[static_cast<std::size_t>(b * (m + 1) + a)] = *uv;
    }
  }
  const Eigen::Vector3d c = camera_centre(camera, pose);
  for (int b = 0; b < m; ++b) {
    for (int a = 0; a < m; ++a) {
      const Eigen::Vector2d& p00 = nodes[static_cast<std::size_t>(b * (m + 1) + a)];
      const Eigen::Vector2d& p10 = nodes[static_cast<std::size_t>(b * (m + 1) + a + 1)];
      const Eigen::Vector2d& p11 = nodes[static_cast<std::size_t>((b + 1) * (m + 1) + a + 1)];
      const Eigen::Vector2d& p01 = nodes[static_cast<std::size_t>((b + 1) * (m + 1) + a)];
      const double area = 0.5 * std::abs((p00.x() * p10.y() - p10.x() * p00.y()) +
                                         (p10.x() * p11.y() - p11.x() * p10.y()) +
                                         (p11.x() * p01.y() - p01.x() * p11.y()) +
                                         (p01.x() * p00.y() - p00.x() * p01.y()));
      const Eigen::Vector3d world = centre + Eigen::Vector3d(-0.5 * side_m + (a + 0.5) * step,
                                                             -0.5 * side_m + (b + 0.5) * step, 0.0);
      const double weight = gain / (world - c).squaredNorm() * area;
      const Eigen::Vector2d mid = 0.25 * (p00 + p10 + p11 + p01);
      const int i = static_cast<int>(std::lround(mid.x()));
      const int j = static_cast<int>(std::lround(mid.y()));
      ref.bins[{i, j}] += weight;
      if (a == 0 || b == 0 || a == m - 1 || b == m - 1) ref.edge[{i, j}] = true;
      ref.mass += weight;
      ref.centroid += weight * Eigen::Vector2d(i, j);
      ref.min_i = std::min(ref.min_i, i);
      ref.max_i = std::max(ref.max_i, i);
      ref.min_j = std::min(ref.min_j, j);
      ref.max_j = std::max(ref.max_j, j);
    }
  }
  ref.centroid /= ref.mass;
  return ref;
}

// Standard deviation bound of a pixel's value from N x N jittered-stratified
// sampling near an edge: an edge (two, at a dot corner) crosses at most 2N - 1
// strata; each crossed stratum is a Bernoulli of variance <= 1/4 in units of
// the full pixel value / N^2.
double edge_sigma_fraction(int n) {
  return std::sqrt(2.0 * (2.0 * n - 1.0) / 4.0) / (n * n);
}

struct DotCase {
  double pitch_deg;
  bool distorted;
  CameraPose pose;
};

TEST(GoldenRenderer, DotCentroidsMatchForwardProjection) {
  const int n = 32;
  const std::vector<DotCase> cases = {
      {45.0, false, {0.0, 0.0, 0.0}},  {45.0, true, {1.0, 0.3, 0.2}},
      {90.0, true, {2.0, -0.5, 0.7}},  {90.0, false, {0.0, 0.0, -1.9}},
      {30.0, true, {-1.0, 1.0, -0.4}}, {70.0, true, {0.5, 0.2, 2.8}},
  };
  double worst_ratio = 0.0, worst_error_px = 0.0;
  for (const DotCase& dc : cases) {
    const host::CameraConfig camera = make_camera(dc.pitch_deg, dc.distorted);
    RenderParams params = exact_params(n);
    params.apply_distortion = dc.distorted;
    CeilingScene scene;
    std::vector<Eigen::Vector3d> centres;
    std::vector<double> sides_m;
    for (double v : {110.0, 240.0, 380.0}) {
      for (double u : {150.0, 320.0, 500.0}) {
        const Eigen::Vector3d p = ceiling_point_near_pixel(camera, dc.pose, u, v);
        // About 6 px across, whatever the range.
        const double side_m = 6.0 * (p - camera_centre(camera, dc.pose)).norm() / camera.fx();
        centres.push_back(p);
        sides_m.push_back(side_m);
        scene.tapes.push_back({p.x() - 0.5 * side_m, p.y(), p.x() + 0.5 * side_m, p.y(), side_m});
      }
    }
    const cv::Mat image = render_float(camera, scene, dc.pose, params) - params.background_grey;
    const double affine_error_px = affine_undistortion_error_px(camera);
    for (std::size_t dot = 0; dot < centres.size(); ++dot) {
      const Eigen::Vector3d& centre = centres[dot];
      const DotReference ref =
          reference_dot(camera, dc.pose, centre, sides_m[dot], params.tape_gain, dc.distorted, 240);
      double mass = 0.0, variance_c = 0.0, variance_m = 0.0;
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      // A fully covered pixel's value; +5% for the range change across the dot.
      const double full_value =
          1.05 * params.tape_gain / (centre - camera_centre(camera, dc.pose)).squaredNorm();
      for (int j = ref.min_j - 2; j <= ref.max_j + 2; ++j) {
        for (int i = ref.min_i - 2; i <= ref.max_i + 2; ++i) {
          ASSERT_TRUE(i >= 0 && j >= 0 && i < image.cols && j < image.rows);
          const double value = image.at<double>(j, i);
          mass += value;
          centroid += value * Eigen::Vector2d(i, j);
        }
      }
      centroid /= mass;
      const double sigma_px = edge_sigma_fraction(n) * full_value;
      for (const auto& [ij, is_edge] : ref.edge) {
        variance_c += (Eigen::Vector2d(ij.first, ij.second) - ref.centroid).squaredNorm() *
                      sigma_px * sigma_px;
        variance_m += sigma_px * sigma_px;
      }
      // 5 sigma of sampling + the affine ray error (moves the whole blob) +
      // 2e-3 px for the reference's mis-binned border cells.
      const double tolerance_px =
          5.0 * std::sqrt(variance_c) / ref.mass + 2.0 * affine_error_px + 2e-3;
      EXPECT_LT(tolerance_px, 0.05) << "area " << ref.mass / full_value << " px^2, edge pixels "
                                    << ref.edge.size() << " pitch " << dc.pitch_deg;
      worst_ratio = std::max(worst_ratio, (centroid - ref.centroid).norm() / tolerance_px);
      worst_error_px = std::max(worst_error_px, (centroid - ref.centroid).norm());
      EXPECT_LT((centroid - ref.centroid).norm(), tolerance_px)
          << "pitch " << dc.pitch_deg << " distorted " << dc.distorted << " dot at "
          << ref.centroid.transpose() << " rendered " << centroid.transpose();
      EXPECT_NEAR(mass, ref.mass, 5.0 * std::sqrt(variance_m) + 1e-3 * ref.mass);
      // The analytic projection of the dot centre differs from the blob
      // centroid only by second-order perspective/falloff terms.
      const auto projected = project_point(camera, dc.pose, centre, dc.distorted);
      ASSERT_TRUE(projected);
      EXPECT_LT((centroid - *projected).norm(), 0.05 + 0.25 / std::sqrt(ref.mass / full_value));
    }
  }
  std::printf("dot centroid error: largest %.4f px, largest error / tolerance %.2f\n",
              worst_error_px, worst_ratio);
}

// ---------------------------------------------------------------------------
// Tape centre line. Without distortion and without roll, image row v is the
// set of rays (x, y_n, 1) with y_n = (v - cy)/fy; their rise above the camera
// is U = y_n d_z + f_z (r_z = 0), the same for the whole row, so the ceiling
// point P(x) = C + (h/U)(x r + y_n d + f) is affine in x and the tape occupies
// a symmetric interval x_c +- a. The intensity is
//   g(x) = gain / r^2 = gain U^2 / (h^2 (q + x^2)),  q = 1 + y_n^2,
// whose integrals are closed-form (atan and log), so the pixel-box integrals
// of a row are exact; only the average over the row's height [v-1/2, v+1/2]
// uses a K-point midpoint rule (the overlap is piecewise linear in v).
// Falloff bias: c - x_c = (a^2/3) d ln g/dx = -(2/3) a^2 x_c / (q + x_c^2) + O(a^4),
// i.e. towards the principal column, where the range along the row is least.

struct RowInterval {
  double x_a, x_b, x_c, t, q;
};

bool row_interval(const host::CameraConfig& camera, const CameraPose& pose, double y_ref,
                  double width_m, double v, RowInterval& out) {
  const Eigen::Matrix3d r = world_to_camera_rotation(pose.yaw_rad, pitch_rad(camera));
  const double yn = (v - camera.cy()) / camera.fy();
  const double rise = yn * r(1, 2) + r(2, 2);
  if (!(rise > 0.0)) return false;
  const double t = camera.ceiling_above_camera_m() / rise;
  const auto x_at = [&](double y) {
    return ((y - pose.y_m) / t - yn * r(1, 1) - r(2, 1)) / r(0, 1);
  };
  const double x1 = x_at(y_ref - 0.5 * width_m), x2 = x_at(y_ref + 0.5 * width_m);
  out = {std::min(x1, x2), std::max(x1, x2), x_at(y_ref), t, 1.0 + yn * yn};
  return true;
}

TEST(GoldenRenderer, TapeRowCentroidsLieOnTheCentreLine) {
  const double width_m = 0.05;
  const int n = 8;
  const int sub_rows = 64;
  const CeilingScene scene = single_tape_scene(width_m);
  struct Case {
    double pitch_deg;
    CameraPose pose;
  };
  const std::vector<Case> cases = {{45.0, {0.0, 0.3, 0.0}}, {45.0, {0.0, -0.4, 0.35}},
                                   {90.0, {0.0, 0.5, 0.2}}, {30.0, {0.0, 1.0, -0.5}},
                                   {60.0, {0.0, 0.0, 0.1}}, {90.0, {0.0, -0.2, 2.9}}};
  int rows_checked = 0;
  double worst_bias_px = 0.0;
  for (const Case& tc : cases) {
    const host::CameraConfig camera = make_camera(tc.pitch_deg, false);
    const RenderParams params = exact_params(n);
    const cv::Mat image = render_float(camera, scene, tc.pose, params) - params.background_grey;
    const double fx = camera.fx(), cx = camera.cx();
    for (int j = 10; j < camera.image_height - 10; j += 17) {
      RowInterval centre{};
      if (!row_interval(camera, tc.pose, scene.reference_y_m, width_m, j, centre)) continue;
      const double u_a = cx + fx * centre.x_a, u_b = cx + fx * centre.x_b;
      const double u_centre = cx + fx * centre.x_c;
      if (u_a < 8.0 || u_b > camera.image_width - 9.0) continue;
      // The centre line's crossing of the row, cross-checked with project_point.
      const Eigen::Matrix3d r = world_to_camera_rotation(tc.pose.yaw_rad, pitch_rad(camera));
      const double yn = (j - camera.cy()) / camera.fy();
      const Eigen::Vector3d on_line = camera_centre(camera, tc.pose) +
                                      centre.t * (centre.x_c * r.row(0).transpose() +
                                                  yn * r.row(1).transpose() + r.row(2).transpose());
      ASSERT_NEAR(on_line.y(), scene.reference_y_m, 1e-12);
      ASSERT_TRUE(on_line.x() > -9.0 && on_line.x() < 99.0);
      const auto projected = project_point(camera, tc.pose, on_line, false);
      ASSERT_TRUE(projected);
      ASSERT_NEAR(projected->x(), u_centre, 1e-9);
      ASSERT_NEAR(projected->y(), j, 1e-9);

      // Continuous centroid on the row centre and the derived falloff bias.
      const double sq = std::sqrt(centre.q);
      const double c_cont =
          0.5 *
          std::log((centre.q + centre.x_b * centre.x_b) / (centre.q + centre.x_a * centre.x_a)) /
          ((std::atan(centre.x_b / sq) - std::atan(centre.x_a / sq)) / sq);
      const double a = 0.5 * (centre.x_b - centre.x_a);
      const double bias_px =
          -fx * (2.0 / 3.0) * a * a * centre.x_c / (centre.q + centre.x_c * centre.x_c);
      EXPECT_NEAR(fx * (c_cont - centre.x_c), bias_px, 0.02 * std::abs(bias_px) + 1e-9);
      worst_bias_px = std::max(worst_bias_px, std::abs(bias_px));

      // Exact pixel-box reference for the row.
      const int i0 = static_cast<int>(std::floor(u_a)) - 2;
      const int i1 = static_cast<int>(std::ceil(u_b)) + 2;
      std::vector<double> ref(static_cast<std::size_t>(i1 - i0 + 1), 0.0);
      std::vector<char> edge(ref.size(), 0);
      for (int k = 0; k < sub_rows; ++k) {
        const double v = j - 0.5 + (k + 0.5) / sub_rows;
        RowInterval row{};
        ASSERT_TRUE(row_interval(camera, tc.pose, scene.reference_y_m, width_m, v, row));
        const double s = std::sqrt(row.q);
        for (int i = i0; i <= i1; ++i) {
          const double p1 = (i - 0.5 - cx) / fx, p2 = (i + 0.5 - cx) / fx;
          const double x1 = std::max(p1, row.x_a), x2 = std::min(p2, row.x_b);
          if (x2 <= x1) continue;
          if (x2 - x1 < (p2 - p1) * (1.0 - 1e-12)) edge[static_cast<std::size_t>(i - i0)] = 1;
          ref[static_cast<std::size_t>(i - i0)] += fx / sub_rows * params.tape_gain /
                                                   (row.t * row.t) *
                                                   (std::atan(x2 / s) - std::atan(x1 / s)) / s;
        }
      }
      double ref_mass = 0.0, ref_moment = 0.0, mass = 0.0, moment = 0.0, full_value = 0.0;
      for (int i = i0; i <= i1; ++i) {
        const double value = ref[static_cast<std::size_t>(i - i0)];
        ref_mass += value;
        ref_moment += i * value;
        full_value = std::max(full_value, value);
        mass += image.at<double>(j, i);
        moment += i * image.at<double>(j, i);
      }
      // Nothing of the tape outside the window.
      EXPECT_EQ(image.at<double>(j, i0 - 1), 0.0);
      EXPECT_EQ(image.at<double>(j, i1 + 1), 0.0);
      const double c_ref = ref_moment / ref_mass, c_rendered = moment / mass;
      double variance = 0.0;
      for (int i = i0; i <= i1; ++i) {
        if (!edge[static_cast<std::size_t>(i - i0)]) continue;
        const double sigma = edge_sigma_fraction(n) * 1.05 * full_value;
        variance += (i - c_ref) * (i - c_ref) * sigma * sigma;
      }
      const double sampling_px = 5.0 * std::sqrt(variance) / ref_mass;
      EXPECT_NEAR(c_rendered, c_ref, sampling_px + 1e-4)
          << "pitch " << tc.pitch_deg << " row " << j;
      // Stated tolerance against the projected centre line: falloff bias +
      // pixel locking (each of the two edges moves the moment by at most
      // full_value / 8 px) + sampling.
      const double locking_px = 2.0 * full_value / 8.0 / ref_mass;
      EXPECT_NEAR(c_rendered, u_centre, std::abs(bias_px) + locking_px + sampling_px + 2e-3)
          << "pitch " << tc.pitch_deg << " row " << j;
      ++rows_checked;
    }
  }
  std::printf("tape rows checked: %d, largest 1/r^2 bias %.4f px\n", rows_checked, worst_bias_px);
  EXPECT_GT(rows_checked, 60);
}

// ---------------------------------------------------------------------------

TEST(GoldenRenderer, TruthVanishingPointIsTheFarPointAlongX) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  CeilingScene scene = corridor_scene(0.05, {.reference_y_m = 0.7});
  for (int trial = 0; trial < 200; ++trial) {
    host::CameraConfig camera = make_camera(20.0 + 60.0 * unit(rng), trial % 2 == 0);
    const CameraPose pose{-3.0 + 6.0 * unit(rng), -2.0 + 4.0 * unit(rng),
                          1.2 * (2 * unit(rng) - 1)};
    const FrameTruth truth = truth_for(camera, scene, pose);
    EXPECT_EQ(truth.yaw_rad, pose.yaw_rad);
    EXPECT_EQ(truth.offset_m, pose.y_m - 0.7);
    EXPECT_DOUBLE_EQ(truth.pitch_rad, camera.camera_pitch_deg * kDeg);
    EXPECT_EQ(truth.ceiling_above_camera_m, 2.5);
    ASSERT_TRUE(truth.vp_finite);
    // A point 1e9 m ahead: its image differs from the vanishing point by
    // ~ f |C| / (1e9 f_z^2) < 1e-4 px here (f_z >= cos 80 deg cos 1.2 rad).
    const auto far = project_point(camera, pose, {1e9, 0.7, 3.0}, false);
    ASSERT_TRUE(far);
    EXPECT_NEAR(truth.vp_u_px, far->x(), 1e-3);
    EXPECT_NEAR(truth.vp_v_px, far->y(), 1e-3);
  }
  const FrameTruth zenith = truth_for(make_camera(90.0, false), scene, {0.0, 0.0, 0.3});
  EXPECT_FALSE(zenith.vp_finite);
  EXPECT_TRUE(std::isnan(zenith.vp_u_px));
  const FrameTruth sideways =
      truth_for(make_camera(45.0, false), scene, {0, 0, std::numbers::pi / 2});
  EXPECT_FALSE(sideways.vp_finite);
  // The horizon row of seed 000 eq. 26 (BRIEF §4): v = cy + fy tan(pitch) at
  // yaw 0; a camera pitched up sees the horizon below the image centre.
  const host::CameraConfig camera = make_camera(35.0, false);
  const FrameTruth ahead = truth_for(camera, scene, {0.0, 0.0, 0.0});
  EXPECT_NEAR(ahead.vp_v_px, camera.cy() + camera.fy() * std::tan(35.0 * kDeg), 1e-9);
  EXPECT_NEAR(ahead.vp_u_px, camera.cx(), 1e-9);

  CeilingScene bad = scene;
  bad.reference_y_m = 0.0;
  EXPECT_THROW(truth_for(camera, bad, {}), std::invalid_argument);
}

TEST(GoldenRenderer, CorridorSceneLayout) {
  const CeilingScene scene = corridor_scene(0.04, {.second_tape = true});
  ASSERT_EQ(scene.tapes.size(), 6u);  // 4 reference pieces, branch, second tape
  double covered_m = 0.0;
  for (std::size_t t = 0; t < 4; ++t) {
    EXPECT_EQ(scene.tapes[t].y0_m, 0.0);
    EXPECT_EQ(scene.tapes[t].y1_m, 0.0);
    covered_m += scene.tapes[t].x1_m - scene.tapes[t].x0_m;
  }
  EXPECT_NEAR(covered_m, 65.0 - 0.8 - 1.2 - 0.5, 1e-12);
  EXPECT_EQ(scene.tapes[4].x0_m, scene.tapes[4].x1_m);  // the branch runs along Y
  EXPECT_EQ(scene.tapes[5].y0_m, 2.0);
  EXPECT_THROW(corridor_scene(0.04, {.gaps_m = {{70.0, 71.0}}}), std::invalid_argument);
}

TEST(GoldenRenderer, TruthCsvRoundTripAndFailure) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("ceilnav_rd_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "truth.csv").string();
  const host::CameraConfig camera = make_camera(45.0, false);
  const CeilingScene scene = single_tape_scene(0.05);
  const FrameTruth a = truth_for(camera, scene, {1.0, 0.1234567890123, 0.05});
  const FrameTruth b = truth_for(make_camera(90.0, false), scene, {2.0, -0.2, -0.1});
  write_truth_csv(path, {{"frame_000", a}, {"odd,name", b}});
  std::ifstream in(path);
  std::string header, line1, line2;
  std::getline(in, header);
  std::getline(in, line1);
  std::getline(in, line2);
  EXPECT_EQ(header,
            "frame,yaw_rad,offset_m,pitch_rad,vp_u_px,vp_v_px,vp_finite,ceiling_above_camera_m");
  std::stringstream fields(line1);
  std::vector<std::string> cells;
  for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
  ASSERT_EQ(cells.size(), 8u);
  EXPECT_EQ(cells[0], "frame_000");
  EXPECT_EQ(std::stod(cells[2]), a.offset_m);  // %.17g round-trips exactly
  EXPECT_EQ(std::stod(cells[4]), a.vp_u_px);
  EXPECT_EQ(cells[6], "1");
  EXPECT_EQ(line2.rfind("\"odd,name\",", 0), 0u);
  // b looks at the zenith: no vanishing point, NaN u and v are empty fields.
  ASSERT_FALSE(b.vp_finite);
  EXPECT_NE(line2.find(",,,0,"), std::string::npos) << line2;
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  const std::string bad_path = (dir / "missing_dir" / "truth.csv").string();
  EXPECT_THROW(write_truth_csv(bad_path, {{"x", a}}), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(bad_path));
  std::filesystem::remove_all(dir);
}

// ---------------------------------------------------------------------------

TEST(GoldenRenderer, NoiseIsSeededGaussianWithTheRequestedSigma) {
  const host::CameraConfig camera = make_camera(45.0, true);
  const CeilingScene empty;
  RenderParams params = exact_params(4);
  params.background_grey = 100.0;
  params.noise_sigma_grey = 5.0;
  params.noise_seed = 42;
  const cv::Mat first = render_float(camera, empty, {}, params);
  const cv::Mat again = render_float(camera, empty, {}, params);
  EXPECT_EQ(cv::norm(first, again, cv::NORM_INF), 0.0);
  params.noise_seed = 43;
  const cv::Mat other = render_float(camera, empty, {}, params);
  EXPECT_GT(cv::norm(first, other, cv::NORM_INF), 1.0);
  // The renderer keeps the noise of the last few seeds: a seed rendered again
  // after others have displaced it gets the same noise as when it was kept.
  for (uint64_t seed = 44; seed < 50; ++seed) {
    params.noise_seed = seed;
    render_float(camera, empty, {}, params);
  }
  params.noise_seed = 42;
  EXPECT_EQ(cv::norm(first, render_float(camera, empty, {}, params), cv::NORM_INF), 0.0);

  const double count = static_cast<double>(first.total());
  double sum = 0.0, sum2 = 0.0, lag = 0.0, within = 0.0;
  for (int j = 0; j < first.rows; ++j) {
    for (int i = 0; i < first.cols; ++i) {
      const double z = first.at<double>(j, i) - 100.0;
      sum += z;
      sum2 += z * z;
      within += std::abs(z) <= 5.0;
      if (i > 0) lag += z * (first.at<double>(j, i - 1) - 100.0);
    }
  }
  const double sigma = std::sqrt(sum2 / count);
  // Sampling spreads: mean sigma/sqrt(n) = 0.009; sigma's relative spread
  // 1/sqrt(2n) = 0.13%; P(|z| <= 1 sigma) = 0.6827 +- 0.0008; lag-1
  // correlation +- 1/sqrt(n) = 0.0018. Tolerances are >= 5 of these.
  EXPECT_NEAR(sum / count, 0.0, 0.05);
  EXPECT_NEAR(sigma, 5.0, 5.0 * 0.01);
  EXPECT_NEAR(within / count, 0.6827, 0.005);
  EXPECT_NEAR(lag / (sum2 / count) / count, 0.0, 0.01);

  // The 8-bit frame is the float frame rounded and saturated.
  params.background_grey = 250.0;
  const cv::Mat grey = render_frame(camera, empty, {}, params);
  const cv::Mat real = render_float(camera, empty, {}, params);
  ASSERT_EQ(grey.type(), CV_8UC1);
  ASSERT_EQ(grey.rows, camera.image_height);
  ASSERT_EQ(grey.cols, camera.image_width);
  int saturated = 0;
  for (int j = 0; j < grey.rows; ++j) {
    for (int i = 0; i < grey.cols; ++i) {
      const double expected = std::clamp(std::nearbyint(real.at<double>(j, i)), 0.0, 255.0);
      ASSERT_EQ(grey.at<uint8_t>(j, i), expected);
      saturated += grey.at<uint8_t>(j, i) == 255;
    }
  }
  EXPECT_GT(saturated, 10000);
}

TEST(GoldenRenderer, BlurPreservesIntensityAndAddsSigmaSquared) {
  const host::CameraConfig camera = make_camera(60.0, true);
  const CameraPose pose{0.0, 0.0, 0.3};
  CeilingScene scene;
  const Eigen::Vector3d p = ceiling_point_near_pixel(camera, pose, 300.0, 250.0);
  scene.tapes.push_back({p.x() - 0.03, p.y(), p.x() + 0.03, p.y(), 0.06});
  RenderParams params = exact_params(8);
  const cv::Mat sharp = render_float(camera, scene, pose, params) - params.background_grey;
  params.blur_sigma_px = 1e-9;
  const cv::Mat tiny = render_float(camera, scene, pose, params) - params.background_grey;
  EXPECT_LT(cv::norm(sharp, tiny, cv::NORM_INF), 1e-12);  // sigma -> 0 leaves the image alone

  const double sigma_px = 1.7;
  params.blur_sigma_px = sigma_px;
  const cv::Mat blurred = render_float(camera, scene, pose, params) - params.background_grey;
  EXPECT_GT(cv::norm(sharp, blurred, cv::NORM_INF), 1.0);  // the blur did act
  const auto moments = [](const cv::Mat& image) {
    double m = 0, mu = 0, mv = 0;
    for (int j = 0; j < image.rows; ++j) {
      for (int i = 0; i < image.cols; ++i) {
        m += image.at<double>(j, i);
        mu += i * image.at<double>(j, i);
        mv += j * image.at<double>(j, i);
      }
    }
    double var_u = 0, var_v = 0;
    for (int j = 0; j < image.rows; ++j) {
      for (int i = 0; i < image.cols; ++i) {
        var_u += (i - mu / m) * (i - mu / m) * image.at<double>(j, i);
        var_v += (j - mv / m) * (j - mv / m) * image.at<double>(j, i);
      }
    }
    return std::array<double, 5>{m, mu / m, mv / m, var_u / m, var_v / m};
  };
  const auto before = moments(sharp);
  const auto after = moments(blurred);
  EXPECT_GT(before[0], 1000.0);
  EXPECT_NEAR(after[0], before[0], 1e-9 * before[0]);  // the blob is far from the borders
  EXPECT_NEAR(after[1], before[1], 1e-9);
  EXPECT_NEAR(after[2], before[2], 1e-9);
  // Convolution adds the kernel's variance (the sampled Gaussian's variance is
  // sigma^2 to ~1e-20 for sigma > 1; the +-5 sigma truncation removes < 1e-5).
  EXPECT_NEAR(after[3], before[3] + sigma_px * sigma_px, 1e-3);
  EXPECT_NEAR(after[4], before[4] + sigma_px * sigma_px, 1e-3);
}

// ---------------------------------------------------------------------------

// Adaptive sampling (tile culling, footprint classification, batched edge
// pixels) against full sampling of every pixel: edge and background pixels
// are bit-identical; interior pixels differ by the 2x2 midpoint vs NxN
// jittered quadrature of a smooth 1/r^2, which varies by < 1% across a
// footprint: relative difference < 1e-3. A wrongly classified edge pixel
// (e.g. a strip culled that touches it) would differ by >= 1/N^2 = 6% of its
// value.
void expect_adaptive_equals_full(const host::CameraConfig& camera, const CeilingScene& scene,
                                 const CameraPose& pose, RenderParams params) {
  RenderStats adaptive_stats, full_stats;
  params.adaptive_sampling = true;
  const cv::Mat adaptive = render_float(camera, scene, pose, params, &adaptive_stats);
  params.adaptive_sampling = false;
  const cv::Mat full = render_float(camera, scene, pose, params, &full_stats);
  double peak = 0.0;
  cv::minMaxLoc(full, nullptr, &peak);
  EXPECT_GT(peak, 60.0);
  EXPECT_LT(cv::norm(adaptive, full, cv::NORM_INF), 1e-3 * peak);
  int differing = 0;
  for (int j = 0; j < full.rows; ++j) {
    for (int i = 0; i < full.cols; ++i)
      differing += adaptive.at<double>(j, i) != full.at<double>(j, i);
  }
  EXPECT_LE(differing, adaptive_stats.interior_pixels);
  EXPECT_GT(adaptive_stats.edge_pixels, 100);
  EXPECT_GT(adaptive_stats.interior_pixels, 100);
  EXPECT_LT(adaptive_stats.edge_pixels, full_stats.edge_pixels / 20);
  EXPECT_EQ(adaptive_stats.background_pixels + adaptive_stats.interior_pixels +
                adaptive_stats.edge_pixels,
            static_cast<int64_t>(camera.image_width) * camera.image_height);
}

TEST(GoldenRenderer, AdaptiveSamplingEqualsFullSampling) {
  const CeilingScene scene = corridor_scene(0.05, {.second_tape = true});
  struct Case {
    double pitch_deg;
    bool distorted;
    CameraPose pose;
  };
  for (const Case& tc : {Case{45.0, true, {4.0, 0.3, 0.1}}, Case{90.0, true, {9.8, -0.2, 0.4}},
                         Case{20.0, false, {0.0, 0.5, -0.05}}}) {
    const host::CameraConfig camera = make_camera(tc.pitch_deg, tc.distorted);
    RenderParams params = exact_params(4);
    params.apply_distortion = tc.distorted;
    expect_adaptive_equals_full(camera, scene, tc.pose, params);
  }
}

// The tile culling scales a strip on its own ceiling height like the pixels'
// box test: strips above and below the default ceiling, seen steeply and
// towards the horizon, render as with full sampling.
TEST(GoldenRenderer, AdaptiveSamplingEqualsFullSamplingOnHeightZones) {
  CeilingScene scene = corridor_scene(0.05, {.second_tape = true});
  for (std::size_t k = 0; k < scene.tapes.size(); ++k) {
    if (k % 3 != 0) scene.tapes[k].ceiling_height_m = k % 3 == 1 ? 3.4 : 2.6;
  }
  for (const double pitch : {60.0, 15.0}) {
    const host::CameraConfig camera = make_camera(pitch, true);
    expect_adaptive_equals_full(camera, scene, {5.5, 0.2, 0.3}, exact_params(4));
  }
}

TEST(GoldenRenderer, RadianceOfTheViewFinishedOnceIsRenderFloat) {
  const host::CameraConfig camera = make_camera(40.0, true);
  const CeilingScene scene = corridor_scene(0.05, {.second_tape = true});
  const CameraPose pose{5.2, 0.21, -0.15};
  RenderParams params;  // blur and noise on
  RenderStats stats_float, stats_radiance;
  const cv::Mat expected = render_float(camera, scene, pose, params, &stats_float);
  cv::Mat image =
      render_radiance(camera, scene, camera_view(camera, pose), params, &stats_radiance);
  finish_render(image, params);
  EXPECT_EQ(cv::norm(image, expected, cv::NORM_INF), 0.0);
  EXPECT_EQ(stats_radiance.edge_pixels, stats_float.edge_pixels);
  EXPECT_EQ(stats_radiance.samples, stats_float.samples);
}

// Pixels of two renders that differ by more than `tolerance`.
int pixels_differing(const cv::Mat& a, const cv::Mat& b, double tolerance) {
  cv::Mat diff;
  cv::absdiff(a, b, diff);
  return cv::countNonZero(diff > tolerance);
}

TEST(GoldenRenderer, AStripOnItsOwnCeilingHeightIsSeenAsOnThatCeiling) {
  // A strip with ceiling_height_m = 3.4 under a configured 3.0 m ceiling
  // renders as the same strip under a configured 3.4 m ceiling: the same
  // rays, points scaled from the camera by k = 2.9 / 2.5, radiance / k^2.
  for (const double pitch : {35.0, 90.0}) {
    host::CameraConfig camera = make_camera(pitch, true);
    CeilingScene own;
    own.tapes.push_back({-5.0, 0.1, 30.0, 0.3, 0.05, 1.0, 3.4});
    own.tapes.push_back({2.0, -3.0, 2.5, 3.0, 0.08, 1.5, 3.4});
    CeilingScene plain = own;
    for (TapeSegment& t : plain.tapes) t.ceiling_height_m = 0.0;
    const CameraPose pose{0.3, -0.1, 0.2};
    const RenderParams params = exact_params(8);
    const cv::Mat scaled = render_float(camera, own, pose, params);
    camera.ceiling_height_m = 3.4;
    const cv::Mat reference = render_float(camera, plain, pose, params);
    double peak = 0.0;
    cv::minMaxLoc(reference, nullptr, &peak);
    EXPECT_GT(peak, 60.0);
    // The same samples: equal but for rounding (a sample on an edge to the
    // last bit may flip).
    EXPECT_LE(pixels_differing(scaled, reference, 1e-9 * peak), 2) << pitch;
    // Its height is what matters: at the configured height it is the plain strip.
    for (TapeSegment& t : own.tapes) t.ceiling_height_m = 3.4;
    EXPECT_EQ(cv::norm(render_float(camera, own, pose, params), reference, cv::NORM_INF), 0.0);
  }
}

TEST(GoldenRenderer, RollAboutAZenithAxisIsAYawTurn) {
  // At pitch 90 deg a roll by phi about the optical axis is the yaw psi + phi.
  const host::CameraConfig camera = make_camera(90.0, true);
  const CeilingScene scene = corridor_scene(0.05, {.second_tape = true});
  const CameraPose pose{9.8, -0.2, 0.3};
  const double phi = 0.1;
  CameraView view = camera_view(camera, pose);
  Eigen::Matrix3d roll;
  roll << std::cos(phi), std::sin(phi), 0.0, -std::sin(phi), std::cos(phi), 0.0, 0.0, 0.0, 1.0;
  view.world_to_camera = roll * view.world_to_camera;
  const RenderParams params = exact_params(8);
  const cv::Mat rolled = render_radiance(camera, scene, view, params);
  const cv::Mat turned =
      render_radiance(camera, scene, camera_view(camera, {9.8, -0.2, 0.3 + phi}), params);
  double peak = 0.0;
  cv::minMaxLoc(turned, nullptr, &peak);
  EXPECT_GT(peak, 60.0);
  EXPECT_LE(pixels_differing(rolled, turned, 1e-9 * peak), 2);
  // A view that differs: a pitch 1 deg off changes many pixels.
  view = camera_view(camera, pose);
  view.world_to_camera = world_to_camera_rotation(0.3, 89.0 * kDeg);
  EXPECT_GT(pixels_differing(render_radiance(camera, scene, view, params),
                             render_radiance(camera, scene, camera_view(camera, pose), params),
                             1e-3 * peak),
            100);
}

TEST(GoldenRenderer, RejectsBadInput) {
  const host::CameraConfig camera = make_camera(45.0, false);
  const CeilingScene scene = single_tape_scene(0.05);
  RenderParams params;
  params.supersample = 0;
  EXPECT_THROW(render_frame(camera, scene, {}, params), std::invalid_argument);
  host::CameraConfig low_ceiling = camera;
  low_ceiling.ceiling_height_m = 0.4;
  EXPECT_THROW(render_frame(low_ceiling, scene, {}, RenderParams{}), std::invalid_argument);
  CeilingScene degenerate;
  degenerate.tapes.push_back({1.0, 1.0, 1.0, 1.0, 0.05});
  EXPECT_THROW(render_frame(camera, degenerate, {}, RenderParams{}), std::invalid_argument);
  CeilingScene below;
  below.tapes.push_back({0.0, 0.0, 5.0, 0.0, 0.05, 1.0, 0.45});  // under the camera
  EXPECT_THROW(render_frame(camera, below, {}, RenderParams{}), std::invalid_argument);
  CameraView nan_view = camera_view(camera, {});
  nan_view.centre.x() = std::nan("");
  EXPECT_THROW(render_radiance(camera, scene, nan_view, RenderParams{}), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::golden
