// Seed 002 eq. 7-16 in our frames against golden::corridor::truth_for: the
// predicted vanishing points (eq. 10, 11), their inversion to the pan, the
// vanishing line's two roots (eq. 12-15) and the seed's sign, the robust
// point from lines and the status; the two-point pan against the axis point
// alone on synthetic frames with noisy lines.
#include "host/corridor/vanishing.hpp"

#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "golden/corridor/corridor.hpp"
#include "golden/scene.hpp"

namespace ceilnav::host::corridor {
namespace {

namespace gc = golden::corridor;
constexpr double kDeg = std::numbers::pi / 180.0;

CameraConfig camera(double fy = 505.0) {
  CameraConfig c;
  c.camera_matrix = {500.0, 0.0, 321.0, 0.0, fy, 236.0, 0.0, 0.0, 1.0};
  return c;
}

gc::Pose pose(double pan_deg, double tilt_deg, double swing_deg, double y_m = 0.2) {
  gc::Pose p = gc::default_pose();
  p.pan_rad = pan_deg * kDeg;
  p.tilt_rad = tilt_deg * kDeg;
  p.swing_rad = swing_deg * kDeg;
  p.y_m = y_m;
  return p;
}

CameraMount mount_of(const gc::Pose& p, double on_vehicle = 0.0) {
  return {p.tilt_rad, p.swing_rad, on_vehicle};
}

Eigen::Vector3d normalised(const CameraConfig& c, const Eigen::Vector3d& px_h) {
  return {(px_h.x() - c.cx() * px_h.z()) / c.fx(), (px_h.y() - c.cy() * px_h.z()) / c.fy(),
          px_h.z()};
}

TEST(Vanishing, PredictedPointsEqualTheTruth) {
  const CameraConfig cam = camera();
  for (double pan : {-30.0, -8.0, -0.5, 3.0, 17.0}) {
    for (double tilt : {20.0, 35.0, 50.0}) {
      for (double swing : {-4.0, 0.0, 2.5}) {
        const gc::Pose p = pose(pan, tilt, swing);
        const gc::FrameTruth t = gc::truth_for(cam, gc::default_corridor(), p);
        const ImagePoint a = axis_vanishing_point(cam, p.pan_rad, mount_of(p));
        const ImagePoint c = cross_vanishing_point(cam, p.pan_rad, mount_of(p));
        ASSERT_TRUE(a.finite && t.axis.finite);
        EXPECT_NEAR(a.px.x(), t.axis.u_px, 1e-7);
        EXPECT_NEAR(a.px.y(), t.axis.v_px, 1e-7);
        ASSERT_TRUE(c.finite && t.cross.finite);
        EXPECT_NEAR(c.px.x(), t.cross.u_px, 1e-6 * (1.0 + std::abs(t.cross.u_px)));
        EXPECT_NEAR(c.px.y(), t.cross.v_px, 1e-6 * (1.0 + std::abs(t.cross.v_px)));
      }
    }
  }
  // phi = 0: the cross point is at infinity, along the horizon.
  const gc::Pose p = pose(0.0, 35.0, 2.0);
  const ImagePoint c = cross_vanishing_point(cam, 0.0, mount_of(p));
  EXPECT_FALSE(c.finite);
  const ImagePoint a1 = axis_vanishing_point(cam, 0.1, mount_of(p));
  const ImagePoint a2 = axis_vanishing_point(cam, -0.1, mount_of(p));
  const Eigen::Vector2d horizon = (a1.px - a2.px).normalized();
  EXPECT_NEAR(std::abs(horizon.dot(c.direction)), 1.0, 1e-9);
}

TEST(Vanishing, PanFromEitherPointInvertsEq10And11) {
  const CameraConfig cam = camera();
  for (double pan : {-60.0, -12.0, 0.0, 0.3, 9.0, 44.0}) {
    for (double swing : {-3.0, 0.0, 3.0}) {
      const gc::Pose p = pose(pan, 33.0, swing);
      const gc::FrameTruth t = gc::truth_for(cam, gc::default_corridor(), p);
      const Direction a = axis_pan_of(normalised(cam, t.axis.homogeneous), mount_of(p));
      EXPECT_NEAR(a.pan_rad, p.pan_rad, 1e-9);
      EXPECT_NEAR(a.elevation_rad, 0.0, 1e-9);
      const Direction c = cross_pan_of(normalised(cam, t.cross.homogeneous), mount_of(p));
      EXPECT_NEAR(c.pan_rad, p.pan_rad, 1e-9);
      EXPECT_NEAR(c.elevation_rad, 0.0, 1e-9);
      // The vertical point is 90 deg off the horizon.
      const Direction v = axis_pan_of(normalised(cam, t.vertical.homogeneous), mount_of(p));
      EXPECT_NEAR(std::abs(v.elevation_rad), 0.5 * std::numbers::pi, 1e-9);
    }
  }
  // The single-point pan, written out (header): tan phi = cos theta (cos psi
  // x - sin psi y) for the axis point's normalised (x, y).
  const gc::Pose p = pose(7.0, 40.0, 2.0);
  const gc::FrameTruth t = gc::truth_for(cam, gc::default_corridor(), p);
  const double x = (t.axis.u_px - cam.cx()) / cam.fx(), y = (t.axis.v_px - cam.cy()) / cam.fy();
  EXPECT_NEAR(
      std::atan(std::cos(p.tilt_rad) * (std::cos(p.swing_rad) * x - std::sin(p.swing_rad) * y)),
      p.pan_rad, 1e-12);
}

TEST(Vanishing, VanishingLineRootsAndBranch) {
  const CameraConfig cam = camera(500.0);
  for (double pan : {-40.0, -10.0, -1.0, 0.0, 2.0, 25.0}) {
    for (double swing : {-3.0, 0.0, 1.5}) {
      const gc::Pose p = pose(pan, 30.0, swing);
      const gc::FrameTruth t = gc::truth_for(cam, gc::default_corridor(), p);
      const Eigen::Vector3d a = normalised(cam, t.axis.homogeneous);
      const Eigen::Vector3d c = normalised(cam, t.cross.homogeneous);
      const VanishingLinePan near = pan_from_vanishing_line(a, c, mount_of(p), p.pan_rad);
      EXPECT_FALSE(near.clamped);
      EXPECT_NEAR(near.chosen, p.pan_rad, 1e-9) << pan;
      EXPECT_NEAR(near.roots[0], p.pan_rad, 1e-9);
      // The other root: +-90 deg - phi (tan phi2 = cot phi).
      const double other = (p.pan_rad >= 0.0 ? 0.5 : -0.5) * std::numbers::pi - p.pan_rad;
      if (pan != 0.0) {
        EXPECT_NEAR(near.roots[1], other, 1e-9);
        const VanishingLinePan far = pan_from_vanishing_line(a, c, mount_of(p), other + 0.05);
        EXPECT_NEAR(far.chosen, other, 1e-9);
      }
      if (pan != 0.0 && std::abs(pan) < 45.0) {
        // eq. 14 written out on the pixel vector d = p_axis - p_cross with
        // c1 = f cos psi / cos theta (fx = fy = f): tan phi = (m / c1 -+
        // sqrt(m^2 / c1^2 - 4)) / 2, the small root with the sign of m.
        const double m = t.axis.u_px - t.cross.u_px;
        const double c1 = cam.fx() * std::cos(p.swing_rad) / std::cos(p.tilt_rad);
        const double s = m / c1;
        const double tan_small = 0.5 * (s - std::copysign(std::sqrt(s * s - 4.0), s));
        EXPECT_NEAR(std::atan(tan_small), p.pan_rad, 1e-9);
        // The seed's eq. 12 is p_cross - p_axis (errata): its m gives -phi.
        const double seed_s = -s;
        EXPECT_NEAR(std::atan(0.5 * (seed_s - std::copysign(std::sqrt(s * s - 4.0), seed_s))),
                    -p.pan_rad, 1e-9);
      }
    }
  }
  // |s| < 2 (points too close for any pan): clamped to 45 deg.
  const CameraMount m{30.0 * kDeg, 0.0, 0.0};
  const VanishingLinePan cl = pan_from_vanishing_line({0.2, 0.5, 1.0}, {-0.5, 0.5, 1.0}, m, 0.0);
  EXPECT_TRUE(cl.clamped);
  EXPECT_NEAR(cl.roots[0], 45.0 * kDeg, 1e-12);
}

TEST(Vanishing, HeadingIsEq16) {
  const CameraMount m{0.6, 0.01, 4.0 * kDeg};
  EXPECT_DOUBLE_EQ(vehicle_heading(10.0 * kDeg, m), 6.0 * kDeg);
}

// The truth's visible axis lines (and lines across the ceiling: the seams
// across at x = 0.3 + 0.6 k, projected), optionally with noise on theta and
// on the line's offset.
std::vector<ImageLine> axis_lines(const CameraConfig& cam, const gc::Pose& p) {
  std::vector<ImageLine> out;
  for (const gc::ImageLine& l : gc::truth_for(cam, gc::default_corridor(), p).lines) {
    if (l.visible && (l.to_px - l.from_px).norm() > 40.0) {
      out.push_back({l.theta_rad, l.rho_px, (l.to_px - l.from_px).norm()});
    }
  }
  return out;
}

// The image line of the world segment a-b seen from p, its strength the
// segment's image length; nullopt when an end is behind the camera.
std::optional<ImageLine> image_of_segment(const CameraConfig& cam, const gc::Pose& p,
                                          const Eigen::Vector3d& a_w, const Eigen::Vector3d& b_w) {
  const Eigen::Matrix3d r = golden::world_to_camera_rotation(p.pan_rad, p.tilt_rad, p.swing_rad);
  const Eigen::Vector3d centre(p.x_m, p.y_m, p.height_m);
  Eigen::Matrix3d k;
  k << cam.fx(), 0.0, cam.cx(), 0.0, cam.fy(), cam.cy(), 0.0, 0.0, 1.0;
  const Eigen::Vector3d a = k * r * (a_w - centre);
  const Eigen::Vector3d b = k * r * (b_w - centre);
  if (a.z() <= 0.0 || b.z() <= 0.0) return std::nullopt;
  const double len = (a.head<2>() / a.z() - b.head<2>() / b.z()).norm();
  return line_from_homogeneous(a.cross(b), len);
}

std::vector<ImageLine> cross_lines(const CameraConfig& cam, const gc::Pose& p) {
  std::vector<ImageLine> out;
  for (int i = 0; i < 8; ++i) {
    const double x = 0.3 + 0.6 * (i + 2);
    const std::optional<ImageLine> l = image_of_segment(cam, p, {x, 1.2, 2.8}, {x, -1.2, 2.8});
    if (l) out.push_back(*l);
  }
  return out;
}

ImageLine perturbed(const ImageLine& l, std::mt19937_64& rng, double theta_sigma_rad,
                    double rho_sigma_px) {
  std::normal_distribution<double> n(0.0, 1.0);
  // Rotate about the line's point nearest the image centre.
  const double c = std::cos(l.theta_rad), s = std::sin(l.theta_rad);
  const double d = 320.0 * c + 240.0 * s - l.rho_px;
  const Eigen::Vector2d q(320.0 - d * c, 240.0 - d * s);
  const double t = l.theta_rad + theta_sigma_rad * n(rng);
  ImageLine out = line_from_homogeneous(
      {std::cos(t), std::sin(t), -(q.x() * std::cos(t) + q.y() * std::sin(t))}, l.strength);
  out.rho_px += rho_sigma_px * n(rng);
  return out;
}

TEST(Vanishing, ExactLinesGiveTheExactPan) {
  const CameraConfig cam = camera(500.0);
  for (double pan : {-12.0, -3.0, 0.0, 5.0, 14.0}) {
    for (double swing : {-3.0, 0.0, 2.0}) {
      const gc::Pose p = pose(pan, 35.0, swing, -0.4 + 0.05 * pan);
      std::vector<ImageLine> lines = axis_lines(cam, p);
      PanEstimate e = estimate_pan(lines, cam, mount_of(p, 1.0 * kDeg), p.pan_rad + 3.0 * kDeg);
      EXPECT_EQ(e.status, PanStatus::one_point) << pan;  // no line across: one point
      EXPECT_NEAR(e.pan_rad, p.pan_rad, 1e-7);
      EXPECT_NEAR(e.heading_rad, p.pan_rad - 1.0 * kDeg, 1e-7);
      EXPECT_GE(e.axis.inliers.size(), 6u);
      EXPECT_LT(e.axis.residual_rad, 1e-9);
      EXPECT_NEAR(e.axis.support, 1.0, 1e-12);
      // With the lines across: both points, the vanishing line's pan too.
      if (std::abs(pan) >= 3.0) {
        for (const ImageLine& l : cross_lines(cam, p)) lines.push_back(l);
        VanishingParams vp;
        vp.min_axis_support = 0.3;
        e = estimate_pan(lines, cam, mount_of(p), p.pan_rad + 3.0 * kDeg, vp);
        EXPECT_EQ(e.status, PanStatus::ok) << pan;
        EXPECT_NEAR(e.line_pan_rad, p.pan_rad, 1e-7);
        EXPECT_NEAR(e.cross_pan_rad, p.pan_rad, 1e-7);
        EXPECT_NEAR(e.pan_rad, p.pan_rad, 1e-7);
        vp.source = PanSource::vanishing_line;
        e = estimate_pan(lines, cam, mount_of(p), p.pan_rad + 3.0 * kDeg, vp);
        EXPECT_EQ(e.pan_rad, e.line_pan_rad);
      }
    }
  }
}

TEST(Vanishing, StatusNotFound) {
  const CameraConfig cam = camera(500.0);
  const gc::Pose p = pose(5.0, 35.0, 0.0);
  const CameraMount m = mount_of(p);
  std::vector<ImageLine> lines = axis_lines(cam, p);
  // Too few lines.
  const std::vector<ImageLine> two(lines.begin(), lines.begin() + 2);
  EXPECT_EQ(estimate_pan(two, cam, m, p.pan_rad).status, PanStatus::not_found);
  EXPECT_EQ(estimate_pan({}, cam, m, p.pan_rad).status, PanStatus::not_found);
  // The prediction 15 deg off: the point is outside the window.
  EXPECT_EQ(estimate_pan(lines, cam, m, p.pan_rad + 15.0 * kDeg).status, PanStatus::not_found);
  // Every line through a point well off the horizon (5 deg above it).
  const ImagePoint off = axis_vanishing_point(cam, p.pan_rad, {p.tilt_rad - 5.0 * kDeg, 0.0, 0.0});
  std::vector<ImageLine> fan;
  for (int i = 0; i < 8; ++i) {
    const double t = (10.0 + 20.0 * i) * kDeg;
    fan.push_back({t, off.px.x() * std::cos(t) + off.px.y() * std::sin(t), 100.0});
  }
  EXPECT_EQ(estimate_pan(fan, cam, m, p.pan_rad).status, PanStatus::not_found);
  // Residual against the bound (3 px at f = 500): every line 4 px off the
  // point (alternating sides) passes, 7 px does not.
  const ImagePoint on = axis_vanishing_point(cam, p.pan_rad, m);
  std::vector<ImageLine> loose;
  for (int i = 0; i < 8; ++i) {
    const double t = (10.0 + 20.0 * i) * kDeg;
    loose.push_back(
        {t, on.px.x() * std::cos(t) + on.px.y() * std::sin(t) + (i % 2 ? 4.0 : -4.0), 100.0});
  }
  EXPECT_EQ(estimate_pan(loose, cam, m, p.pan_rad).status, PanStatus::one_point);     // 4 px: ok
  for (size_t i = 0; i < loose.size(); ++i) loose[i].rho_px += (i % 2 ? 3.0 : -3.0);  // 7 px
  EXPECT_EQ(estimate_pan(loose, cam, m, p.pan_rad).status, PanStatus::not_found);
  // Random lines: no point.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> th(0.0, std::numbers::pi), rh(-300.0, 700.0);
  int claimed = 0;
  for (int f = 0; f < 200; ++f) {
    std::vector<ImageLine> r;
    for (int i = 0; i < 8; ++i) r.push_back({th(rng), rh(rng), 100.0});
    if (estimate_pan(r, cam, m, 0.0).status != PanStatus::not_found) ++claimed;
  }
  EXPECT_EQ(claimed, 0);
}

// The axis point's strength share leaves out the lines through the vertical
// vanishing point (door jambs, corners: fixed by the tilt and swing alone).
// Four axis lines and four strong door jambs: found; the same four axis
// lines and four equally strong lines through a point off both directions:
// not found (they dilute the share below min_axis_support).
TEST(Vanishing, VerticalEdgesDoNotDiluteTheAxisSupport) {
  const CameraConfig cam = camera(500.0);
  const gc::Pose p = pose(8.0, 35.0, 0.0);
  const CameraMount m = mount_of(p);
  std::vector<ImageLine> axis = axis_lines(cam, p);
  ASSERT_GE(axis.size(), 4u);
  axis.resize(4);
  double axis_strength = 0.0;
  for (const ImageLine& l : axis) axis_strength += l.strength;
  // Door jambs: vertical segments on the left wall (y = 1.2) 2-6 m ahead.
  std::vector<ImageLine> jambs;
  for (int i = 0; i < 4; ++i) {
    const double x = 2.0 + 1.3 * i;
    std::optional<ImageLine> l = image_of_segment(cam, p, {x, 1.2, 0.5}, {x, 1.2, 2.0});
    ASSERT_TRUE(l.has_value());
    l->strength = axis_strength / 4.0;
    jambs.push_back(*l);
  }
  std::vector<ImageLine> with_jambs = axis;
  with_jambs.insert(with_jambs.end(), jambs.begin(), jambs.end());
  const PanEstimate e = estimate_pan(with_jambs, cam, m, p.pan_rad);
  EXPECT_NE(e.status, PanStatus::not_found);
  EXPECT_NEAR(e.pan_rad, p.pan_rad, 1e-6);
  EXPECT_EQ(e.axis.inliers.size(), 4u);
  EXPECT_NEAR(e.axis.support, 1.0, 1e-9);
  // The same jambs turned about their image midpoints by 20 deg: they no
  // longer pass through the vertical point and count against the axis.
  std::vector<ImageLine> with_others = axis;
  for (const ImageLine& j : jambs) {
    const Eigen::Vector2d mid =
        j.rho_px * Eigen::Vector2d(std::cos(j.theta_rad), std::sin(j.theta_rad));
    const double t = j.theta_rad + 20.0 * kDeg;
    with_others.push_back(line_from_homogeneous(
        {std::cos(t), std::sin(t), -(mid.x() * std::cos(t) + mid.y() * std::sin(t))}, j.strength));
  }
  EXPECT_EQ(estimate_pan(with_others, cam, m, p.pan_rad).status, PanStatus::not_found);
}

// The two estimates with the same line noise (theta 0.15 deg, rho 0.5 px on
// every line): the axis point alone is more accurate than the vanishing
// line (the cross point lies far out along the horizon, fixed by few
// nearly parallel lines).
TEST(Vanishing, AxisPointBeatsTheVanishingLineOnNoisyLines) {
  const CameraConfig cam = camera(500.0);
  std::mt19937_64 rng(11);
  double s_axis = 0.0, s_line = 0.0;
  int n = 0;
  VanishingParams vp;
  vp.min_axis_support = 0.3;
  for (int f = 0; f < 120; ++f) {
    const double pan = (f % 2 ? 1.0 : -1.0) * (4.0 + 0.09 * f);
    const gc::Pose p = pose(pan, 28.0 + 0.12 * f, -2.0 + 0.03 * f, -0.6 + 0.01 * f);
    std::vector<ImageLine> lines;
    for (const ImageLine& l : axis_lines(cam, p)) {
      lines.push_back(perturbed(l, rng, 0.15 * kDeg, 0.5));
    }
    for (const ImageLine& l : cross_lines(cam, p)) {
      lines.push_back(perturbed(l, rng, 0.15 * kDeg, 0.5));
    }
    const PanEstimate e = estimate_pan(lines, cam, mount_of(p), p.pan_rad + 1.0 * kDeg, vp);
    if (e.status != PanStatus::ok) continue;
    ++n;
    s_axis += std::pow((e.axis_pan_rad - p.pan_rad) / kDeg, 2);
    s_line += std::pow((e.line_pan_rad - p.pan_rad) / kDeg, 2);
  }
  const double rms_axis = std::sqrt(s_axis / n), rms_line = std::sqrt(s_line / n);
  std::printf(
      "noisy lines, %d frames with both points: axis point RMS %.3f deg, vanishing "
      "line RMS %.3f deg\n",
      n, rms_axis, rms_line);
  EXPECT_GE(n, 100);
  EXPECT_LT(rms_axis, rms_line);
}

}  // namespace
}  // namespace ceilnav::host::corridor
