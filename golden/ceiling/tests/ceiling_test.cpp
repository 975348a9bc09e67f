// Structured ceilings (seed 004's homing): what covers each point and its
// radiance under a lighting, the file-free validation, the camera looking
// up, and the renderer against the projection of known points.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "golden/ceiling/ceiling.hpp"
#include "golden/ceiling/render.hpp"

namespace ceilnav::golden::ceiling {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Ceiling one_of_each() {
  Ceiling c;
  c.height_m = 3.0;
  Lamp l;
  l.rect = {1.0, 0.0, 1.2, 0.3, 0.0};
  c.lamps.push_back(l);
  Vent v;
  v.rect = {-1.0, 0.0, 0.5, 0.5, 0.0};
  v.slats = 2;  // 5 bands of 0.088 m inside the 0.03 m frame
  c.vents.push_back(v);
  c.spots.push_back({0.0, 1.0, 0.05, 0.2});
  c.beams.push_back({-2.0, -1.0, 2.0, -1.0, 0.2, 0.5});
  return c;
}

TEST(Ceiling, WhatCoversAPointAndItsRadiance) {
  const Ceiling c = one_of_each();
  Lighting on;
  const Paint lamp = paint_at(c, on, 1.0, 0.0);
  EXPECT_TRUE(lamp.emissive);
  EXPECT_DOUBLE_EQ(radiance_at(c, on, 1.0, 0.0), 3.0);
  EXPECT_DOUBLE_EQ(paint_at(c, on, 1.0, 0.145).value, 0.9);  // in the 2 cm frame
  EXPECT_FALSE(paint_at(c, on, 1.0, 0.145).emissive);
  // The grille: frame, then bands bar / slot / bar / slot / bar along X.
  const double in0 = -1.0 - 0.25 + 0.03, band = (0.5 - 0.06) / 5.0;
  EXPECT_DOUBLE_EQ(paint_at(c, on, -1.0 - 0.24, 0.0).value, 0.85);
  EXPECT_DOUBLE_EQ(paint_at(c, on, in0 + 0.5 * band, 0.0).value, 0.85);
  EXPECT_DOUBLE_EQ(paint_at(c, on, in0 + 1.5 * band, 0.0).value, 0.1);
  EXPECT_DOUBLE_EQ(paint_at(c, on, in0 + 2.5 * band, 0.0).value, 0.85);
  EXPECT_DOUBLE_EQ(paint_at(c, on, in0 + 3.5 * band, 0.0).value, 0.1);
  EXPECT_NE(paint_at(c, on, in0 + 1.5 * band, 0.0).id, paint_at(c, on, in0 + 0.5 * band, 0.0).id);
  EXPECT_DOUBLE_EQ(paint_at(c, on, 0.0, 1.04).value, 0.2);   // spot
  EXPECT_DOUBLE_EQ(paint_at(c, on, 0.5, -1.09).value, 0.5);  // beam
  // Tiles: 0.6 m grid with 24 mm gaps at multiples of 0.6.
  EXPECT_DOUBLE_EQ(paint_at(c, on, 0.61, 0.3).value, 0.55);
  EXPECT_DOUBLE_EQ(paint_at(c, on, 0.3, 0.3).value, 0.8);
  // Lighting: gain and gradient scale the albedos, not the lamps; lamps off
  // show their diffuser's albedo.
  Lighting dim;
  dim.gain = 0.5;
  dim.gradient_x_per_m = 0.1;
  EXPECT_DOUBLE_EQ(radiance_at(c, dim, 0.3, 0.3), 0.8 * 0.5 * 1.03);
  EXPECT_DOUBLE_EQ(radiance_at(c, dim, 1.0, 0.0), 3.0);
  Lighting off;
  off.lamps_on = false;
  EXPECT_FALSE(paint_at(c, off, 1.0, 0.0).emissive);
  EXPECT_DOUBLE_EQ(radiance_at(c, off, 1.0, 0.0), 0.7);
  // The tile grid turned by 45 deg.
  Ceiling t = c;
  t.tiles.angle_rad = 45.0 * kDeg;
  const double d = 0.6 / std::sqrt(2.0);
  EXPECT_DOUBLE_EQ(paint_at(t, on, 3.0 * d, 3.0 * d).value, 0.55);
}

TEST(Ceiling, ValidationNamesTheKey) {
  const auto error = [](const Ceiling& c) {
    try {
      validate(c, "c.yaml");
    } catch (const CeilingError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(office_ceiling()), "");
  EXPECT_EQ(error(hall_ceiling()), "");
  Ceiling c = one_of_each();
  c.height_m = -1.0;
  EXPECT_NE(error(c).find("c.yaml: height_m"), std::string::npos);
  c = one_of_each();
  c.tiles.gap_m = 0.7;
  EXPECT_NE(error(c).find("tiles.gap_m"), std::string::npos);
  c = one_of_each();
  c.lamps[0].border_m = 0.2;
  EXPECT_NE(error(c).find("lamps[0]"), std::string::npos);
  c = one_of_each();
  c.vents[0].slats = 0;
  EXPECT_NE(error(c).find("vents[0]"), std::string::npos);
  c = one_of_each();
  c.beams[0].x1_m = c.beams[0].x0_m;
  c.beams[0].y1_m = c.beams[0].y0_m;
  EXPECT_NE(error(c).find("beams[0]"), std::string::npos);
  c = one_of_each();
  c.spots[0].radius_m = std::nan("");
  EXPECT_NE(error(c).find("spots[0]"), std::string::npos);
  Lighting l;
  l.gain = -1.0;
  EXPECT_THROW(validate(l), CeilingError);
}

TEST(Ceiling, TheCameraLooksUpWithTheHeadingDownTheImage) {
  Pose p;
  p.yaw_rad = 30.0 * kDeg;
  const CameraView v = view_of(p);
  const Eigen::Vector3d axis = v.world_to_camera.row(2).transpose();
  EXPECT_NEAR(axis.z(), 1.0, 1e-12);
  const Eigen::Vector3d heading(std::cos(p.yaw_rad), std::sin(p.yaw_rad), 0.0);
  EXPECT_NEAR(v.world_to_camera.row(1).dot(heading), 1.0, 1e-12);  // v down the image
  const Eigen::Vector3d left(-heading.y(), heading.x(), 0.0);
  EXPECT_NEAR(v.world_to_camera.row(0).dot(left), -1.0, 1e-12);  // u to the right
  p.pitch_error_rad = 0.02;
  EXPECT_NEAR(view_of(p).world_to_camera.row(2).dot(heading), std::sin(0.02), 1e-12);
  p.pitch_error_rad = 0.0;
  p.roll_error_rad = 0.02;
  EXPECT_NEAR(view_of(p).world_to_camera.row(2).dot(left), std::sin(0.02), 1e-12);
}

// A lamp alone on a plain ceiling: the bright blob's centroid is the
// projection of the lamp's centre (an affine image of a rectangle keeps its
// centroid; blur and the symmetric footprint integration keep it too), for
// poses turned and shifted, with and without the lens distortion.
TEST(Ceiling, RenderedLampLiesWhereItsCentreProjects) {
  Ceiling c;
  c.height_m = 3.0;
  c.tiles.pitch_x_m = c.tiles.pitch_y_m = 0.0;
  c.plain_albedo = 0.2;
  Lamp l;
  l.rect = {0.4, -0.2, 0.6, 0.3, 20.0 * kDeg};
  l.border_m = 0.0;
  c.lamps.push_back(l);
  host::CameraConfig cam;
  RenderParams rp;
  rp.noise_sigma_grey = 0.0;
  rp.gain_grey = 60.0;
  for (const double yaw_deg : {0.0, 37.0, -120.0}) {
    Pose p;
    p.x_m = 0.1;
    p.y_m = 0.05;
    p.height_m = 0.5;
    p.yaw_rad = yaw_deg * kDeg;
    const cv::Mat r = render_radiance(cam, c, Lighting{}, p, rp);
    // Centroid of (radiance - plain) over the image.
    double s = 0.0, su = 0.0, sv = 0.0;
    for (int v = 0; v < r.rows; ++v) {
      for (int u = 0; u < r.cols; ++u) {
        const double e = r.at<double>(v, u) - 0.2;
        if (e <= 1e-12) continue;
        s += e;
        su += e * u;
        sv += e * v;
      }
    }
    ASSERT_GT(s, 0.0);
    const auto px = project(cam, c, p, l.rect.x_m, l.rect.y_m, false);
    ASSERT_TRUE(px.has_value());
    EXPECT_NEAR(su / s, px->x(), 0.02) << "yaw " << yaw_deg;
    EXPECT_NEAR(sv / s, px->y(), 0.02) << "yaw " << yaw_deg;
  }
}

// The adaptive footprints against N x N samples everywhere.
TEST(Ceiling, AdaptiveSamplingMatchesTheReference) {
  const Ceiling c = office_ceiling();
  host::CameraConfig cam;
  cam.image_width = 160;
  cam.image_height = 120;
  cam.camera_matrix = {125.0, 0.0, 79.5, 0.0, 125.0, 59.5, 0.0, 0.0, 1.0};
  Pose p;
  p.x_m = 0.7;
  p.y_m = -1.1;
  p.yaw_rad = 12.0 * kDeg;
  RenderParams rp;
  rp.supersample = 6;
  Lighting l;
  l.gradient_y_per_m = 0.05;
  const cv::Mat a = render_radiance(cam, c, l, p, rp);
  rp.adaptive_sampling = false;
  const cv::Mat b = render_radiance(cam, c, l, p, rp);
  double worst = 0.0;
  cv::minMaxLoc(cv::abs(a - b), nullptr, &worst);
  // A uniform pixel's value is exact; the reference's samples differ from it
  // only through the light's gradient across the footprint (linear: the
  // jittered mean is within a small fraction of it).
  EXPECT_LT(worst, 2e-3);
}

}  // namespace
}  // namespace ceilnav::golden::ceiling
