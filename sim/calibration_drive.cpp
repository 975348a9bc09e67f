#include "sim/calibration_drive.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace ceilnav::sim {
namespace {

enum class Phase { standstill, run, stop, turn, done };

// Odometry travel and heading at the ticks, interpolated linearly.
struct OdometryLog {
  std::vector<double> t, distance, yaw;
  double interpolate(const std::vector<double>& v, double ts) const {
    if (ts <= t.front()) return v.front();
    if (ts >= t.back()) return v.back();
    const auto i = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), ts) - t.begin());
    const double u = (ts - t[i - 1]) / (t[i] - t[i - 1]);
    return v[i - 1] + u * (v[i] - v[i - 1]);
  }
  double distance_at(double ts) const { return interpolate(distance, ts); }
  double yaw_at(double ts) const { return interpolate(yaw, ts); }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

Course calibration_course(double run_length_m, double ceiling_height_m) {
  Course c;
  c.name = "calibration";
  TapePolyline t;
  t.name = "calibration tape";
  t.points = {{-3.0, 0.0}, {run_length_m + 3.0, 0.0}};
  c.tapes.push_back(t);
  c.ceiling_height_m = ceiling_height_m;
  c.start = {0.0, 0.0, 0.0};
  validate(c);
  return c;
}

CalibrationDriveResult calibration_drive(const CalibrationDriveConfig& config) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (!(config.odometry_rate_hz > 0.0) || !(config.frame_rate_hz > 0.0) ||
      !(config.exposure_s >= 0.0) || config.exposure_s >= 1.0 / config.frame_rate_hz) {
    throw std::invalid_argument(
        "calibration drive: odometry and frame rates must be positive and the exposure shorter "
        "than a frame");
  }
  if (!(config.run_length_m >= 0.5) || !(config.speed_mps > 0.0) ||
      !(config.heading_rad > 0.0 && config.heading_rad < 0.3) || !(config.standstill_s > 0.0) ||
      !(config.heading_gain_per_s > 0.0)) {
    throw std::invalid_argument(
        "calibration drive: run length >= 0.5 m, speed > 0, heading in (0, 0.3) rad, standstill "
        "and heading gain > 0");
  }
  validate(config.course);
  const TapePolyline& tape = config.course.tapes.front();
  const double tape_dir =
      std::atan2(tape.points[1].y_m - tape.points[0].y_m, tape.points[1].x_m - tape.points[0].x_m);
  {
    const double dx = tape.points[1].x_m - tape.points[0].x_m,
                 dy = tape.points[1].y_m - tape.points[0].y_m;
    const double along = (config.course.start.x_m - tape.points[0].x_m) * std::cos(tape_dir) +
                         (config.course.start.y_m - tape.points[0].y_m) * std::sin(tape_dir);
    if (along < 1.0 || along + config.run_length_m + 1.0 > std::hypot(dx, dy)) {
      throw std::invalid_argument(
          "calibration drive: the course's first tape segment must reach 1 m behind the start "
          "and 1 m beyond the run");
    }
  }

  host::CameraConfig camera = config.camera;
  camera.ceiling_height_m = config.course.ceiling_height_m;
  camera.camera_height_m = config.camera_height_m;
  const double above = camera.ceiling_height_m - camera.camera_height_m;
  const double pitch = camera.camera_pitch_deg * std::numbers::pi / 180.0;
  host::Navigator navigator(camera, drivers::make_device(config.device), config.navigator);

  CalibrationDriveResult result;
  result.runs.resize(2);
  result.runs[1].turned_in_place = true;
  const double dt = 1.0 / config.odometry_rate_hz;
  Robot robot(config.robot, config.course.start, 0.0);
  PoseTrack track;
  track.add(0.0, robot.pose());
  OdometryLog log;
  log.t.push_back(0.0);
  log.distance.push_back(0.0);
  log.yaw.push_back(0.0);
  double odo_distance = 0.0;
  double odo_yaw = 0.0;  // the odometry's heading, unwrapped (interpolated between ticks)

  Phase phase = Phase::standstill;
  int run = 0;
  double phase_start_t = 0.0, run_start_distance = 0.0;
  double run_dir = 0.0;  // the tape's direction for this run, in the odometry's frame
  double turn_target = 0.0;
  int settled_ticks = 0;
  std::vector<double> standstill_yaws;
  int next_frame = 0;
  const double max_time = 10.0 * (2.0 * config.run_length_m / config.speed_mps + 20.0);
  double t = 0.0;

  auto expose = [&](int index) {
    const double t0 = index / config.frame_rate_hz;
    const double tm = t0 + 0.5 * config.exposure_s;
    const PoseAt pose_at = [&track](double ts) { return track.at(ts); };
    DriveRenderParams rp = config.render;
    rp.frame_index = index;  // each frame its own noise
    const cv::Mat frame =
        render_drive_frame(camera, config.course, config.mount, pose_at, t0, config.exposure_s, rp);
    const host::FrameOutcome out = navigator.process(frame);
    const host::TapePose& pose = host::navigation_pose(out);
    CalibrationFrame f;
    f.run = phase == Phase::run ? run : -1;
    f.t_s = tm;
    f.truth = track.at(tm);
    f.ok = pose.status == host::Status::ok;
    f.yaw_rad = pose.yaw_rad;
    f.offset_m = pose.offset_m;
    const TapeTruth truth =
        tape_truth(camera, config.course, camera_pose(camera, config.mount, f.truth));
    f.true_yaw_rad = truth.yaw_rad;
    f.true_offset_m = truth.offset_m;
    if (phase == Phase::run) {
      f.distance_m = std::max(0.0, log.distance_at(tm) - run_start_distance);
      if (f.ok) {
        result.runs[static_cast<std::size_t>(run)].samples.push_back(
            {f.distance_m, f.yaw_rad, f.offset_m});
        // The tape's direction in the odometry's frame, as this frame sees
        // it, low-passed into the one steered on: the odometry's heading
        // drift (wheel scale errors, slip) is taken out, the mount's yaw
        // (assumed_yaw_rad) is not.
        const double seen = log.yaw_at(tm) - (f.yaw_rad - config.assumed_yaw_rad);
        run_dir += config.tape_steering_gain * nav::wrap_angle(seen - run_dir);
      }
      const double heading =
          nav::wrap_angle(f.truth.yaw_rad - tape_dir - (run == 1 ? std::numbers::pi : 0.0));
      result.max_abs_true_heading_rad =
          std::max(result.max_abs_true_heading_rad, std::abs(heading));
    } else if (f.ok) {
      standstill_yaws.push_back(f.yaw_rad);
    }
    result.frames_ok += f.ok;
    result.frames.push_back(f);
  };

  while (phase != Phase::done) {
    if (t > max_time) throw std::runtime_error("calibration drive: out of time");
    double v = 0.0, omega = 0.0;
    const double since = t - phase_start_t;
    switch (phase) {
      case Phase::standstill:
        if (since >= config.standstill_s) {
          if (standstill_yaws.size() < 3) {
            throw std::runtime_error(
                "calibration drive: the tape is not in view at the start of a run");
          }
          // The heading relative to the tape, as the camera sees it (the
          // mount yaw taken as assumed_yaw_rad): the tape's direction in the
          // odometry's frame, held on odometry while driving.
          const double relative = median(standstill_yaws) - config.assumed_yaw_rad;
          run_dir = odo_yaw - relative;
          result.believed_start_heading_rad[run] = relative;
          result.true_start_heading_rad[run] = nav::wrap_angle(robot.pose().yaw_rad - tape_dir -
                                                               (run == 1 ? std::numbers::pi : 0.0));
          standstill_yaws.clear();
          phase = Phase::run;
          phase_start_t = t;
          run_start_distance = odo_distance;
        }
        break;
      case Phase::run: {
        const double s = odo_distance - run_start_distance;
        const double remaining = config.run_length_m - s;
        if (remaining <= 1e-3) {
          phase = Phase::stop;
          phase_start_t = t;
          break;
        }
        const double target =
            run_dir + (s < 0.5 * config.run_length_m ? config.heading_rad : -config.heading_rad);
        omega = config.heading_gain_per_s * nav::wrap_angle(target - odo_yaw);
        // Brake at 0.5 m/s^2 to stop at the run's end (no slower than 2 cm/s).
        v = std::min(config.speed_mps, std::max(0.02, std::sqrt(2.0 * 0.5 * remaining)));
        break;
      }
      case Phase::stop:
        if (since >= 0.3) {
          result.runs[static_cast<std::size_t>(run)].end_distance_m =
              odo_distance - run_start_distance;
          if (run == 1) {
            phase = Phase::done;
            break;
          }
          phase = Phase::turn;
          phase_start_t = t;
          turn_target = run_dir + std::numbers::pi;
          settled_ticks = 0;
        }
        break;
      case Phase::turn: {
        const double err = nav::wrap_angle(turn_target - odo_yaw);
        omega = std::clamp(config.heading_gain_per_s * err, -1.0, 1.0);
        settled_ticks = std::abs(err) < 1e-3 ? settled_ticks + 1 : 0;
        if (settled_ticks >= 20) {
          omega = 0.0;
          run = 1;
          phase = Phase::standstill;
          phase_start_t = t;
        }
        break;
      }
      case Phase::done:
        break;
    }
    if (phase == Phase::done) break;
    const nav::OdometryStep step = robot.step(dt, v, omega);
    t = robot.time_s();
    track.add(t, robot.pose());
    const nav::Motion m = nav::motion_of(step, config.robot.wheel_base_m);
    odo_distance += m.distance_m;
    log.t.push_back(t);
    log.distance.push_back(odo_distance);
    odo_yaw += m.dyaw_rad;
    log.yaw.push_back(odo_yaw);
    // Frames whose exposure has ended, while standing before a run or
    // driving one (none during the stop and the turn).
    while (next_frame / config.frame_rate_hz + config.exposure_s <= t + 1e-9) {
      if (phase == Phase::standstill || phase == Phase::run) expose(next_frame);
      ++next_frame;
    }
  }
  result.sim_time_s = t;

  nav::MountCalibrationOptions options;
  options.forward_m = config.drawing_forward_m;
  options.offset_sigma_m = 0.0;  // from the residuals
  options.fit_pitch = config.fit_pitch;
  options.ceiling_above_camera_m = above;
  result.calibration = nav::calibrate_mount(result.runs, options);
  if (result.calibration.ok) {
    result.errors = nav::split_mount(result.calibration, config.drawing_left_m, pitch, above,
                                     config.drawing_left_sigma_m);
  }
  result.true_effective_yaw_rad =
      config.mount.yaw_error_rad + config.mount.roll_error_rad * std::sin(pitch);
  result.true_effective_lateral_m =
      config.mount.left_m - config.mount.roll_error_rad * above * std::cos(pitch);
  result.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return result;
}

}  // namespace ceilnav::sim
