// Frames of a drive through the host: the tape truth of a course frame, the
// mount's yaw, a ceiling height zone, motion blur and pattern stations.
#include "sim/course_render.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "drivers/device.hpp"
#include "host/navigator.hpp"

namespace ceilnav::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

host::CameraConfig camera(double pitch_deg) {
  host::CameraConfig c;
  c.camera_matrix = {520.0, 0.0, 321.5, 0.0, 518.0, 238.0, 0.0, 0.0, 1.0};
  c.distortion_coefficients = {-0.08, 0.015, 0.0004, -0.0003, 0.0};
  c.camera_pitch_deg = pitch_deg;
  c.camera_height_m = 0.5;
  c.ceiling_height_m = 2.5;  // the default course's default ceiling
  c.tape_width_m = 0.05;
  return c;
}

DriveRenderParams drive_params() {
  DriveRenderParams p;
  p.render.tape_gain = 1200.0;
  p.render.noise_sigma_grey = 2.0;
  p.render.blur_sigma_px = 0.6;
  return p;
}

PoseAt still(const nav::Pose2& pose) {
  return [pose](double) { return pose; };
}

struct Measured {
  host::Status status;
  double yaw_rad, offset_m;
};

Measured measure(const host::CameraConfig& cam, const cv::Mat& frame) {
  host::Navigator nav(cam, drivers::make_device());
  const host::FrameOutcome r = nav.process(frame);
  return {r.pose.status, r.pose.yaw_rad, r.pose.offset_m};
}

TEST(TapeTruth, FindsTheTapeInViewAndTheCamerasPoseToIt) {
  const Course course = default_course();
  const host::CameraConfig cam = camera(45.0);
  CameraMount mount;
  mount.forward_m = 0.1;
  // On C (x = 20, pointing +Y), heading up it, 0.1 m right of it.
  const TapeTruth t = tape_truth(cam, course, camera_pose(cam, mount, {20.1, 5.0, 92.0 * kDeg}));
  EXPECT_TRUE(t.in_view);
  EXPECT_EQ(t.tape, 2);
  EXPECT_EQ(t.segment, 0);
  EXPECT_NEAR(t.tape_heading_rad, 90.0 * kDeg, 1e-12);
  EXPECT_NEAR(t.yaw_rad, 2.0 * kDeg, 1e-12);
  EXPECT_NEAR(t.offset_m, -(0.1 - 0.1 * std::sin(2.0 * kDeg)), 1e-12);
  EXPECT_NEAR(t.ceiling_above_camera_m, 2.0, 1e-12);
  // Heading down C: the tape is taken the other way, the camera is left of it.
  const TapeTruth back = tape_truth(cam, course, camera_pose(cam, {}, {20.1, 15.0, -90.0 * kDeg}));
  EXPECT_EQ(back.tape, 2);
  EXPECT_NEAR(back.tape_heading_rad, -90.0 * kDeg, 1e-12);
  EXPECT_NEAR(back.offset_m, 0.1, 1e-12);
  // Looking into the 2.8 m zone from A.
  const TapeTruth zone = tape_truth(cam, course, camera_pose(cam, {}, {30.0, 0.05, 0.0}));
  EXPECT_EQ(zone.tape, 0);
  EXPECT_NEAR(zone.ceiling_above_camera_m, 2.3, 1e-12);
  EXPECT_NEAR(zone.look_point.x_m, 32.3, 1e-9);
  // Looking away from every tape: nothing in view.
  const TapeTruth none = tape_truth(cam, course, camera_pose(cam, {}, {10.0, 10.0, 0.0}));
  EXPECT_FALSE(none.in_view);
}

// Documented accuracy of the host on a drive frame (docs/navigation.md):
// yaw within 0.1 deg and offset within 3 mm of tape_truth, still camera.
constexpr double kYawTolerance = 0.1 * kDeg;
constexpr double kOffsetTolerance = 0.003;

TEST(DriveFrame, HostTapePoseEqualsTheTruthOfTheTapeInView) {
  const Course course = default_course();
  struct Case {
    double pitch_deg;
    nav::Pose2 robot;
  };
  int checked = 0;
  for (const Case& c :
       {Case{45.0, {3.0, 0.12, -4.0 * kDeg}}, Case{45.0, {20.1, 3.0, 93.0 * kDeg}},
        Case{30.0, {34.0, 19.85, 178.0 * kDeg}}, Case{90.0, {12.0, -0.1, 5.0 * kDeg}},
        Case{60.0, {0.08, 14.0, -88.0 * kDeg}}}) {
    const host::CameraConfig cam = camera(c.pitch_deg);
    CameraMount mount;
    mount.forward_m = 0.15;
    mount.left_m = 0.02;
    const cv::Mat frame =
        render_drive_frame(cam, course, mount, still(c.robot), 0.0, 0.0, drive_params());
    const TapeTruth truth = tape_truth(cam, course, camera_pose(cam, mount, c.robot));
    ASSERT_TRUE(truth.in_view);
    ASSERT_NEAR(truth.ceiling_above_camera_m, 2.0, 1e-12);  // outside the zone
    const Measured m = measure(cam, frame);
    ASSERT_EQ(m.status, host::Status::ok) << c.robot.x_m << " " << c.robot.y_m;
    std::printf(
        "pitch %2.0f at (%5.2f, %5.2f): yaw %+.4f deg (truth %+.4f), offset %+.4f m "
        "(truth %+.4f)\n",
        c.pitch_deg, c.robot.x_m, c.robot.y_m, m.yaw_rad / kDeg, truth.yaw_rad / kDeg, m.offset_m,
        truth.offset_m);
    EXPECT_NEAR(m.yaw_rad, truth.yaw_rad, kYawTolerance);
    EXPECT_NEAR(m.offset_m, truth.offset_m, kOffsetTolerance);
    ++checked;
  }
  EXPECT_EQ(checked, 5);
}

TEST(DriveFrame, MountYawShowsInTheMeasuredYaw) {
  const Course course = default_course();
  const host::CameraConfig cam = camera(45.0);
  const nav::Pose2 robot{4.0, 0.1, 1.0 * kDeg};
  CameraMount mount;
  const Measured straight =
      measure(cam, render_drive_frame(cam, course, mount, still(robot), 0.0, 0.0, drive_params()));
  mount.yaw_error_rad = 2.5 * kDeg;
  const Measured turned =
      measure(cam, render_drive_frame(cam, course, mount, still(robot), 0.0, 0.0, drive_params()));
  ASSERT_EQ(straight.status, host::Status::ok);
  ASSERT_EQ(turned.status, host::Status::ok);
  EXPECT_NEAR(straight.yaw_rad, 1.0 * kDeg, kYawTolerance);
  EXPECT_NEAR(turned.yaw_rad - straight.yaw_rad, 2.5 * kDeg, 0.05 * kDeg);
  EXPECT_NEAR(tape_truth(cam, course, camera_pose(cam, mount, robot)).yaw_rad, 3.5 * kDeg, 1e-12);
}

TEST(DriveFrame, AHigherCeilingZoneScalesTheMeasuredOffset) {
  // The host assumes the configured 2.5 m ceiling: under the 2.8 m zone a
  // lateral offset d reads d (2.5 - 0.5) / (2.8 - 0.5) (the seed's c = d/d').
  const Course course = default_course();
  const host::CameraConfig cam = camera(90.0);
  for (const double x : {12.0, 32.0}) {
    const nav::Pose2 robot{x, 0.2, 2.0 * kDeg};
    const cv::Mat frame =
        render_drive_frame(cam, course, {}, still(robot), 0.0, 0.0, drive_params());
    const TapeTruth truth = tape_truth(cam, course, camera_pose(cam, {}, robot));
    const Measured m = measure(cam, frame);
    ASSERT_EQ(m.status, host::Status::ok) << x;
    const double predicted = truth.offset_m * 2.0 / truth.ceiling_above_camera_m;
    std::printf("x %.0f: ceiling %.1f m above, offset %.4f m measured, %.4f predicted, %.4f true\n",
                x, truth.ceiling_above_camera_m, m.offset_m, predicted, truth.offset_m);
    EXPECT_NEAR(m.offset_m, predicted, kOffsetTolerance);
    EXPECT_NEAR(m.yaw_rad, truth.yaw_rad, kYawTolerance);
    if (x > 25.0) {
      EXPECT_NEAR(truth.ceiling_above_camera_m, 2.3, 1e-12);
      EXPECT_GT(truth.offset_m - m.offset_m, 0.02);  // the scale is seen
    }
  }
}

TEST(DriveFrame, RandomCoursesMeasureAsTheirTruth) {
  // Held-out courses: on each random course's cross branch (tape C), 0.1 m
  // right of it and 2 deg off its direction; the host's offset scaled by
  // the ceiling it does not know (configured 2.5 m).
  const host::CameraConfig cam = camera(45.0);
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const Course course = random_course(seed, 80.0 + 20.0 * static_cast<double>(seed));
    const Point2 &a = course.tapes[2].points[0], &b = course.tapes[2].points[1];
    const double dir = std::atan2(b.y_m - a.y_m, b.x_m - a.x_m);
    const nav::Pose2 robot{0.5 * (a.x_m + b.x_m) + 0.1 * std::sin(dir),
                           0.5 * (a.y_m + b.y_m) - 0.1 * std::cos(dir), dir + 2.0 * kDeg};
    const cv::Mat frame =
        render_drive_frame(cam, course, {}, still(robot), 0.0, 0.0, drive_params());
    const TapeTruth truth = tape_truth(cam, course, camera_pose(cam, {}, robot));
    ASSERT_TRUE(truth.in_view) << seed;
    EXPECT_EQ(truth.tape, 2) << seed;
    const Measured m = measure(cam, frame);
    ASSERT_EQ(m.status, host::Status::ok) << seed;
    EXPECT_NEAR(m.yaw_rad, truth.yaw_rad, kYawTolerance) << seed;
    EXPECT_NEAR(m.offset_m, truth.offset_m * 2.0 / truth.ceiling_above_camera_m, kOffsetTolerance)
        << seed;
  }
}

// Rows where a column profile crosses `level` going from `from` toward
// `to` (linear interpolation between pixels).
double crossing(const cv::Mat& image, int col, int from, int to, double level) {
  const int step = to > from ? 1 : -1;
  for (int j = from; j != to; j += step) {
    const double a = image.at<double>(j, col), b = image.at<double>(j + step, col);
    if ((a - level) * (b - level) <= 0.0 && a != b) return j + step * (level - a) / (b - a);
  }
  return std::nan("");
}

TEST(DriveFrame, MotionBlurSmearsAnEdgeByTheImageMotion) {
  // A zenith camera (no distortion) moving along +X at v under a 0.3 m strip
  // across X: image rows follow X, so each edge of the strip becomes a ramp
  // of L = v t_exp fy / h pixels (h = 2 m), rising 10 -> 90 % over 0.8 L.
  host::CameraConfig cam = camera(90.0);
  cam.distortion_coefficients = {};
  Course course;
  course.tapes.push_back({"cross", {{0.0, -3.0}, {0.0, 3.0}}, 0.3, 1.0, {}});
  course.ceiling_height_m = 2.5;
  DriveRenderParams p = drive_params();
  p.render.noise_sigma_grey = 0.0;
  p.render.blur_sigma_px = 0.0;
  p.render.background_grey = 0.0;
  const double v = 1.0, t_exp = 0.05;
  const PoseAt moving = [&](double t) { return nav::Pose2{-0.05 + v * t, 0.0, 0.0}; };
  for (const bool blur : {false, true}) {
    DriveFrameInfo info;
    const auto start = std::chrono::steady_clock::now();
    const cv::Mat img =
        render_drive_float(cam, course, {}, moving, 0.0, blur ? t_exp : 0.0, p, &info);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const int col = 320, centre = static_cast<int>(std::lround(cam.cy()));
    const double plateau = img.at<double>(centre, col);
    ASSERT_GT(plateau, 100.0);
    double widths = 0.0;
    for (const int to : {0, cam.image_height - 1}) {
      const double r10 = crossing(img, col, centre, to, 0.1 * plateau);
      const double r90 = crossing(img, col, centre, to, 0.9 * plateau);
      widths += std::abs(r10 - r90);
    }
    const double width = 0.5 * widths;
    const double smear = v * t_exp * cam.fy() / 2.0;
    std::printf("exposure %s: %d sub-exposures, motion %.2f px, edge 10-90 %% %.2f px (%.1f ms)\n",
                blur ? "50 ms" : "0", info.subexposures, info.motion_px, width, ms);
    if (blur) {
      EXPECT_NEAR(info.motion_px, smear, 0.01);
      EXPECT_EQ(info.subexposures, static_cast<int>(std::ceil(smear / p.max_step_px)));
      // A sharp edge over the pixel box reads up to 1.6 px between pixel
      // centres: that much slack.
      EXPECT_NEAR(width, 0.8 * smear, 1.0);
    } else {
      EXPECT_EQ(info.subexposures, 1);
      EXPECT_LT(width, 1.7);
    }
  }
}

TEST(DriveFrame, PatternStationsAreCompositedWhereInView) {
  const Course course = default_course();
  const PatternStation& station = course.patterns.at(0);
  host::CameraConfig cam = camera(90.0);
  const DriveRenderParams p = drive_params();
  // The camera right under the station, heading along it.
  const nav::Pose2 under{station.x_m, station.y_m, station.yaw_rad};
  DriveFrameInfo info;
  const cv::Mat frame = render_drive_frame(cam, course, {}, still(under), 0.0, 0.0, p, &info);
  EXPECT_GT(info.pattern_pixels, 10000);
  // The disc centre is at the image centre (distortion is zero there to
  // first order): the disc's grey; the panel's bars and plates are dark.
  const double disc = p.pattern_radiometry.observed_level(golden::pattern::PixelClass::pattern);
  EXPECT_NEAR(frame.at<uint8_t>(static_cast<int>(cam.cy()), static_cast<int>(cam.cx())), disc,
              10.0);
  // Far from the panel the frame is the tape scene's background.
  EXPECT_NEAR(frame.at<uint8_t>(5, 5), p.render.background_grey, 10.0);
  // Pixels composited equal the pattern renderer's own frame (before the
  // tape frame's blur and noise).
  const StationFrame sf = station_frame(course, station, p.pattern_geometry);
  const golden::CameraView view = camera_view(cam, {}, under);
  const golden::pattern::PatternView pv{sf.axes.transpose() * (view.centre - sf.origin),
                                        view.world_to_camera * sf.axes};
  golden::pattern::PatternRenderParams rp;
  rp.noise_sigma_grey = 0.0;
  rp.blur_sigma_px = 0.0;
  const cv::Mat alone = golden::pattern::render_pattern(cam, p.pattern_geometry,
                                                        p.pattern_radiometry, station.id, pv, rp);
  DriveRenderParams clean = p;
  clean.render.noise_sigma_grey = 0.0;
  clean.render.blur_sigma_px = 0.0;
  const cv::Mat composited = render_drive_frame(cam, course, {}, still(under), 0.0, 0.0, clean);
  const int j = static_cast<int>(cam.cy()) + 20, i = static_cast<int>(cam.cx()) + 100;
  EXPECT_EQ(composited.at<uint8_t>(j, i), alone.at<uint8_t>(j, i));
  // Out of view (10 m away) nothing is composited.
  render_drive_frame(cam, course, {}, still({station.x_m + 10.0, station.y_m, 0.0}), 0.0, 0.0, p,
                     &info);
  EXPECT_EQ(info.pattern_pixels, 0);
}

TEST(DriveFrame, LeavingOutStripsOutOfViewChangesNothing) {
  Course course = default_course();
  course.patterns.clear();
  const golden::CeilingScene strips = ceiling_scene(course);
  const DriveRenderParams p = drive_params();
  // Pitch 20: the horizon is in view (every strip kept); 45, 90: culled.
  for (const double pitch : {20.0, 45.0, 90.0}) {
    const host::CameraConfig cam = camera(pitch);
    for (const nav::Pose2& robot :
         {nav::Pose2{3.0, 0.1, 0.05}, nav::Pose2{24.0, 0.2, 0.3}, nav::Pose2{39.9, 17.0, 1.6}}) {
      const golden::CameraView view = camera_view(cam, {}, robot);
      const cv::Mat all = golden::render_radiance(cam, strips, view, p.render);
      const cv::Mat culled = course_radiance(cam, course, strips, view, p);
      EXPECT_EQ(cv::norm(all, culled, cv::NORM_INF), 0.0) << pitch << " " << robot.x_m;
      EXPECT_GT(cv::norm(all, cv::NORM_INF), 50.0);
    }
  }
}

TEST(PoseTrack, InterpolatesAndHolds) {
  PoseTrack track;
  track.add(0.0, {0.0, 0.0, 170.0 * kDeg});
  track.add(1.0, {1.0, 2.0, -170.0 * kDeg});
  const nav::Pose2 mid = track.at(0.5);
  EXPECT_NEAR(mid.x_m, 0.5, 1e-12);
  EXPECT_NEAR(mid.y_m, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(mid.yaw_rad), std::numbers::pi, 1e-12);  // the short way round
  EXPECT_EQ(track.at(-1.0).x_m, 0.0);
  EXPECT_EQ(track.at(5.0).x_m, 1.0);
  EXPECT_THROW(track.add(1.0, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::sim

namespace ceilnav::sim {
namespace {

TEST(FrameNoise, EachFrameItsOwnFieldOfTheRightSigmaReproducibly) {
  const auto field = [](uint64_t seed, int64_t frame) {
    cv::Mat m(240, 320, CV_64FC1, cv::Scalar(0.0));
    add_frame_noise(m, 2.0, seed, frame);
    return m;
  };
  const cv::Mat a = field(1, 0), b = field(1, 1), c = field(2, 0);
  EXPECT_EQ(cv::norm(a, field(1, 0), cv::NORM_INF), 0.0);  // reproducible
  cv::Scalar mean, sd;
  cv::meanStdDev(a, mean, sd);
  // 76,800 draws: the mean within 4 x 2/sqrt(n) = 0.029, the sd within 1 %.
  EXPECT_NEAR(mean[0], 0.0, 0.03);
  EXPECT_NEAR(sd[0], 2.0, 0.02);
  // Another frame, another seed: uncorrelated fields (|r| < 4 / sqrt(n)).
  for (const cv::Mat* o : {&b, &c}) {
    const double r = a.dot(*o) / (cv::norm(a) * cv::norm(*o));
    EXPECT_LT(std::abs(r), 0.015);
  }
  // Neighbouring pixels uncorrelated too.
  const double r1 = a.colRange(0, 319).dot(a.colRange(1, 320)) /
                    (cv::norm(a.colRange(0, 319)) * cv::norm(a.colRange(1, 320)));
  EXPECT_LT(std::abs(r1), 0.015);
  cv::Mat bad(2, 2, CV_8UC1);
  EXPECT_THROW(add_frame_noise(bad, 1.0, 1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::sim
