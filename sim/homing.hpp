// Seed 004's homing in the loop (docs/homing.md, "Servoing", "Capture
// zone", "Triangle race"): a differential-drive robot (robot.hpp, with the
// navigation layer's drift model) under a structured ceiling (a ceiling
// file, golden/ceiling/ceiling_file.hpp). Every frame is rendered at the
// camera's true pose under the return lighting, its orientation histogram
// taken (the orientation block's, golden::orientation_histogram_fixed),
// the site tracked (host::homing::SiteTracker), turned into a
// HomingMeasurement and fed to nav::HomingServo, whose command reaches the
// wheels `latency_s` after the exposure. Between sites the robot follows
// the map's odometric paths on its wheel odometry alone.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "drivers/device.hpp"
#include "golden/ceiling/ceiling_file.hpp"
#include "golden/ceiling/render.hpp"
#include "host/homing/site_map.hpp"
#include "host/homing/tracker.hpp"
#include "nav/homing_servo.hpp"
#include "sim/robot.hpp"

namespace ceilnav::sim {

struct HomingSimParams {
  double frame_rate_hz = 10.0;
  double odometry_rate_hz = 50.0;
  // From a frame's exposure to its command at the wheels: the tracking
  // (<= 10 ms) and the host's cycle.
  double latency_s = 0.05;
  // The drift model: wheel radii 0.2 % and -0.3 % off (a heading drift of
  // 0.7 deg per metre), the default slip, tyre scrub in turns.
  RobotParams robot = [] {
    RobotParams r;
    r.left_scale = 1.002;
    r.right_scale = 0.997;
    r.scrub_sigma_sqrt_rad = 0.01;
    r.max_yaw_rate_rad_s = 1.0;
    return r;
  }();
  golden::ceiling::RenderParams render;  // noise 2 grey, blur 0.5 px
  host::homing::SiteOptions site;
  // The tracker: a match is the site from an NCC of 0.94 (real photos reach
  // 0.76 in the fast mode, a like grille elsewhere on the office ceiling
  // 0.84, site 1's patch turned 180 deg beside it 0.92; the site itself
  // scores 0.97-0.999 on the study ceilings).
  host::homing::TrackerOptions tracker = [] {
    host::homing::TrackerOptions t;
    t.min_score = 0.94;
    // The coarse level's gate stays at 0.6 (the tracker's default 0.7 -
    // 0.15 was 0.55): a site at the frame's edge scores 0.7-0.8 there.
    t.coarse_margin = 0.3;
    return t;
  }();
  nav::HomingServoParams servo;  // the camera offset is the world's
  // The first frame of a homing searches within acquire_radius_m (on the
  // ceiling) of where the site point would be if the odometry were right;
  // then each frame within track_radius_px of the last match, in the fast
  // mode (three templates about the last gamma).
  double acquire_radius_m = 1.5;
  double track_radius_px = 40.0;
  // Before the first match the robot turns in place at search_yaw_rate_rad_s
  // (the frame's long side sweeps round it, and the camera's look offset
  // comes closer to a site behind): the homing is not_found when a whole
  // turn brought no match. Once acquired it is lost after max_lost_frames
  // consecutive frames without an `ok` match in which the odometry's
  // prediction puts the site well inside the frame (frames that put it
  // out of view, while the robot turns toward it, do not count, for up to
  // max_bridge_m of motion since the last match), or after max_time_s. It
  // succeeds when the servo is done on settle_frames consecutive frames
  // with the robot at rest.
  int max_lost_frames = 10;
  double search_yaw_rate_rad_s = 0.5;
  double max_bridge_m = 0.6;
  // A match must agree with the odometry: the robot's error toward the site
  // predicted from the last match and the wheel odometry since, within
  // consistency_position_m + 10 % of the motion and consistency_turn_rad +
  // 5 % of the turn; else it is dropped (counted as lost) and the site
  // searched for again: within 2.5 track_radius_px of the last good match
  // in the fast mode about the turn the odometry predicts, then over the
  // whole view.
  double consistency_position_m = 0.02;
  double consistency_turn_rad = 0.035;
  double max_time_s = 60.0;
  int settle_frames = 2;
  // Odometric paths: the turns' and the straight legs' speed.
  double path_speed_m_s = 0.4;
  double path_yaw_rate_rad_s = 0.8;
  uint64_t seed = 1;  // frame noise (the slip's: robot.seed)
  // The orientation histograms: nullopt, golden::orientation_histogram_fixed
  // of each frame (bit-equal to the device's); else each frame streams
  // through the homing device on this backend (drivers::Device, its
  // device_config set to regs::kConfigHoming; identity LUT, ORI_CONTROL
  // threshold 16) and the histogram is read from its registers.
  std::optional<drivers::DeviceOptions> device;
};
// Throws std::invalid_argument naming the first bad field.
void validate(const HomingSimParams& p);

// The camera model of the world: `intrinsics`' lens and image, the world's
// camera height and ceiling height.
host::CameraConfig homing_camera(const host::CameraConfig& intrinsics,
                                 const golden::ceiling::CeilingFile& world);

// Records every site of the world: the robot placed at the site's pose, one
// frame under the recording lighting; the map's paths join the sites in
// the file's order and back to the first (the triangle of the race).
host::homing::SiteMap record_sites(const golden::ceiling::CeilingFile& world,
                                   const host::CameraConfig& camera, const HomingSimParams& p);

enum class HomingOutcome {
  homed,      // the servo finished
  not_found,  // the site never matched in a whole turn (outside the capture zone)
  lost,       // matched, then lost for max_lost_frames (in view)
  timeout,
  unusable,  // the map marks the site unusable (SiteMap's MapSite::unusable)
};
const char* to_string(HomingOutcome o);

// One frame of a homing.
struct HomingFrame {
  double t_s = 0.0;
  nav::Pose2 robot;  // true, at the exposure
  host::homing::TrackStatus track = host::homing::TrackStatus::not_found;
  double score = 0.0;
  nav::HomingMeasurement measurement;
  nav::HomingError true_error;  // the robot's error toward the site's true pose
  nav::HomingCommand command;
  bool consistent = true;  // false: the match disagreed with the odometry (dropped)
  bool predicted = false;  // the command came from the odometry's prediction (no match)
};

struct HomingRun {
  HomingOutcome outcome = HomingOutcome::not_found;
  int frames = 0;
  double time_s = 0.0;
  // The robot's true error after the homing (wheel-axis midpoint to the
  // site's recorded pose, heading: site - robot), and before it.
  double position_error_m = 0.0, heading_error_rad = 0.0;
  double start_distance_m = 0.0, start_heading_error_rad = 0.0;
  double travelled_m = 0.0;
  int inconsistent_frames = 0;  // matches the odometry's check dropped
};

// Homes the robot on `site` of the map (its true pose: world.sites[site]).
// heading_prior_rad: the turn to the site's heading the odometry predicts
// (after an odometric path: 0, within its drift of a few degrees). With it
// the first frames search in the seed's fast mode about that turn (the
// quadrant known), and only without a match there the whole 360 deg; without
// it (the capture study: nothing known) the whole 360 deg.
HomingRun home(Robot& robot, const host::homing::SiteMap& map, int site,
               const golden::ceiling::CeilingFile& world, const host::CameraConfig& camera,
               const HomingSimParams& p,
               const std::function<void(const HomingFrame&)>& on_frame = {},
               std::optional<double> heading_prior_rad = std::nullopt);

// Follows an odometric path on the wheel odometry: turn, straight leg, turn.
// Returns the odometry's travelled distance.
double follow_path(Robot& robot, const host::homing::OdometricPath& path, const HomingSimParams& p);

// The capture zone (seed section 3.4): homings of `site` from starts at
// radius r and bearing b from the site (around it, in the world) with the
// robot's heading the site's plus h. A start succeeds when the robot homes
// within success_position_m and success_heading_rad of the true site pose.
struct CaptureStart {
  double radius_m = 0.0, bearing_rad = 0.0, heading_offset_rad = 0.0;
  HomingRun run;
  bool success = false;
};
struct CaptureZone {
  std::vector<CaptureStart> starts;
  // The largest radius at which and inside which every start succeeded
  // (0 when a start at the smallest radius failed).
  double radius_m = 0.0;
  int false_homings = 0;  // homed, but outside the success bounds
};
struct CaptureParams {
  std::vector<double> radii_m{0.5, 0.75, 1.0, 1.15, 1.3, 1.5};
  int bearings = 8;
  std::vector<double> heading_offsets_rad{0.0, 1.5708, 3.14159};
  double success_position_m = 0.005;
  double success_heading_rad = 0.0087;
};
CaptureZone capture_zone(const golden::ceiling::CeilingFile& world,
                         const host::CameraConfig& camera, const host::homing::SiteMap& map,
                         int site, const HomingSimParams& p, const CaptureParams& c,
                         const std::function<void(const CaptureStart&)>& on_start = {});

// The triangle race (seed section 4.3): from the first site, `loops` times
// round the map's paths (sites 1, 2, 3, 1, ...), homing at each site on
// arrival. with_homing false: the same paths on odometry alone (the drift
// the homing removes).
struct RaceLeg {
  int loop = 0, site = 0;
  // On arrival (the odometric path's error) and after the homing.
  double arrival_distance_m = 0.0, arrival_heading_error_rad = 0.0;
  HomingRun homing;  // outcome not_found and zeros without homing
};
struct RaceResult {
  std::vector<RaceLeg> legs;
  double position_rms_m = 0.0, position_max_m = 0.0;  // after the homings that homed
  double heading_rms_rad = 0.0, heading_max_rad = 0.0;
  double arrival_rms_m = 0.0;  // the odometric paths' error at arrival
  int homed = 0, failed = 0, false_homings = 0;
  double distance_m = 0.0, time_s = 0.0;
};
RaceResult run_race(const golden::ceiling::CeilingFile& world, const host::CameraConfig& camera,
                    const host::homing::SiteMap& map, const HomingSimParams& p, int loops,
                    bool with_homing = true, const std::function<void(const RaceLeg&)>& on_leg = {},
                    const std::function<void(const HomingFrame&)>& on_frame = {});

}  // namespace ceilnav::sim
