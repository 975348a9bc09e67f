#include "host/camera_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

namespace ceilnav::host {
namespace {

CameraConfig make_config(int w, int h, std::array<double, 5> dist) {
  CameraConfig c;
  c.image_width = w;
  c.image_height = h;
  const double f = 0.8 * w;
  c.camera_matrix = {f, 0.0, 0.5 * w - 0.5 + 3.25, 0.0, f * 1.01, 0.5 * h - 0.5 - 2.75, 0, 0, 1};
  c.distortion_coefficients = dist;
  return c;
}

// Distortion sets a calibration can produce for a 50-70 deg lens.
const std::vector<std::array<double, 5>> kDistortions = {
    {-0.30, 0.12, 0.0, 0.0, -0.02},       // barrel
    {0.15, -0.05, 0.0, 0.0, 0.01},        // pincushion
    {-0.22, 0.05, 1.5e-3, -2.0e-3, 0.0},  // with tangential terms
    {-0.05, 0.0, 0.0, 0.0, 0.0},          // mild
};

std::vector<cv::Point2d> pixel_grid(const CameraConfig& c) {
  std::vector<cv::Point2d> px;
  for (int j = 0; j <= 16; ++j) {
    for (int i = 0; i <= 16; ++i) {
      px.emplace_back(-0.5 + (c.image_width) * i / 16.0, -0.5 + (c.image_height) * j / 16.0);
    }
  }
  return px;
}

TEST(CameraModel, WithoutDistortionIsInverseK) {
  const CameraConfig c = make_config(640, 480, {});
  const CameraModel m(c);
  EXPECT_FALSE(m.has_distortion());
  for (const auto& p : pixel_grid(c)) {
    const Eigen::Vector2d xy = m.normalise(p.x, p.y);
    EXPECT_NEAR(xy.x(), (p.x - c.cx()) / c.fx(), 1e-15);
    EXPECT_NEAR(xy.y(), (p.y - c.cy()) / c.fy(), 1e-15);
    const Eigen::Vector2d back = m.distort_to_pixel(xy);
    EXPECT_NEAR(back.x(), p.x, 1e-12);
    EXPECT_NEAR(back.y(), p.y, 1e-12);
    EXPECT_EQ(m.ideal_pixel(xy), back);
  }
}

TEST(CameraModel, DistortToPixelMatchesProjectPoints) {
  for (const auto& dist : kDistortions) {
    const CameraConfig c = make_config(800, 600, dist);
    const CameraModel m(c);
    std::vector<cv::Point3d> obj;
    std::vector<Eigen::Vector2d> xy;
    for (int j = -6; j <= 6; ++j) {
      for (int i = -8; i <= 8; ++i) {
        xy.emplace_back(0.08 * i, 0.08 * j);
        obj.emplace_back(0.08 * i, 0.08 * j, 1.0);
      }
    }
    const cv::Mat k(3, 3, CV_64F, const_cast<double*>(c.camera_matrix.data()));
    const cv::Mat d(1, 5, CV_64F, const_cast<double*>(c.distortion_coefficients.data()));
    std::vector<cv::Point2d> img;
    cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d, img);
    for (size_t n = 0; n < xy.size(); ++n) {
      const Eigen::Vector2d p = m.distort_to_pixel(xy[n]);
      EXPECT_NEAR(p.x(), img[n].x, 1e-9);
      EXPECT_NEAR(p.y(), img[n].y, 1e-9);
      const Eigen::Vector2d ideal = m.ideal_pixel(xy[n]);
      EXPECT_NEAR(ideal.x(), c.fx() * xy[n].x() + c.cx(), 1e-12);
    }
  }
}

TEST(CameraModel, NormaliseInvertsDistortionToBelow1e10) {
  for (const auto& dist : kDistortions) {
    for (const auto& [w, h] : {std::pair{320, 240}, std::pair{640, 480}, std::pair{1280, 960}}) {
      const CameraConfig c = make_config(w, h, dist);
      const CameraModel m(c);
      for (const auto& p : pixel_grid(c)) {
        const Eigen::Vector2d xy = m.normalise(p.x, p.y);
        const Eigen::Vector2d xd = m.distort(xy);
        // Residual in normalised (distorted) coordinates.
        EXPECT_NEAR(xd.x(), (p.x - c.cx()) / c.fx(), 1e-12) << w << " " << p.x << "," << p.y;
        EXPECT_NEAR(xd.y(), (p.y - c.cy()) / c.fy(), 1e-12) << w << " " << p.x << "," << p.y;
      }
    }
  }
}

TEST(CameraModel, NormaliseMatchesUndistortPoints) {
  for (const auto& dist : kDistortions) {
    const CameraConfig c = make_config(640, 480, dist);
    const CameraModel m(c);
    const std::vector<cv::Point2d> px = pixel_grid(c);
    const cv::Mat k(3, 3, CV_64F, const_cast<double*>(c.camera_matrix.data()));
    const cv::Mat d(1, 5, CV_64F, const_cast<double*>(c.distortion_coefficients.data()));
    std::vector<cv::Point2d> und;
    // OpenCV's default is 5 fixed-point iterations; ask for convergence.
    cv::undistortPoints(
        px, und, k, d, cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 500, 1e-15));
    for (size_t n = 0; n < px.size(); ++n) {
      const Eigen::Vector2d xy = m.normalise(px[n].x, px[n].y);
      EXPECT_NEAR(xy.x(), und[n].x, 1e-9) << px[n].x << "," << px[n].y;
      EXPECT_NEAR(xy.y(), und[n].y, 1e-9) << px[n].x << "," << px[n].y;
    }
  }
}

// The batch form runs the same Newton iterations in SIMD lanes: the results
// must be the single-point ones bit for bit, inside the start table, outside
// it and for every batch length (spare lanes in the last block).
TEST(CameraModel, BatchNormaliseEqualsSinglePointBitForBit) {
  std::vector<std::array<double, 5>> sets = kDistortions;
  sets.push_back({});  // no distortion: K^-1
  for (const auto& dist : sets) {
    const CameraConfig c = make_config(640, 480, dist);
    const CameraModel m(c);
    for (size_t n : {size_t{0}, size_t{1}, size_t{15}, size_t{16}, size_t{17}, size_t{203}}) {
      std::vector<double> u(n), v(n), x(n), y(n);
      for (size_t i = 0; i < n; ++i) {
        // A spiral from the image centre out past the borders (the table's edge).
        const double t = static_cast<double>(i);
        u[i] = 319.5 + 1.9 * t * std::cos(0.37 * t) + 0.013 * t;
        v[i] = 239.5 + 1.5 * t * std::sin(0.37 * t) - 0.007 * t;
      }
      m.normalise(u, v, x, y);
      for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector2d want = m.normalise(u[i], v[i]);
        EXPECT_EQ(x[i], want.x()) << n << " " << u[i] << "," << v[i];
        EXPECT_EQ(y[i], want.y()) << n << " " << u[i] << "," << v[i];
      }
    }
  }
  const CameraModel m(make_config(640, 480, kDistortions[0]));
  std::vector<double> a(3), b(2);
  EXPECT_THROW(m.normalise(a, a, a, b), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::host
