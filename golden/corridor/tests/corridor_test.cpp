// The corridor's truth against independent computations (golden's
// project_point and truth_for, line intersections) and the rendered frames
// against the truth: edges found in the image lie on the truth lines.
// Derivations: docs/renderer.md, "Corridor scenes".
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "golden/corridor/corridor.hpp"
#include "golden/corridor/render.hpp"
#include "golden/scene.hpp"

namespace ceilnav::golden::corridor {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

host::CameraConfig make_camera(bool distorted, double fy = 498.0) {
  host::CameraConfig camera;
  camera.camera_matrix = {505.0, 0.0, 322.3, 0.0, fy, 236.8, 0.0, 0.0, 1.0};
  if (distorted) camera.distortion_coefficients = {-0.28, 0.09, 0.0012, -0.0008, -0.012};
  return camera;
}

RenderParams exact_params() {
  RenderParams p;
  p.blur_sigma_px = 0.0;
  p.noise_sigma_grey = 0.0;
  return p;
}

// Pixel of a world point on the undistorted image (pinhole, own K R).
Eigen::Vector2d pinhole(const host::CameraConfig& camera, const Pose& pose,
                        const Eigen::Vector3d& world) {
  const CameraView v = view_of(pose);
  const Eigen::Vector3d p = v.world_to_camera * (world - v.centre);
  return {camera.fx() * p.x() / p.z() + camera.cx(), camera.fy() * p.y() / p.z() + camera.cy()};
}

Eigen::Vector3d homogeneous_line(const ImageLine& l) {
  return {std::cos(l.theta_rad), std::sin(l.theta_rad), -l.rho_px};
}

// |sin| of the angle between two homogeneous vectors: 0 when they are one point.
double projective_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return a.normalized().cross(b.normalized()).norm();
}

std::vector<Pose> poses() {
  std::vector<Pose> out{default_pose(),
                        {3.0, -0.8, 0.4, -12.0 * kDeg, 20.0 * kDeg, 3.0 * kDeg},
                        {10.0, 0.5, 1.6, 25.0 * kDeg, 60.0 * kDeg, -8.0 * kDeg},
                        {1.0, 0.0, 1.2, 0.0, 89.0 * kDeg, 0.0}};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pan(-40.0, 40.0), tilt(5.0, 85.0), swing(-20.0, 20.0),
      lateral(-1.0, 1.0), height(0.3, 2.2);
  for (int i = 0; i < 20; ++i) {
    out.push_back(
        {2.0 + i, lateral(rng), height(rng), pan(rng) * kDeg, tilt(rng) * kDeg, swing(rng) * kDeg});
  }
  return out;
}

TEST(CorridorTruth, SwingZeroIsGoldensCameraAndVanishingPoint) {
  // With swing 0 the pose is golden's camera (yaw = pan, pitch = tilt): the
  // same rotation, projection and vanishing point of +X.
  host::CameraConfig camera = make_camera(false);
  const Corridor corridor = default_corridor();
  for (const Pose& pose : poses()) {
    Pose flat = pose;
    flat.swing_rad = 0.0;
    camera.camera_pitch_deg = flat.tilt_rad / kDeg;
    camera.camera_height_m = flat.height_m;
    camera.ceiling_height_m = corridor.ceiling_height_m;
    const CameraPose golden_pose{flat.x_m, flat.y_m, flat.pan_rad};
    EXPECT_LT(
        (view_of(flat).world_to_camera - world_to_camera_rotation(flat.pan_rad, pitch_rad(camera)))
            .cwiseAbs()
            .maxCoeff(),
        1e-15);
    const FrameTruth truth = truth_for(camera, corridor, flat);
    const golden::FrameTruth g = golden::truth_for(camera, CeilingScene{}, golden_pose);
    ASSERT_EQ(truth.axis.finite, g.vp_finite);
    if (g.vp_finite) {
      EXPECT_NEAR(truth.axis.u_px, g.vp_u_px, 1e-7 * (1.0 + std::abs(g.vp_u_px)));
      EXPECT_NEAR(truth.axis.v_px, g.vp_v_px, 1e-7 * (1.0 + std::abs(g.vp_v_px)));
    }
    for (const ImageLine& line : truth.lines) {
      for (double x : {line.line.x0_m, 0.5 * (line.line.x0_m + line.line.x1_m), line.line.x1_m}) {
        const auto px = project_point(camera, golden_pose,
                                      line.line.point + Eigen::Vector3d(x, 0.0, 0.0), false);
        if (!px) continue;
        EXPECT_NEAR(px->x() * std::cos(line.theta_rad) + px->y() * std::sin(line.theta_rad),
                    line.rho_px, 1e-7 * (1.0 + px->norm()))
            << line.line.name;
      }
    }
  }
}

TEST(CorridorTruth, LinesHoldTheirProjectedPointsAndMeetAtTheVanishingPoints) {
  const host::CameraConfig camera = make_camera(false);
  const Corridor corridor = default_corridor();
  for (const Pose& pose : poses()) {
    const FrameTruth truth = truth_for(camera, corridor, pose);
    ASSERT_EQ(truth.lines.size(), axis_lines(corridor).size());
    std::vector<Eigen::Vector3d> lines;
    for (const ImageLine& line : truth.lines) {
      ASSERT_TRUE(line.defined) << line.line.name;
      EXPECT_GE(line.theta_rad, 0.0);
      EXPECT_LT(line.theta_rad, std::numbers::pi);
      const CameraView v = view_of(pose);
      for (double x : {-3.0, 0.5, 7.0, 40.0}) {
        const Eigen::Vector3d world = line.line.point + Eigen::Vector3d(x, 0.0, 0.0);
        if ((v.world_to_camera * (world - v.centre)).z() < 0.05) continue;
        const Eigen::Vector2d px = pinhole(camera, pose, world);
        EXPECT_NEAR(px.x() * std::cos(line.theta_rad) + px.y() * std::sin(line.theta_rad),
                    line.rho_px, 1e-8 * (1.0 + px.norm()));
      }
      lines.push_back(homogeneous_line(line));
    }
    // Every pair of axis lines meets at the axis vanishing point.
    for (std::size_t i = 0; i < lines.size(); ++i) {
      for (std::size_t j = i + 1; j < lines.size(); ++j) {
        if (projective_distance(lines[i], lines[j]) < 1e-6) continue;  // (nearly) one image line
        EXPECT_LT(projective_distance(lines[i].cross(lines[j]), truth.axis.homogeneous), 1e-9);
      }
    }
    // Cross (+Y) and vertical (+Z) directions: the image of a lamp end, a
    // door jamb passes through their vanishing points.
    const Eigen::Vector3d lamp_end(corridor.lamps.first_x_m + 0.6, 0.0, corridor.ceiling_height_m);
    const Eigen::Vector3d jamb(corridor.doors[0].x_m, 0.5 * corridor.width_m, 1.0);
    const CameraView v = view_of(pose);
    for (const auto& [point, dir, vp] :
         {std::tuple{lamp_end, Eigen::Vector3d(0, 1, 0), truth.cross},
          std::tuple{jamb, Eigen::Vector3d(0, 0, 1), truth.vertical}}) {
      const Eigen::Vector3d a = v.world_to_camera * (point - v.centre);
      const Eigen::Vector3d b = v.world_to_camera * (point + 0.3 * dir - v.centre);
      Eigen::Matrix3d k;
      k << camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1;
      const Eigen::Vector3d line = (k * a).cross(k * b);
      EXPECT_LT(std::abs(line.normalized().dot(vp.homogeneous)), 1e-12);
    }
  }
}

TEST(CorridorTruth, PanTiltSwingSignConventions) {
  // Axis vanishing point (docs/renderer.md, "Corridor scenes"): R e_x =
  // (sin pan, sin tilt cos pan, cos tilt cos pan) at swing 0, so
  // u = cx + fx tan(pan) / cos(tilt), v = cy + fy tan(tilt).
  const host::CameraConfig camera = make_camera(false, 505.0);
  const Corridor corridor = default_corridor();
  Pose pose{0.0, 0.0, 1.0, 0.0, 30.0 * kDeg, 0.0};
  const FrameTruth level = truth_for(camera, corridor, pose);
  EXPECT_NEAR(level.axis.u_px, camera.cx(), 1e-9);
  EXPECT_NEAR(level.axis.v_px, camera.cy() + camera.fy() * std::tan(30.0 * kDeg), 1e-9);
  // Positive pan (turn left, counter-clockwise seen from above): the
  // corridor direction is now to the camera's right, the vanishing point
  // moves right (u grows).
  pose.pan_rad = 10.0 * kDeg;
  const FrameTruth panned = truth_for(camera, corridor, pose);
  EXPECT_GT(panned.axis.u_px, level.axis.u_px + 50.0);
  EXPECT_NEAR(panned.axis.u_px,
              camera.cx() + camera.fx() * std::tan(10.0 * kDeg) / std::cos(30.0 * kDeg), 1e-9);
  EXPECT_NEAR(panned.axis.v_px, level.axis.v_px, 1e-9);
  // Positive tilt (look up): the horizon and the vanishing point move down.
  pose.pan_rad = 0.0;
  pose.tilt_rad = 40.0 * kDeg;
  EXPECT_GT(truth_for(camera, corridor, pose).axis.v_px, level.axis.v_px + 50.0);
  // Positive swing: the image content turns counter-clockwise on the screen
  // (v down) about the principal point: (du, dv) -> (c du + s dv, -s du + c dv).
  for (double swing : {5.0, -17.0, 60.0}) {
    pose = {4.0, 0.2, 1.0, 10.0 * kDeg, 30.0 * kDeg, 0.0};
    const FrameTruth flat = truth_for(camera, corridor, pose);
    pose.swing_rad = swing * kDeg;
    const FrameTruth turned = truth_for(camera, corridor, pose);
    const double c = std::cos(swing * kDeg), s = std::sin(swing * kDeg);
    for (const auto& [a, b] : {std::pair{flat.axis, turned.axis}, {flat.cross, turned.cross}}) {
      const double du = a.u_px - camera.cx(), dv = a.v_px - camera.cy();
      EXPECT_NEAR(b.u_px - camera.cx(), c * du + s * dv, 1e-8 * (1.0 + std::hypot(du, dv)));
      EXPECT_NEAR(b.v_px - camera.cy(), -s * du + c * dv, 1e-8 * (1.0 + std::hypot(du, dv)));
    }
    if (swing == 5.0) {  // counter-clockwise on screen: a point right of centre moves up
      EXPECT_LT(turned.axis.v_px - camera.cy(), flat.axis.v_px - camera.cy());
    }
  }
  // Straight ahead and level: the vanishing point is the principal point;
  // the junctions are symmetric, the left wall's on the image's left.
  pose = {4.0, 0.0, 1.4, 0.0, 0.0, 0.0};
  const FrameTruth ahead = truth_for(camera, corridor, pose);
  EXPECT_NEAR(ahead.axis.u_px, camera.cx(), 1e-9);
  EXPECT_NEAR(ahead.axis.v_px, camera.cy(), 1e-9);
  EXPECT_FALSE(ahead.cross.finite);
  EXPECT_FALSE(ahead.vertical.finite);
}

TEST(CorridorTruth, VisibilityFollowsTheFrame) {
  const host::CameraConfig camera = make_camera(true);
  const Corridor corridor = default_corridor();
  // Looking up along the corridor: the ceiling lines are seen, the floor
  // junctions are not (behind the lower frame edge at tilt 60).
  const Pose up{2.0, 0.0, 1.0, 0.0, 60.0 * kDeg, 0.0};
  const FrameTruth t = truth_for(camera, corridor, up);
  for (const ImageLine& l : t.lines) {
    if (l.line.kind == LineKind::lamp_edge || l.line.kind == LineKind::junction) {
      EXPECT_TRUE(l.visible) << l.line.name;
      // The visible ends lie on the line.
      for (const Eigen::Vector2d& p : {l.from_px, l.to_px}) {
        EXPECT_NEAR(p.x() * std::cos(l.theta_rad) + p.y() * std::sin(l.theta_rad), l.rho_px, 1e-6);
      }
    }
    if (l.line.kind == LineKind::floor_junction) {
      EXPECT_FALSE(l.visible) << l.line.name;
    }
  }
  // Looking back at the near wall from close by: the lamps start ahead.
  const Pose back{-4.5, 0.0, 1.0, std::numbers::pi, 10.0 * kDeg, 0.0};
  for (const ImageLine& l : truth_for(camera, corridor, back).lines) {
    if (l.line.kind == LineKind::lamp_edge) {
      EXPECT_FALSE(l.visible) << l.line.name;
    }
  }
}

// ---------------------------------------------------------------------------
// Rendered edges against the truth.

// Bilinear value of a CV_64FC1 image at (u, v); false outside.
bool bilinear(const cv::Mat& image, double u, double v, double& out) {
  const int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
  if (i < 0 || j < 0 || i + 1 >= image.cols || j + 1 >= image.rows) return false;
  const double fu = u - i, fv = v - j;
  out = (1 - fv) * ((1 - fu) * image.at<double>(j, i) + fu * image.at<double>(j, i + 1)) +
        fv * ((1 - fu) * image.at<double>(j + 1, i) + fu * image.at<double>(j + 1, i + 1));
  return true;
}

// Distorted pixel of an undistorted pixel.
Eigen::Vector2d distort_px(const host::CameraConfig& camera, const Eigen::Vector2d& px) {
  const Eigen::Vector2d n((px.x() - camera.cx()) / camera.fx(),
                          (px.y() - camera.cy()) / camera.fy());
  const Eigen::Vector2d d = distort_normalised(camera, n);
  return {camera.fx() * d.x() + camera.cx(), camera.fy() * d.y() + camera.cy()};
}

// The edge's sub-pixel position near the undistorted point q of a truth
// line: the half-way crossing of the rendered profile along the line's
// normal (taken into the distorted image), mapped back to the undistorted
// image. false where the profile leaves the frame or has no clear step.
bool edge_point(const host::CameraConfig& camera, const cv::Mat& image, const ImageLine& line,
                const Eigen::Vector2d& q, Eigen::Vector2d& found) {
  const Eigen::Vector2d normal(std::cos(line.theta_rad), std::sin(line.theta_rad));
  const Eigen::Vector2d centre = distort_px(camera, q);
  // Only where the lens model is one to one (beyond its fold-over a point
  // far outside the view distorts into the frame).
  const std::optional<Eigen::Vector2d> back = undistort_pixel(camera, centre);
  if (!back || std::hypot(camera.fx() * back->x() + camera.cx() - q.x(),
                          camera.fy() * back->y() + camera.cy() - q.y()) > 1e-6) {
    return false;
  }
  Eigen::Vector2d dn = distort_px(camera, q + 0.01 * normal) - centre;
  dn.normalize();
  constexpr int kSteps = 160;  // -4 .. +4 px in steps of 0.05
  std::vector<double> profile(kSteps + 1);
  for (int s = 0; s <= kSteps; ++s) {
    const Eigen::Vector2d p = centre + (-4.0 + 0.05 * s) * dn;
    if (!bilinear(image, p.x(), p.y(), profile[static_cast<std::size_t>(s)])) return false;
  }
  const double lo = profile.front(), hi = profile.back();
  if (std::abs(hi - lo) < 20.0) return false;
  const double half = 0.5 * (lo + hi);
  double best = 1e9;  // the crossing nearest the truth line
  for (std::size_t s = 0; s + 1 < profile.size(); ++s) {
    if ((profile[s] - half) * (profile[s + 1] - half) > 0.0 || profile[s + 1] == profile[s]) {
      continue;
    }
    const double f = (half - profile[s]) / (profile[s + 1] - profile[s]);
    const double offset = -4.0 + 0.05 * (static_cast<double>(s) + f);
    if (std::abs(offset) < std::abs(best)) best = offset;
  }
  if (best > 1e8) return false;
  const std::optional<Eigen::Vector2d> n = undistort_pixel(camera, centre + best * dn);
  if (!n) return false;
  found = {camera.fx() * n->x() + camera.cx(), camera.fy() * n->y() + camera.cy()};
  return true;
}

// A corridor of strong edges: bright lamps on a dark ceiling over bright
// walls, no seams, bands or doors.
Corridor contrast_corridor() {
  Corridor c;
  c.lamps.rows_y_m = {-0.55, 0.45};
  c.lamps.first_x_m = 1.0;
  c.lamps.radiance = 2.2;
  c.ceiling_albedo = 0.3;
  c.wall_albedo = 1.2;
  return c;
}

// Fits a line (cv::fitLine, L2) to the edge points found along a truth line
// where `usable(x)` holds for the point's world x; returns the largest
// distance of the fitted line from the truth line over the points' span.
double fitted_line_error(const host::CameraConfig& camera, const cv::Mat& image,
                         const ImageLine& line, const Pose& pose,
                         const std::function<bool(double)>& usable, int& points) {
  std::vector<cv::Point2f> found;
  const CameraView v = view_of(pose);
  for (double x = line.line.x0_m; x <= line.line.x1_m; x += 0.01) {
    if (!usable(x)) continue;
    const Eigen::Vector3d world = line.line.point + Eigen::Vector3d(x, 0.0, 0.0);
    if ((v.world_to_camera * (world - v.centre)).z() < 0.3) continue;
    const Eigen::Vector2d q = pinhole(camera, pose, world);
    Eigen::Vector2d p;
    if (!edge_point(camera, image, line, q, p)) continue;
    found.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  }
  points = static_cast<int>(found.size());
  if (found.size() < 20) return 1e9;
  cv::Vec4f fit;
  cv::fitLine(found, fit, cv::DIST_L2, 0, 1e-4, 1e-4);
  const Eigen::Vector2d dir(fit[0], fit[1]), origin(fit[2], fit[3]);
  const Eigen::Vector2d n(std::cos(line.theta_rad), std::sin(line.theta_rad));
  double worst = 0.0;
  for (const cv::Point2f& p : found) {
    // The fitted line at the point's place along it.
    const Eigen::Vector2d on = origin + dir * dir.dot(Eigen::Vector2d(p.x, p.y) - origin);
    worst = std::max(worst, std::abs(on.dot(n) - line.rho_px));
  }
  return worst;
}

TEST(CorridorRender, LampAndJunctionEdgesLieOnTheTruthLines) {
  const Corridor corridor = contrast_corridor();
  RenderParams params = exact_params();
  int checked = 0;
  double worst = 0.0;
  for (bool distorted : {false, true}) {
    const host::CameraConfig camera = make_camera(distorted);
    for (const Pose& pose : {Pose{0.0, 0.2, 1.0, 6.0 * kDeg, 35.0 * kDeg, 0.0},
                             Pose{2.0, -0.4, 0.8, -10.0 * kDeg, 55.0 * kDeg, 7.0 * kDeg},
                             Pose{5.0, 0.1, 1.3, 3.0 * kDeg, 80.0 * kDeg, -4.0 * kDeg}}) {
      const cv::Mat image = render_float(camera, corridor, pose, params);
      const FrameTruth truth = truth_for(camera, corridor, pose);
      for (const ImageLine& line : truth.lines) {
        if (!line.visible) continue;
        std::function<bool(double)> usable;
        if (line.line.kind == LineKind::lamp_edge) {
          // On a lamp, away from its ends.
          usable = [&](double x) {
            const double rel =
                std::fmod(x - corridor.lamps.first_x_m + 0.5 * corridor.lamps.spacing_m,
                          corridor.lamps.spacing_m) -
                0.5 * corridor.lamps.spacing_m;
            return std::abs(rel) < 0.5 * corridor.lamps.length_m - 0.1;
          };
        } else if (line.line.kind == LineKind::junction) {
          usable = [](double x) { return x > -4.0; };
        } else {
          continue;
        }
        int points = 0;
        const double error = fitted_line_error(camera, image, line, pose, usable, points);
        if (points < 20) continue;  // too little of it in the frame
        EXPECT_LT(error, 0.15) << line.line.name << " distorted " << distorted << " pose tilt "
                               << pose.tilt_rad / kDeg << " (" << points << " points)";
        ++checked;
        worst = std::max(worst, error);
      }
    }
  }
  EXPECT_GE(checked, 20);
  RecordProperty("lines_checked", checked);
  RecordProperty("worst_error_px", std::to_string(worst));
  std::printf("%d lines, worst fitted-line distance from the truth %.4f px\n", checked, worst);
}

TEST(CorridorRender, DeterministicPerSeed) {
  const host::CameraConfig camera = make_camera(true);
  RenderParams params;  // noise and blur on
  const cv::Mat a = render_frame(camera, default_corridor(), default_pose(), params);
  const cv::Mat b = render_frame(camera, default_corridor(), default_pose(), params);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  params.noise_seed = 2;
  const cv::Mat c = render_frame(camera, default_corridor(), default_pose(), params);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 0.5 * static_cast<double>(a.total()));
  // The noise is the golden renderer's: zero mean, the sigma asked for.
  params.noise_sigma_grey = 0.0;
  const cv::Mat clean = render_float(camera, default_corridor(), default_pose(), params);
  params.noise_sigma_grey = 3.0;
  const cv::Mat noisy = render_float(camera, default_corridor(), default_pose(), params);
  cv::Scalar mean, sigma;
  cv::meanStdDev(noisy - clean, mean, sigma);
  EXPECT_NEAR(mean[0], 0.0, 0.05);
  EXPECT_NEAR(sigma[0], 3.0, 0.05);
}

TEST(CorridorRender, AdaptiveSamplingEqualsFullSampling) {
  host::CameraConfig camera = make_camera(true);
  camera.image_width = 200;
  camera.image_height = 150;
  camera.camera_matrix = {160.0, 0.0, 99.5, 0.0, 158.0, 74.5, 0.0, 0.0, 1.0};
  const Corridor corridor = default_corridor();
  RenderParams params = exact_params();
  for (const Pose& pose :
       {default_pose(), Pose{6.0, -0.5, 0.6, -20.0 * kDeg, 15.0 * kDeg, 9.0 * kDeg}}) {
    RenderStats stats;
    const cv::Mat adaptive = render_radiance(camera, corridor, view_of(pose), params, &stats);
    params.adaptive_sampling = false;
    const cv::Mat full = render_radiance(camera, corridor, view_of(pose), params);
    params.adaptive_sampling = true;
    EXPECT_GT(stats.uniform_pixels, 4 * stats.edge_pixels);
    EXPECT_GT(stats.edge_pixels, 500);
    EXPECT_EQ(stats.uniform_pixels + stats.edge_pixels, 200 * 150);
    // Edge pixels are sampled alike in both modes: equal; uniform pixels
    // differ only by the smooth lighting's variation over the footprint.
    double max_diff = 0.0;
    int equal = 0;
    for (int j = 0; j < 150; ++j) {
      for (int i = 0; i < 200; ++i) {
        const double d = std::abs(adaptive.at<double>(j, i) - full.at<double>(j, i));
        max_diff = std::max(max_diff, d);
        equal += d == 0.0;
      }
    }
    EXPECT_LT(max_diff, 1e-3);
    EXPECT_GE(equal, stats.edge_pixels);
  }
}

TEST(CorridorRender, MotionBlurAveragesTheSubexposures) {
  const host::CameraConfig camera = make_camera(false);
  const Corridor corridor = default_corridor();
  RenderParams params = exact_params();
  const Pose a = default_pose();
  Pose b = a;
  b.x_m += 0.05;
  b.pan_rad += 1.0 * kDeg;
  const Exposure exposure{a, b, 4};
  const cv::Mat blurred = render_float(camera, corridor, exposure, params);
  cv::Mat sum(camera.image_height, camera.image_width, CV_64FC1, cv::Scalar(0.0));
  for (int k = 0; k < 4; ++k) {
    sum += render_radiance(camera, corridor, view_of(interpolate(a, b, (k + 0.5) / 4.0)), params);
  }
  sum *= params.gain_grey / 4.0;
  EXPECT_LT(cv::norm(blurred, sum, cv::NORM_INF), 1e-9);
  EXPECT_EQ(mid_exposure(exposure), interpolate(a, b, 0.5));
  // A still exposure is the single frame.
  EXPECT_EQ(cv::norm(render_float(camera, corridor, Exposure{a, a, 1}, params),
                     render_float(camera, corridor, a, params), cv::NORM_INF),
            0.0);
}

TEST(CorridorRender, RejectsBadInput) {
  const host::CameraConfig camera = make_camera(false);
  RenderParams params = exact_params();
  Pose outside = default_pose();
  outside.y_m = 5.0;
  EXPECT_THROW(render_frame(camera, default_corridor(), outside, params), CorridorError);
  EXPECT_THROW(truth_for(camera, default_corridor(), outside), CorridorError);
  Corridor bad = default_corridor();
  bad.width_m = -1.0;
  EXPECT_THROW(render_frame(camera, bad, default_pose(), params), CorridorError);
  params.supersample = 0;
  EXPECT_THROW(render_frame(camera, default_corridor(), default_pose(), params),
               std::invalid_argument);
  params = exact_params();
  EXPECT_THROW(
      render_float(camera, default_corridor(), Exposure{default_pose(), default_pose(), 0}, params),
      std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::golden::corridor
