// The mount calibration drive: a camera roll and pitch error change the
// host's tape yaw and offset as derived (docs/navigation.md, "Mount
// calibration"), checked on the projected centre line and on rendered
// frames; a rendered drive recovers the mounting yaw within 0.05 deg, the
// roll and the pitch, and the estimates follow a changed truth.
#include "sim/calibration_drive.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "host/navigator.hpp"
#include "host/tape_pose.hpp"

namespace ceilnav::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The demo camera at 320 x 240 (as `ceilnav drive`), pitch 60 deg.
host::CameraConfig camera_320() {
  host::CameraConfig c = golden::default_camera();
  c.image_width = 320;
  c.image_height = 240;
  c.camera_matrix = {260.0, 0.0, 160.85, 0.0, 259.25, 119.35, 0.0, 0.0, 1.0};
  c.camera_pitch_deg = 60.0;
  c.camera_height_m = 0.3;
  c.ceiling_height_m = 2.5;
  return c;
}

// The first-order change of the host's (yaw, offset) for a camera of yaw psi
// relative to the tape at offset o: roll phi, pitch error delta, configured
// pitch p, ceiling h above the camera.
struct Bias {
  double yaw, offset;
};
Bias predicted_bias(double psi, double o, double phi, double delta, double p, double h) {
  return {phi * std::sin(p) + o / h * delta,
          -phi * h * std::cos(p) * std::cos(psi) - delta * h * std::sin(psi)};
}

// The host's (yaw, offset) for the centre line a camera of the given mount
// sees, projected exactly (two points of the tape through camera_pose).
Bias projected(const host::CameraConfig& cam, const CameraMount& mount, const nav::Pose2& robot) {
  const CameraWorldPose pose = camera_pose(cam, mount, robot);
  const double ceiling = cam.ceiling_height_m;
  Eigen::Vector3d a =
      pose.world_to_camera * (Eigen::Vector3d(robot.x_m + 1.0, 0.0, ceiling) - pose.centre);
  Eigen::Vector3d b =
      pose.world_to_camera * (Eigen::Vector3d(robot.x_m + 3.0, 0.0, ceiling) - pose.centre);
  a /= a.z();
  b /= b.z();
  Eigen::Vector3d line = a.cross(b);
  line /= std::hypot(line.x(), line.y());
  double yaw = 0.0, offset = 0.0;
  EXPECT_EQ(
      host::pose_from_centre_line(line, cam.camera_pitch_deg * kDeg,
                                  cam.ceiling_height_m - cam.camera_height_m, 1.4, yaw, offset),
      host::Status::ok);
  return {yaw, offset};
}

TEST(MountSensitivity, RollAndPitchChangeTheTapePoseAsDerived) {
  const host::CameraConfig cam = camera_320();
  const double p = cam.camera_pitch_deg * kDeg, h = cam.ceiling_height_m - cam.camera_height_m;
  int checked = 0;
  for (const double psi : {-4.0 * kDeg, 0.0, 4.0 * kDeg}) {
    for (const double y : {-0.1, 0.0, 0.08}) {
      const nav::Pose2 robot{0.0, y, psi};
      const Bias base = projected(cam, {}, robot);
      EXPECT_NEAR(base.yaw, psi, 1e-9);
      EXPECT_NEAR(base.offset, y, 1e-9);
      for (const auto& [phi, delta] : {std::pair{0.5 * kDeg, 0.0}, std::pair{0.0, 1.0 * kDeg},
                                       std::pair{-0.5 * kDeg, -1.0 * kDeg}}) {
        CameraMount m;
        m.roll_error_rad = phi;
        m.pitch_error_rad = delta;
        const Bias got = projected(cam, m, robot);
        const Bias want = predicted_bias(psi, y, phi, delta, p, h);
        // Second order: products of the angles (1.5e-4 rad^2) times h.
        EXPECT_NEAR(got.yaw - base.yaw, want.yaw, 4e-5);
        EXPECT_NEAR(got.offset - base.offset, want.offset, 4e-4);
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 27);
}

TEST(MountSensitivity, RenderedFramesShowTheDerivedBias) {
  const host::CameraConfig cam = camera_320();
  const double p = cam.camera_pitch_deg * kDeg, h = cam.ceiling_height_m - cam.camera_height_m;
  const Course course = calibration_course(4.0);
  DriveRenderParams params;
  params.render = golden::default_render_params();
  auto measure = [&](const CameraMount& m, const nav::Pose2& robot) {
    host::Navigator nav(cam, drivers::make_device());
    const cv::Mat frame = render_drive_frame(
        cam, course, m, [robot](double) { return robot; }, 0.0, 0.0, params);
    const host::FrameOutcome out = nav.process(frame);
    EXPECT_EQ(out.pose.status, host::Status::ok);
    return Bias{out.pose.yaw_rad, out.pose.offset_m};
  };
  for (const nav::Pose2 robot :
       {nav::Pose2{0.0, 0.05, 4.0 * kDeg}, nav::Pose2{0.0, -0.03, -4.0 * kDeg}}) {
    const Bias base = measure({}, robot);
    for (const auto& [phi, delta] : {std::pair{1.0 * kDeg, 0.0}, std::pair{0.0, 2.0 * kDeg}}) {
      CameraMount m;
      m.roll_error_rad = phi;
      m.pitch_error_rad = delta;
      const Bias got = measure(m, robot);
      const Bias want = predicted_bias(robot.yaw_rad, robot.y_m, phi, delta, p, h);
      std::printf(
          "roll %.1f pitch %.1f: yaw %+.4f deg (predicted %+.4f), offset %+.2f mm (%+.2f)\n",
          phi / kDeg, delta / kDeg, (got.yaw - base.yaw) / kDeg, want.yaw / kDeg,
          1e3 * (got.offset - base.offset), 1e3 * want.offset);
      EXPECT_NEAR(got.yaw - base.yaw, want.yaw, 0.01 * kDeg);
      EXPECT_NEAR(got.offset - base.offset, want.offset, 0.5e-3);
    }
  }
}

CalibrationDriveConfig drive_config(uint64_t seed) {
  CalibrationDriveConfig c;
  c.camera = camera_320();
  c.render.render = golden::default_render_params();
  c.render.render.noise_seed = seed;
  c.robot.seed = seed;
  c.robot.left_scale = 1.0 + 0.0015 * std::sin(1.7 * static_cast<double>(seed));
  c.robot.right_scale = 1.0 + 0.0015 * std::cos(2.3 * static_cast<double>(seed));
  c.mount.forward_m = c.drawing_forward_m = 0.1;
  c.mount.left_m = c.drawing_left_m = 0.02;
  c.mount.yaw_error_rad = 0.8 * kDeg;
  c.mount.roll_error_rad = 0.5 * kDeg;
  c.mount.pitch_error_rad = 1.0 * kDeg;
  c.course.start = {0.0, 0.03, -1.5 * kDeg};
  return c;
}

void print(uint64_t seed, const CalibrationDriveResult& r) {
  const auto& c = r.calibration;
  const auto& e = r.errors;
  std::printf(
      "seed %llu: %zu+%zu samples of %zu frames, %.1f s wall; max |heading| %.2f deg; "
      "effective yaw %+.4f deg (truth %+.4f), lateral %.2f mm (%.2f), scale %.4f, rms %.3f mm; "
      "yaw %+.4f (sigma %.4f), roll %+.4f (%.4f), pitch %+.4f (%.4f) deg\n",
      static_cast<unsigned long long>(seed), r.runs[0].samples.size(), r.runs[1].samples.size(),
      r.frames.size(), r.wall_time_s, r.max_abs_true_heading_rad / kDeg, c.yaw_rad / kDeg,
      r.true_effective_yaw_rad / kDeg, 1e3 * c.lateral_m, 1e3 * r.true_effective_lateral_m,
      c.offset_scale, 1e3 * c.rms_residual_m, e.yaw_rad / kDeg,
      std::sqrt(e.covariance(0, 0)) / kDeg, e.roll_rad / kDeg, std::sqrt(e.covariance(1, 1)) / kDeg,
      e.pitch_rad / kDeg, std::sqrt(e.covariance(2, 2)) / kDeg);
}

// Achievable (docs/navigation.md, "Mount calibration", Monte Carlo over
// seeds): the mounting yaw within the goal, the roll and the pitch within
// what the second-order terms and the host's own bias leave.
constexpr double kYawGoal = 0.05 * kDeg, kRollBound = 0.05 * kDeg, kPitchBound = 0.15 * kDeg;

void expect_recovered(const CalibrationDriveConfig& cfg, const CalibrationDriveResult& r) {
  ASSERT_TRUE(r.calibration.ok);
  EXPECT_GT(r.runs[0].samples.size(), 200u);
  EXPECT_GT(r.runs[1].samples.size(), 200u);
  // The heading was held at +-4 deg relative to the tape, give or take the
  // mount's effective yaw (the robot steers on the camera's yaw).
  EXPECT_LT(r.max_abs_true_heading_rad,
            4.0 * kDeg + std::abs(r.true_effective_yaw_rad) + 1.0 * kDeg);
  EXPECT_NEAR(r.calibration.yaw_rad, r.true_effective_yaw_rad, kYawGoal);
  EXPECT_NEAR(r.calibration.offset_scale, 1.0, 0.01);
  EXPECT_NEAR(r.errors.yaw_rad, cfg.mount.yaw_error_rad, kYawGoal);
  EXPECT_NEAR(r.errors.roll_rad, cfg.mount.roll_error_rad, kRollBound);
  EXPECT_NEAR(r.errors.pitch_rad, cfg.mount.pitch_error_rad, kPitchBound);
}

TEST(CalibrationDrive, RecoversTheMountingYawRollAndPitch) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    const CalibrationDriveConfig cfg = drive_config(seed);
    const CalibrationDriveResult r = calibration_drive(cfg);
    print(seed, r);
    expect_recovered(cfg, r);
  }
}

// The estimates follow the truth: a mount without errors, and one with every
// error's sign flipped, are recovered as well (a calibration that returned
// a constant would fail one of the three).
TEST(CalibrationDrive, EstimatesFollowAChangedTruth) {
  CalibrationDriveConfig zero = drive_config(4);
  zero.mount.yaw_error_rad = zero.mount.roll_error_rad = zero.mount.pitch_error_rad = 0.0;
  const CalibrationDriveResult rz = calibration_drive(zero);
  print(4, rz);
  expect_recovered(zero, rz);
  CalibrationDriveConfig flipped = drive_config(5);
  flipped.mount.yaw_error_rad = -0.6 * kDeg;
  flipped.mount.roll_error_rad = -0.5 * kDeg;
  flipped.mount.pitch_error_rad = -1.0 * kDeg;
  const CalibrationDriveResult rf = calibration_drive(flipped);
  print(5, rf);
  expect_recovered(flipped, rf);
  EXPECT_LT(rf.errors.yaw_rad, -0.5 * kDeg);
  EXPECT_LT(rf.errors.roll_rad, -0.4 * kDeg);
  EXPECT_LT(rf.errors.pitch_rad, -0.8 * kDeg);
}

TEST(CalibrationDrive, BadConfigurationsAreRejected) {
  CalibrationDriveConfig c = drive_config(1);
  c.run_length_m = 0.2;
  EXPECT_THROW(calibration_drive(c), std::invalid_argument);
  c = drive_config(1);
  c.course = calibration_course(1.0);  // too short for a 4 m run
  EXPECT_THROW(calibration_drive(c), std::invalid_argument);
  c = drive_config(1);
  c.exposure_s = 0.1;
  EXPECT_THROW(calibration_drive(c), std::invalid_argument);
  // The tape out of view at the start: no heading reference.
  c = drive_config(1);
  c.course.start = {0.0, 5.0, 0.0};
  EXPECT_THROW(calibration_drive(c), std::runtime_error);
}

}  // namespace
}  // namespace ceilnav::sim
