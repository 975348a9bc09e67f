// Seed 004's homing in the loop (sim/homing.hpp) on rendered frames of the
// built-in office ceiling: the look offset measured by turns in place at a
// site, a homing from an offset start, the capture at 1 m in the four
// directions, no homing under a ceiling without the site, and one loop of
// the triangle race meeting the goals (docs/homing.md).
#include "sim/homing.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/device.hpp"
#include "golden/ceiling/ceiling_file.hpp"

namespace ceilnav::sim {
namespace {

namespace gc = golden::ceiling;
constexpr double kDeg = std::numbers::pi / 180.0;

struct World {
  gc::CeilingFile world = gc::default_homing_world();
  host::CameraConfig camera = homing_camera(host::CameraConfig{}, world);
  HomingSimParams params;
  host::homing::SiteMap map = record_sites(world, camera, params);
};
const World& world() {
  static const World w;
  return w;
}

// The look point: the camera 0.1 m ahead of the axis, tilted 0.3 deg
// forward and 0.2 deg right, 3 m below the ceiling: (0.1 + 3 tan 0.3 deg,
// 3 tan -0.2 deg) = (115.7, -10.5) mm.
TEST(Homing, TurnsInPlaceMeasureTheLookOffset) {
  const World& w = world();
  const double d = w.world.ceiling.height_m - w.world.camera.height_m;
  const double forward = w.world.camera.forward_m + d * std::tan(w.world.camera.pitch_error_rad);
  const double left = w.world.camera.left_m + d * std::tan(w.world.camera.roll_error_rad);
  ASSERT_EQ(w.map.sites.size(), 3u);
  ASSERT_EQ(w.map.paths.size(), 3u);
  for (const host::homing::MapSite& s : w.map.sites) {
    EXPECT_NEAR(s.look_forward_m, forward, 0.001) << s.name;
    EXPECT_NEAR(s.look_left_m, left, 0.001) << s.name;
    EXPECT_LT(s.site.rotational_similarity, 0.5) << s.name;
  }
  EXPECT_EQ(w.map.paths[2].from, 2);
  EXPECT_EQ(w.map.paths[2].to, 0);
}

TEST(Homing, HomesFromAnOffsetStartInTheSeedsOrder) {
  const World& w = world();
  const gc::SitePose& s = w.world.sites[1];
  Robot robot(w.params.robot, {s.x_m + 0.3, s.y_m - 0.25, s.yaw_rad + 30.0 * kDeg});
  int switches_back = 0;
  nav::HomingPhase last = nav::HomingPhase::position;
  const HomingRun run =
      home(robot, w.map, 1, w.world, w.camera, w.params, [&](const HomingFrame& f) {
        switches_back +=
            f.command.phase == nav::HomingPhase::position && last != nav::HomingPhase::position;
        last = f.command.phase;
      });
  std::printf("homed in %d frames, %.1f s: %.2f mm, %.3f deg\n", run.frames, run.time_s,
              1e3 * run.position_error_m, run.heading_error_rad / kDeg);
  ASSERT_EQ(run.outcome, HomingOutcome::homed);
  EXPECT_LE(run.position_error_m, 0.003);
  EXPECT_LE(std::abs(run.heading_error_rad), 0.2 * kDeg);
  EXPECT_NEAR(run.start_distance_m, std::hypot(0.3, 0.25), 1e-9);
  EXPECT_LE(switches_back, 1);  // position, orientation, done (one resumption at most)
}

// The orientation histograms read from the homing device (the C++
// cycle-level model through its registers, random tvalid gaps and AXI
// stalls) are the golden's, bit for bit: the same homing, frame for frame.
TEST(Homing, TheDeviceModelGivesTheSameHoming) {
  const World& w = world();
  const gc::SitePose& s = w.world.sites[2];
  const nav::Pose2 start{s.x_m - 0.12, s.y_m + 0.1, s.yaw_rad - 8.0 * kDeg};
  HomingSimParams on_device = w.params;
  drivers::DeviceOptions model;
  model.backend = drivers::Backend::model;
  model.gap_probability = 0.1;
  model.backpressure_probability = 0.3;
  on_device.device = model;
  std::vector<HomingFrame> golden_frames, device_frames;
  Robot a(w.params.robot, start), b(w.params.robot, start);
  const HomingRun ga = home(a, w.map, 2, w.world, w.camera, w.params,
                            [&](const HomingFrame& f) { golden_frames.push_back(f); });
  const HomingRun gb = home(b, w.map, 2, w.world, w.camera, on_device,
                            [&](const HomingFrame& f) { device_frames.push_back(f); });
  ASSERT_EQ(ga.outcome, HomingOutcome::homed);
  EXPECT_EQ(gb.outcome, ga.outcome);
  ASSERT_EQ(device_frames.size(), golden_frames.size());
  for (std::size_t i = 0; i < golden_frames.size(); ++i) {
    EXPECT_EQ(device_frames[i].score, golden_frames[i].score) << i;
    EXPECT_EQ(device_frames[i].measurement.forward_m, golden_frames[i].measurement.forward_m) << i;
    EXPECT_EQ(device_frames[i].measurement.turn_rad, golden_frames[i].measurement.turn_rad) << i;
  }
  EXPECT_EQ(gb.position_error_m, ga.position_error_m);
  EXPECT_EQ(gb.heading_error_rad, ga.heading_error_rad);
}

TEST(Homing, CapturesFromOneMetreAllRound) {
  const World& w = world();
  CaptureParams c;
  c.radii_m = {1.0};
  c.bearings = 4;
  c.heading_offsets_rad = {0.0, 100.0 * kDeg};
  const CaptureZone zone = capture_zone(w.world, w.camera, w.map, 0, w.params, c);
  ASSERT_EQ(zone.starts.size(), 8u);
  for (const CaptureStart& s : zone.starts) {
    EXPECT_TRUE(s.success) << s.bearing_rad / kDeg << " " << s.heading_offset_rad / kDeg << ": "
                           << to_string(s.run.outcome) << " " << 1e3 * s.run.position_error_m;
  }
  EXPECT_EQ(zone.radius_m, 1.0);
  EXPECT_EQ(zone.false_homings, 0);
}

// Under a ceiling without the site (the hall ceiling) the site is never
// matched: not_found after the search turn, and the robot has not left its
// place (it only turned in place).
TEST(Homing, NoHomingWithoutTheSite) {
  const World& w = world();
  gc::CeilingFile other = w.world;
  other.ceiling = gc::hall_ceiling();
  other.ceiling.height_m = w.world.ceiling.height_m;
  for (int site = 0; site < 3; ++site) {
    const gc::SitePose& s = other.sites[static_cast<std::size_t>(site)];
    Robot robot(w.params.robot, {s.x_m, s.y_m, s.yaw_rad});
    const HomingRun run = home(robot, w.map, site, other, w.camera, w.params);
    EXPECT_EQ(run.outcome, HomingOutcome::not_found) << site;
    EXPECT_GE(run.frames, 120) << site;  // a whole turn at 0.5 rad/s and 10 Hz
    EXPECT_LT(std::hypot(robot.pose().x_m - s.x_m, robot.pose().y_m - s.y_m), 0.002);
  }
}

// The 2.6 m study ceiling's first site, a grille with a detector at the
// patch's edge: a robot put down 12 mm and 1.2 deg off it (a 7-loop race
// arrived so). The quarter-resolution peak lies two slats (26 px) from
// the site, and the grille turned by 180 deg, 0.17 m away, scores 0.993.
// With the odometry's heading the fast mode finds the site (a refinement
// window of 6 or 14 px refined a slat-shifted 0.83 and the 360 deg search
// then took the turned look-alike: the robot turned round and lost every
// site after); without it the search is `ambiguous` there, and the homing
// never ends on the look-alike.
TEST(Homing, AGrilleTurnedByHalfATurnIsNotTheSite) {
  const gc::CeilingFile world =
      gc::load_ceiling(std::string(CEILNAV_SOURCE_DIR) + "/examples/homing/study_low_2p6.yaml");
  const host::CameraConfig camera = homing_camera(host::CameraConfig{}, world);
  const HomingSimParams params;
  const host::homing::SiteMap map = record_sites(world, camera, params);
  const gc::SitePose& s = world.sites[0];
  const nav::Pose2 start{s.x_m + 0.00717, s.y_m + 0.01023, s.yaw_rad - 1.2441 * kDeg};
  Robot with_prior(params.robot, start);
  const HomingRun a = home(with_prior, map, 0, world, camera, params, {}, 0.0);
  ASSERT_EQ(a.outcome, HomingOutcome::homed);
  EXPECT_LE(a.position_error_m, 0.003);
  EXPECT_LE(std::abs(a.heading_error_rad), 0.2 * kDeg);
  Robot without(params.robot, start);
  const HomingRun b = home(without, map, 0, world, camera, params);
  std::printf("without a heading prior: %s, %.2f mm, %.3f deg\n", to_string(b.outcome),
              1e3 * b.position_error_m, b.heading_error_rad / kDeg);
  if (b.outcome == HomingOutcome::homed) {
    EXPECT_LE(b.position_error_m, 0.005);
    EXPECT_LE(std::abs(b.heading_error_rad), 0.5 * kDeg);
  }
}

TEST(Homing, OneLoopOfTheTriangleRaceMeetsTheGoals) {
  const World& w = world();
  const RaceResult odo = run_race(w.world, w.camera, w.map, w.params, 1, false);
  const RaceResult r = run_race(w.world, w.camera, w.map, w.params, 1, true);
  ASSERT_EQ(r.legs.size(), 3u);
  for (const RaceLeg& l : r.legs) {
    std::printf("site %d: arrival %.0f mm %.2f deg -> %s %.2f mm %.3f deg\n", l.site + 1,
                1e3 * l.arrival_distance_m, l.arrival_heading_error_rad / kDeg,
                to_string(l.homing.outcome), 1e3 * l.homing.position_error_m,
                l.homing.heading_error_rad / kDeg);
  }
  EXPECT_EQ(r.homed, 3);
  EXPECT_EQ(r.false_homings, 0);
  EXPECT_LE(r.position_rms_m, 0.003);
  EXPECT_LE(r.heading_rms_rad, 0.2 * kDeg);
  // The paths drift (the wheels' scale errors): arrivals centimetres off
  // with homing, and more without it once the drift accumulates.
  EXPECT_GT(r.arrival_rms_m, 0.01);
  EXPECT_GT(odo.legs.back().arrival_distance_m, 3.0 * r.legs.back().arrival_distance_m);
}

TEST(Homing, ParametersAreChecked) {
  HomingSimParams p;
  p.frame_rate_hz = 0.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = {};
  p.path_speed_m_s = 5.0;
  EXPECT_THROW(validate(p), std::invalid_argument);
  p = {};
  p.settle_frames = 0;
  EXPECT_THROW(validate(p), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::sim
