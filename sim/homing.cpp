#include "sim/homing.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "ceilnav/regs.hpp"
#include "common/pipeline_config.hpp"
#include "drivers/device.hpp"
#include "golden/orientation_ref.hpp"
#include "host/camera_model.hpp"
#include "host/homing/homing_measurement.hpp"

namespace ceilnav::sim {
namespace {

namespace gc = golden::ceiling;
namespace hh = host::homing;

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("homing: ") + what);
}

// The robot's true error toward a pose, in the robot's frame.
nav::HomingError true_error(const nav::Pose2& robot, const gc::SitePose& site) {
  const double dx = site.x_m - robot.x_m, dy = site.y_m - robot.y_m;
  const double c = std::cos(robot.yaw_rad), s = std::sin(robot.yaw_rad);
  return {c * dx + s * dy, -s * dx + c * dy, nav::wrap_angle(site.yaw_rad - robot.yaw_rad)};
}

class FrameSource {
 public:
  FrameSource(const gc::CeilingFile& w, const host::CameraConfig& c, const gc::RenderParams& r,
              uint64_t seed, const std::optional<drivers::DeviceOptions>& device)
      : world(w), camera(c), render(r), next_seed(seed) {
    if (!device) return;
    // The homing device: the orientation block on the LUT's remap, an
    // identity LUT (the block sees the camera's grey levels).
    drivers::DeviceOptions o = *device;
    o.device_config = regs::kConfigHoming;
    device_ = std::make_unique<drivers::Device>(o);
    device_->set_orientation({true, kThreshold});
    config_.width = static_cast<uint16_t>(camera.image_width);
    config_.height = static_cast<uint16_t>(camera.image_height);
    for (unsigned g = 0; g < 256; ++g) {
      config_.lut[g] = stream::lut_entry(static_cast<uint8_t>(g), false, 0);
    }
  }
  const gc::CeilingFile& world;
  const host::CameraConfig& camera;
  gc::RenderParams render;
  uint64_t next_seed;
  cv::Mat grey;
  hh::OrientationHistogram histogram;

  void shoot(const nav::Pose2& robot, const gc::Lighting& lighting) {
    render.noise_seed = next_seed++;
    grey = gc::render_frame(camera, world.ceiling, lighting,
                            gc::camera_pose(world.camera, robot.x_m, robot.y_m, robot.yaw_rad),
                            render);
    if (!device_) {
      // The orientation block's histogram by its bit-true golden (what the
      // device reads out, docs/blocks/orientation.md).
      const std::vector<uint32_t> bins =
          golden::orientation_histogram_fixed(grey, {90, kThreshold});
      histogram.assign(bins.begin(), bins.end());
      return;
    }
    // The frame through the device; the histogram read from its registers.
    std::vector<stream::RunRecord> runs;
    uint64_t cycles = 0;
    device_->process(grey, config_, runs, cycles);
    const host::OrientationReadout& o = device_->orientation();
    if (!o.valid || o.frames != ++frames_) {
      throw std::runtime_error("homing: the device published no orientation histogram");
    }
    histogram.assign(o.bins.begin(), o.bins.end());
  }

 private:
  static constexpr uint16_t kThreshold = 16;  // ORI_CONTROL.THRESHOLD
  std::unique_ptr<drivers::Device> device_;
  stream::PipelineConfig config_;
  uint32_t frames_ = 0;  // published by the device
};

uint64_t mix(uint64_t a, uint64_t b) {
  uint64_t x = a * 0x9E3779B97F4A7C15ULL + b + 0x632BE59BD9B4E019ULL;
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ULL;
  return x ^ (x >> 29);
}

}  // namespace

void validate(const HomingSimParams& p) {
  require(std::isfinite(p.frame_rate_hz) && p.frame_rate_hz > 0.0, "frame_rate_hz must be > 0");
  require(std::isfinite(p.odometry_rate_hz) && p.odometry_rate_hz >= p.frame_rate_hz,
          "odometry_rate_hz must be >= frame_rate_hz");
  require(std::isfinite(p.latency_s) && p.latency_s >= 0.0, "latency_s must be >= 0");
  require(std::isfinite(p.acquire_radius_m) && p.acquire_radius_m > 0.0,
          "acquire_radius_m must be > 0");
  require(std::isfinite(p.track_radius_px) && p.track_radius_px > 0.0,
          "track_radius_px must be > 0");
  require(p.max_lost_frames >= 1, "max_lost_frames must be >= 1");
  require(std::isfinite(p.search_yaw_rate_rad_s) && p.search_yaw_rate_rad_s > 0.0 &&
              p.search_yaw_rate_rad_s <= p.robot.max_yaw_rate_rad_s,
          "search_yaw_rate_rad_s must be in (0, robot.max_yaw_rate_rad_s]");
  require(std::isfinite(p.max_bridge_m) && p.max_bridge_m >= 0.0, "max_bridge_m must be >= 0");
  require(std::isfinite(p.max_time_s) && p.max_time_s > 0.0, "max_time_s must be > 0");
  require(std::isfinite(p.consistency_position_m) && p.consistency_position_m > 0.0 &&
              std::isfinite(p.consistency_turn_rad) && p.consistency_turn_rad > 0.0,
          "consistency bounds must be > 0");
  require(p.settle_frames >= 1, "settle_frames must be >= 1");
  require(std::isfinite(p.path_speed_m_s) && p.path_speed_m_s > 0.0 &&
              p.path_speed_m_s <= p.robot.max_speed_m_s,
          "path_speed_m_s must be in (0, robot.max_speed_m_s]");
  require(std::isfinite(p.path_yaw_rate_rad_s) && p.path_yaw_rate_rad_s > 0.0 &&
              p.path_yaw_rate_rad_s <= p.robot.max_yaw_rate_rad_s,
          "path_yaw_rate_rad_s must be in (0, robot.max_yaw_rate_rad_s]");
  validate(p.robot);
  nav::validate(p.servo);
}

host::CameraConfig homing_camera(const host::CameraConfig& intrinsics,
                                 const gc::CeilingFile& world) {
  host::CameraConfig c = intrinsics;
  c.camera_pitch_deg = 90.0;
  c.camera_height_m = world.camera.height_m;
  c.ceiling_height_m = world.ceiling.height_m;
  return c;
}

hh::SiteMap record_sites(const gc::CeilingFile& world, const host::CameraConfig& camera,
                         const HomingSimParams& p) {
  validate(p);
  gc::validate(world);
  FrameSource src{world, camera, p.render, mix(p.seed, 0x5173), p.device};
  const double ceiling_distance = world.ceiling.height_m - world.camera.height_m;
  const host::CameraModel model(camera);
  hh::SiteMap map;
  for (std::size_t k = 0; k < world.sites.size(); ++k) {
    const gc::SitePose& s = world.sites[k];
    const nav::Pose2 pose{s.x_m, s.y_m, s.yaw_rad};
    src.shoot(pose, world.lighting);
    hh::MapSite site;
    site.name = s.name;
    site.pose = pose;
    site.site = hh::record_site(src.grey, src.histogram, camera, p.site);
    // The look point's offset: six turns of 60 deg in place, the site
    // measured after each (nav::look_offset_from_turns).
    const hh::SiteTracker tracker(site.site, p.tracker);
    Robot robot(p.robot, pose);
    // The turns are known to the odometry's accuracy: each frame is
    // searched in the fast mode about the turn made (gamma = -turn).
    std::vector<nav::HomingMeasurement> turns;
    for (int t = 1; t <= 6; ++t) {
      follow_path(robot, {0, 0, std::numbers::pi / 3.0, 0.0, 0.0}, p);
      src.shoot(robot.pose(), world.lighting);
      turns.push_back(
          hh::homing_measurement(tracker.track(src.grey, src.histogram, std::nullopt, -60.0 * t),
                                 model, ceiling_distance, static_cast<int>(k)));
    }
    int found = 0;
    for (const nav::HomingMeasurement& m : turns) found += m.status == nav::MeasurementStatus::ok;
    if (found >= 3) {
      const Eigen::Vector2d look = nav::look_offset_from_turns(turns);
      site.look_forward_m = look.x();
      site.look_left_m = look.y();
    } else {
      site.unusable = "found again at " + std::to_string(found) +
                      " of 6 turns in place: it reads alike elsewhere or turned";
    }
    map.sites.push_back(std::move(site));
  }
  const int n = static_cast<int>(map.sites.size());
  for (int k = 0; n >= 2 && k < n; ++k) {
    const int next = (k + 1) % n;
    map.paths.push_back(hh::path_between(map.sites[static_cast<std::size_t>(k)].pose,
                                         map.sites[static_cast<std::size_t>(next)].pose, k, next));
  }
  return map;
}

const char* to_string(HomingOutcome o) {
  switch (o) {
    case HomingOutcome::homed:
      return "homed";
    case HomingOutcome::not_found:
      return "not_found";
    case HomingOutcome::lost:
      return "lost";
    case HomingOutcome::timeout:
      return "timeout";
    case HomingOutcome::unusable:
      return "unusable";
  }
  return "?";
}

HomingRun home(Robot& robot, const hh::SiteMap& map, int site, const gc::CeilingFile& world,
               const host::CameraConfig& camera, const HomingSimParams& p,
               const std::function<void(const HomingFrame&)>& on_frame,
               std::optional<double> heading_prior_rad) {
  validate(p);
  require(site >= 0 && site < static_cast<int>(map.sites.size()) &&
              site < static_cast<int>(world.sites.size()),
          "the site is not in the map and the world");
  const gc::SitePose& truth = world.sites[static_cast<std::size_t>(site)];
  if (!map.sites[static_cast<std::size_t>(site)].unusable.empty()) {
    HomingRun none;
    none.outcome = HomingOutcome::unusable;
    const nav::HomingError e = true_error(robot.pose(), truth);
    none.start_distance_m = none.position_error_m = e.distance_m();
    none.start_heading_error_rad = none.heading_error_rad = e.turn_rad;
    return none;
  }
  const double ceiling_distance = world.ceiling.height_m - world.camera.height_m;
  const host::CameraModel model(camera);

  hh::TrackerOptions acquire_opt = p.tracker;
  acquire_opt.search_radius_px = p.acquire_radius_m / ceiling_distance * camera.fx();
  hh::TrackerOptions track_opt = p.tracker;
  track_opt.search_radius_px = p.track_radius_px;
  const hh::Site& recorded = map.sites[static_cast<std::size_t>(site)].site;
  hh::TrackerOptions reacquire_opt = track_opt;
  reacquire_opt.search_radius_px = 2.5 * p.track_radius_px;
  const hh::SiteTracker acquirer(recorded, acquire_opt), tracker(recorded, track_opt),
      reacquirer(recorded, reacquire_opt);

  nav::HomingServoParams sp = p.servo;
  sp.camera_forward_m = map.sites[static_cast<std::size_t>(site)].look_forward_m;
  sp.camera_left_m = map.sites[static_cast<std::size_t>(site)].look_left_m;
  nav::HomingServo servo(sp);

  FrameSource src{
      world, camera, p.render,
      mix(p.seed, mix(static_cast<uint64_t>(site), static_cast<uint64_t>(robot.time_s() * 1e3))),
      p.device};
  const double dt = 1.0 / p.odometry_rate_hz, period = 1.0 / p.frame_rate_hz;
  const double t0 = robot.time_s();
  double next_frame = t0;
  std::deque<std::pair<double, nav::HomingCommand>> pending;
  nav::HomingCommand applied;
  applied.phase = nav::HomingPhase::position;
  bool acquired = false;
  bool have_last_error = false;
  nav::HomingError last_error;
  nav::Pose2 moved;  // the odometry's motion since the last consistent match
  int lost = 0, settled = 0;
  double searched_rad = 0.0;  // the search turn's odometry (not wrapped)
  cv::Point2d last_px;
  double last_gamma = 0.0;

  HomingRun run;
  const nav::HomingError start = true_error(robot.pose(), truth);
  run.start_distance_m = start.distance_m();
  run.start_heading_error_rad = start.turn_rad;
  const nav::Pose2 first = robot.pose();
  double travelled = 0.0;
  nav::Pose2 previous = first;
  bool finished = false;
  while (!finished) {
    if (robot.time_s() - t0 > p.max_time_s) {
      run.outcome = HomingOutcome::timeout;
      break;
    }
    if (robot.time_s() >= next_frame - 1e-9) {
      next_frame += period;
      src.shoot(robot.pose(), world.lighting_at_return());
      hh::TrackResult r;
      if (acquired) {
        r = tracker.track(src.grey, src.histogram, last_px, last_gamma);
      } else {
        if (have_last_error) {
          // Lost after a good match: the odometry since it predicts the
          // turn (the quadrant); search about the last place, wider.
          r = reacquirer.track(src.grey, src.histogram, last_px,
                               last_gamma - moved.yaw_rad * 180.0 / std::numbers::pi);
        } else if (heading_prior_rad) {
          // The prior less the search turn so far.
          r = acquirer.track(src.grey, src.histogram, std::nullopt,
                             (*heading_prior_rad - moved.yaw_rad) * 180.0 / std::numbers::pi);
        }
        if (r.status != hh::TrackStatus::ok) r = acquirer.track(src.grey, src.histogram);
      }
      HomingFrame f;
      f.t_s = robot.time_s();
      f.robot = robot.pose();
      f.track = r.status;
      f.score = r.score;
      f.measurement = hh::homing_measurement(r, model, ceiling_distance, site);
      f.measurement.time = {f.t_s, f.t_s + p.latency_s};
      f.true_error = true_error(robot.pose(), truth);
      // The odometry's check of the match: the robot's error toward the
      // site moves against the robot's own motion since the last match
      // (p' = R(-dpsi) (p - d), g' = g - dpsi). A match that does not (a
      // like structure elsewhere, followed as the robot moves) is dropped
      // and the site searched for again.
      if (f.measurement.status == nav::MeasurementStatus::ok) {
        const nav::HomingError now =
            nav::robot_error(f.measurement, sp.camera_forward_m, sp.camera_left_m);
        if (have_last_error) {
          const double c = std::cos(moved.yaw_rad), sn = std::sin(moved.yaw_rad);
          const double dx = last_error.forward_m - moved.x_m, dy = last_error.left_m - moved.y_m;
          const double px = c * dx + sn * dy, py = -sn * dx + c * dy;
          const double gap = std::hypot(now.forward_m - px, now.left_m - py);
          const double turn_gap =
              std::abs(nav::wrap_angle(now.turn_rad - (last_error.turn_rad - moved.yaw_rad)));
          const double motion = std::hypot(moved.x_m, moved.y_m);
          f.consistent = gap <= p.consistency_position_m + 0.1 * motion &&
                         turn_gap <= p.consistency_turn_rad + 0.05 * std::abs(moved.yaw_rad);
        }
        if (f.consistent) {
          last_error = now;
          have_last_error = true;
          moved = {};
        } else {
          f.measurement.status = nav::MeasurementStatus::inconsistent;
          ++run.inconsistent_frames;
        }
      }
      bool out_of_view = false;
      if (f.measurement.status == nav::MeasurementStatus::ok) {
        f.command = servo.update(f.measurement);
      } else if (!have_last_error) {
        // Never matched: the search turn (the servo stays as it was).
        f.command.phase = nav::HomingPhase::position;
        f.command.v_m_s = 0.0;
        f.command.omega_rad_s = p.search_yaw_rate_rad_s;
      } else {
        // No match this frame (the site at the frame's edge while the robot
        // turns toward it, or a match dropped): the servo goes on with the
        // error the odometry predicts from the last good match, p' = R(-dpsi)
        // (p - d), g' = g - dpsi, as the camera's measurement would give it
        // (s = p' + R(g') c - c). It is never `done` on a prediction: the
        // homing ends on matched frames only.
        const double c = std::cos(moved.yaw_rad), sn = std::sin(moved.yaw_rad);
        const double dx = last_error.forward_m - moved.x_m, dy = last_error.left_m - moved.y_m;
        const double g = nav::wrap_angle(last_error.turn_rad - moved.yaw_rad);
        const double cf = sp.camera_forward_m, cl = sp.camera_left_m;
        nav::HomingMeasurement predicted = f.measurement;
        predicted.status = nav::MeasurementStatus::ok;
        predicted.forward_m = c * dx + sn * dy + std::cos(g) * cf - std::sin(g) * cl - cf;
        predicted.left_m = -sn * dx + c * dy + std::sin(g) * cf + std::cos(g) * cl - cl;
        predicted.turn_rad = g;
        f.command = servo.update(predicted);
        f.predicted = true;
        // Where the site should reappear: the search's centre.
        const Eigen::Vector2d px = model.distort_to_pixel(
            {-predicted.left_m / ceiling_distance, predicted.forward_m / ceiling_distance});
        last_px = {px.x(), px.y()};
        // Out of view: the turned template's half diagonal does not fit
        // between the predicted site point and the frame's edge.
        const double half = 0.5 * std::sqrt(2.0) * recorded.options.template_px;
        out_of_view = !(px.x() >= half && px.x() <= camera.image_width - 1 - half &&
                        px.y() >= half && px.y() <= camera.image_height - 1 - half) &&
                      std::hypot(moved.x_m, moved.y_m) <= p.max_bridge_m;
      }
      ++run.frames;
      if (!f.consistent) {
        // Searched again from the next frame, about the odometry's
        // prediction from the last good match (which stays the reference:
        // dropping it for a match that keeps disagreeing homed a 180 deg
        // turned look-alike 0.36 m away).
        acquired = false;
        if (++lost >= p.max_lost_frames) {
          run.outcome = HomingOutcome::lost;
          finished = true;
        }
      } else if (r.status == hh::TrackStatus::ok) {
        acquired = true;
        lost = 0;
        last_px = {r.x_px, r.y_px};
        last_gamma = r.gamma_deg;
      } else {
        // No match: the next frame searches again (about the odometry's
        // prediction when there was a good match).
        if (!have_last_error) {
          if (++lost >= p.max_lost_frames && std::abs(searched_rad) >= 2.0 * std::numbers::pi) {
            run.outcome = HomingOutcome::not_found;
            finished = true;
          }
        } else if (!out_of_view && ++lost >= p.max_lost_frames) {
          run.outcome = HomingOutcome::lost;
          finished = true;
        }
        acquired = false;
      }
      const bool at_rest = robot.speed_m_s() == 0.0 && robot.yaw_rate_rad_s() == 0.0;
      settled = f.command.phase == nav::HomingPhase::done &&
                        f.measurement.status == nav::MeasurementStatus::ok && at_rest
                    ? settled + 1
                    : 0;
      if (settled >= p.settle_frames) {
        run.outcome = HomingOutcome::homed;
        finished = true;
      }
      pending.emplace_back(f.t_s + p.latency_s, f.command);
      if (on_frame) on_frame(f);
      if (finished) break;
    }
    while (!pending.empty() && pending.front().first <= robot.time_s() + 1e-9) {
      applied = pending.front().second;
      pending.pop_front();
    }
    const nav::Motion step =
        nav::motion_of(robot.step(dt, applied.v_m_s, applied.omega_rad_s), p.robot.wheel_base_m);
    moved = nav::advance(moved, step);
    if (!have_last_error) searched_rad += step.dyaw_rad;
    travelled += std::hypot(robot.pose().x_m - previous.x_m, robot.pose().y_m - previous.y_m);
    previous = robot.pose();
  }
  // The robot stops (the servo's last command was zero when homed).
  for (int k = 0; k < 200 && (robot.speed_m_s() != 0.0 || robot.yaw_rate_rad_s() != 0.0); ++k) {
    robot.step(dt, 0.0, 0.0);
  }
  const nav::HomingError end = true_error(robot.pose(), truth);
  run.position_error_m = end.distance_m();
  run.heading_error_rad = end.turn_rad;
  run.time_s = robot.time_s() - t0;
  run.travelled_m = travelled;
  return run;
}

double follow_path(Robot& robot, const hh::OdometricPath& path, const HomingSimParams& p) {
  validate(p);
  const double dt = 1.0 / p.odometry_rate_hz;
  const double b = p.robot.wheel_base_m;
  nav::Pose2 odo;  // dead reckoning from the path's start, in its frame
  double distance = 0.0;
  const auto tick = [&](double v, double w) {
    const nav::Motion m = nav::motion_of(robot.step(dt, v, w), b);
    odo = nav::advance(odo, m);
    distance += std::abs(m.distance_m);
  };
  // Speed toward a remaining distance (or angle) that still stops within
  // it at the given deceleration, and proportional (gain 4/s) at the end.
  const auto profile = [](double remaining, double max_rate, double decel) {
    const double mag = std::min(
        {max_rate, std::sqrt(2.0 * decel * std::abs(remaining)) * 0.9, 4.0 * std::abs(remaining)});
    return std::copysign(mag, remaining);
  };
  const auto turn_to = [&](double yaw) {
    for (int k = 0; k < 100000; ++k) {
      const double err = nav::wrap_angle(yaw - odo.yaw_rad);
      if (std::abs(err) < 2e-4 && std::abs(robot.yaw_rate_rad_s()) < 1e-3) return;
      tick(0.0, profile(err, p.path_yaw_rate_rad_s, p.robot.max_yaw_accel_rad_s2));
    }
  };
  const double heading = path.turn_rad;
  turn_to(heading);
  // The straight leg: along the odometry's line at `heading` from its
  // start, holding the line (heading and lateral offset in the odometry).
  const double c = std::cos(heading), s = std::sin(heading);
  for (int k = 0; k < 1000000; ++k) {
    const double along = c * odo.x_m + s * odo.y_m;
    const double lateral = -s * odo.x_m + c * odo.y_m;
    const double remaining = path.distance_m - along;
    if (std::abs(remaining) < 2e-4 && std::abs(robot.speed_m_s()) < 1e-3) break;
    const double v = profile(remaining, p.path_speed_m_s, p.robot.max_accel_m_s2);
    const double psi = nav::wrap_angle(odo.yaw_rad - heading);
    const double w = -2.0 * psi - 4.0 * lateral * std::max(std::abs(v), 0.05);
    tick(v, std::clamp(w, -p.path_yaw_rate_rad_s, p.path_yaw_rate_rad_s));
  }
  turn_to(nav::wrap_angle(heading + path.final_turn_rad));
  for (int k = 0; k < 200 && (robot.speed_m_s() != 0.0 || robot.yaw_rate_rad_s() != 0.0); ++k) {
    tick(0.0, 0.0);
  }
  return distance;
}

CaptureZone capture_zone(const gc::CeilingFile& world, const host::CameraConfig& camera,
                         const hh::SiteMap& map, int site, const HomingSimParams& p,
                         const CaptureParams& c,
                         const std::function<void(const CaptureStart&)>& on_start) {
  validate(p);
  require(!c.radii_m.empty() && c.bearings >= 1 && !c.heading_offsets_rad.empty(),
          "the capture study needs radii, bearings and headings");
  require(site >= 0 && site < static_cast<int>(world.sites.size()), "no such site");
  const gc::SitePose& s = world.sites[static_cast<std::size_t>(site)];
  CaptureZone zone;
  std::vector<double> radii = c.radii_m;
  std::sort(radii.begin(), radii.end());
  uint64_t n = 0;
  for (double r : radii) {
    for (int k = 0; k < c.bearings; ++k) {
      const double bearing = 2.0 * std::numbers::pi * k / c.bearings;
      for (double h : c.heading_offsets_rad) {
        CaptureStart st;
        st.radius_m = r;
        st.bearing_rad = bearing;
        st.heading_offset_rad = h;
        HomingSimParams q = p;
        q.robot.seed = mix(p.robot.seed, ++n);
        q.seed = mix(p.seed, n);
        Robot robot(q.robot, {s.x_m + r * std::cos(bearing), s.y_m + r * std::sin(bearing),
                              nav::wrap_angle(s.yaw_rad + h)});
        st.run = home(robot, map, site, world, camera, q);
        st.success = st.run.outcome == HomingOutcome::homed &&
                     st.run.position_error_m <= c.success_position_m &&
                     std::abs(st.run.heading_error_rad) <= c.success_heading_rad;
        zone.false_homings += st.run.outcome == HomingOutcome::homed && !st.success;
        zone.starts.push_back(st);
        if (on_start) on_start(st);
      }
    }
  }
  for (double r : radii) {
    const bool all =
        std::all_of(zone.starts.begin(), zone.starts.end(),
                    [&](const CaptureStart& st) { return st.radius_m > r || st.success; });
    if (!all) break;
    zone.radius_m = r;
  }
  return zone;
}

RaceResult run_race(const gc::CeilingFile& world, const host::CameraConfig& camera,
                    const hh::SiteMap& map, const HomingSimParams& p, int loops, bool with_homing,
                    const std::function<void(const RaceLeg&)>& on_leg,
                    const std::function<void(const HomingFrame&)>& on_frame) {
  validate(p);
  require(loops >= 1, "loops must be >= 1");
  const int n = static_cast<int>(map.sites.size());
  require(n >= 2 && n == static_cast<int>(world.sites.size()),
          "the race needs the world's sites (two or more) in the map");
  // The robot is put down near the first site (a placement 8 cm and 4 deg
  // off) and homes there first: the seed's table starts with site 1.
  const gc::SitePose& s0 = world.sites[0];
  Robot robot(p.robot, {s0.x_m + 0.06, s0.y_m - 0.05, s0.yaw_rad + 0.07});
  RaceResult res;
  double sum_p2 = 0.0, sum_h2 = 0.0, sum_a2 = 0.0;
  int current = 0;
  for (int loop = 1; loop <= loops; ++loop) {
    for (int k = 0; k < n; ++k) {
      RaceLeg leg;
      leg.loop = loop;
      leg.site = current;
      const nav::HomingError arrival =
          true_error(robot.pose(), world.sites[static_cast<std::size_t>(current)]);
      leg.arrival_distance_m = arrival.distance_m();
      leg.arrival_heading_error_rad = arrival.turn_rad;
      sum_a2 += leg.arrival_distance_m * leg.arrival_distance_m;
      if (with_homing) {
        leg.homing = home(robot, map, current, world, camera, p, on_frame, 0.0);
        res.distance_m += leg.homing.travelled_m;
        if (leg.homing.outcome == HomingOutcome::homed) {
          ++res.homed;
          sum_p2 += leg.homing.position_error_m * leg.homing.position_error_m;
          sum_h2 += leg.homing.heading_error_rad * leg.homing.heading_error_rad;
          res.position_max_m = std::max(res.position_max_m, leg.homing.position_error_m);
          res.heading_max_rad =
              std::max(res.heading_max_rad, std::abs(leg.homing.heading_error_rad));
          // A homing that ends more than 1 cm or 0.5 deg off claimed a site
          // it was not at.
          res.false_homings +=
              leg.homing.position_error_m > 0.01 || std::abs(leg.homing.heading_error_rad) > 0.0087;
        } else {
          ++res.failed;
        }
      }
      res.legs.push_back(leg);
      if (on_leg) on_leg(leg);
      if (loop == loops && k == n - 1) break;  // the race ends with its last homing
      const hh::OdometricPath* path = map.path_from(current);
      require(path != nullptr, "a site without a path onward");
      res.distance_m += follow_path(robot, *path, p);
      current = path->to;
    }
  }
  const int legs = static_cast<int>(res.legs.size());
  if (res.homed > 0) {
    res.position_rms_m = std::sqrt(sum_p2 / res.homed);
    res.heading_rms_rad = std::sqrt(sum_h2 / res.homed);
  }
  res.arrival_rms_m = std::sqrt(sum_a2 / legs);
  res.time_s = robot.time_s();
  return res;
}

}  // namespace ceilnav::sim
