#include "sim/corridor_drive.hpp"

#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>

#include "sim/corridor_device.hpp"

namespace ceilnav::sim {
namespace {

namespace gc = golden::corridor;
namespace hc = host::corridor;

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("corridor drive: ") + what);
}

}  // namespace

std::vector<gc::Pose> learning_drive(const gc::Pose& start, int frames) {
  std::vector<gc::Pose> out;
  for (int i = 0; i < frames; ++i) {
    gc::Pose p = start;
    p.x_m = start.x_m + i;
    p.y_m = start.y_m + 0.01 * std::sin(0.9 * i);
    p.pan_rad = start.pan_rad + 0.5 * std::numbers::pi / 180.0 * std::sin(1.3 * i + 0.4);
    out.push_back(p);
  }
  return out;
}

void validate(const CorridorDriveParams& p) {
  require(std::isfinite(p.length_m) && p.length_m > 0.0, "length_m must be > 0");
  require(std::isfinite(p.speed_m_s) && p.speed_m_s > 0.0, "speed_m_s must be > 0");
  require(std::isfinite(p.frame_rate_hz) && p.frame_rate_hz > 0.0, "frame_rate_hz must be > 0");
  require(std::isfinite(p.odometry_rate_hz) && p.odometry_rate_hz >= p.frame_rate_hz,
          "odometry_rate_hz must be >= frame_rate_hz");
  require(std::isfinite(p.start_offset_m), "start_offset_m must be finite");
  require(std::isfinite(p.start_heading_rad) && std::abs(p.start_heading_rad) < 0.5,
          "start_heading_rad must be within +-0.5 rad");
  require(std::isfinite(p.convergence_length_m) && p.convergence_length_m > 0.0,
          "convergence_length_m must be > 0");
  validate(p.robot);
  require(p.speed_m_s <= p.robot.max_speed_m_s, "speed_m_s must not exceed robot.max_speed_m_s");
}

CorridorDriveResult run_corridor_drive(
    const gc::Corridor& corridor, const host::CameraConfig& camera, const gc::Pose& start,
    const CorridorDriveParams& params,
    const std::function<void(const CorridorDriveFrame&, const cv::Mat&)>& on_frame) {
  validate(params);
  gc::validate(corridor);
  gc::validate(start, corridor, "start");
  const double frame_period = 1.0 / params.frame_rate_hz;
  const double dt = 1.0 / params.odometry_rate_hz;
  const double x_end = start.x_m + params.length_m;
  require(x_end < corridor.x_end_m(), "the drive must end before the corridor's far end");

  // The camera looks along the vehicle's heading panned by start.pan_rad
  // (its pan on the vehicle, eq. 16's phi_CA): the learning drive's vehicle
  // heads along the axis.
  hc::GuideParams gp;
  gp.mount = {start.tilt_rad, start.swing_rad, start.pan_rad};
  gp.initial_pan_rad = start.pan_rad;
  hc::TurnLawDesign design;
  design.convergence_length_m = params.convergence_length_m;
  design.wheelbase_m = params.robot.wheel_base_m;
  gp.turn = hc::design_turn_law(design);

  const stream::HoughShape shape = corridor_hough_shape();
  CorridorDevice device(shape, camera.image_width, camera.image_height);
  gc::RenderParams rp = params.render;
  uint64_t frame_counter = 0;
  const auto render = [&](const gc::Pose& p) {
    rp.noise_seed = params.seed * 1000003ULL + ++frame_counter;
    return gc::render_frame(camera, corridor, p, rp);
  };

  CorridorDriveResult r;
  // Learning (section 4.1).
  std::vector<hc::LearningImage> images;
  double path_y = 0.0;
  {
    hc::CorridorGuide learner(camera, gp);
    const std::vector<gc::Pose> poses = learning_drive(start);
    for (const gc::Pose& p : poses) {
      const hc::GuideFrame f = learner.process(device.process(render(p)).acc);
      if (std::optional<hc::LearningImage> li = hc::learning_image(f)) images.push_back(*li);
      path_y += p.y_m;
    }
    r.learning_frames = static_cast<int>(poses.size());
    path_y /= static_cast<double>(poses.size());
  }
  r.learning_frames_with_pan = static_cast<int>(images.size());
  r.path_y_m = path_y;
  if (images.size() < 3) {
    throw std::runtime_error(
        "corridor drive: the learning drive gave a pan on fewer than 3 frames");
  }
  hc::LearnOptions lo;
  lo.line_height_m = corridor.ceiling_height_m - start.height_m;
  r.model = hc::learn_model(images, hc::model_camera(camera, gp.mount), lo);

  // The closed loop.
  Robot robot(params.robot,
              nav::Pose2{start.x_m, path_y + params.start_offset_m, params.start_heading_rad});
  hc::CorridorGuide guide(camera, gp, &r.model);
  struct Pending {
    double t_s, omega;
  };
  std::deque<Pending> pending;
  double omega_cmd = 0.0, next_frame_t = 0.0, sum2 = 0.0;
  // The wheel odometry's distance since the last frame (the guide's shift
  // prediction).
  double odometry_m = 0.0;
  bool first_frame = true;
  int64_t samples = 0, held_samples = 0;
  double held_sum2 = 0.0;
  const double timeout = 3.0 * params.length_m / params.speed_m_s + 10.0;
  const auto camera_at = [&](const nav::Pose2& q) {
    gc::Pose c = start;
    c.x_m = q.x_m;
    c.y_m = q.y_m;
    c.pan_rad = q.yaw_rad + start.pan_rad;
    return c;
  };
  while (robot.pose().x_m < x_end) {
    const double t = robot.time_s();
    if (t > timeout) {
      r.stop_reason = "timed out";
      break;
    }
    if (t >= next_frame_t - 1e-9) {
      CorridorDriveFrame fr;
      fr.index = static_cast<int>(r.frames.size());
      fr.t_s = t;
      fr.camera = camera_at(robot.pose());
      fr.path_y_m = path_y;
      try {
        gc::validate(fr.camera, corridor);
      } catch (const gc::CorridorError&) {
        r.stop_reason = "left the corridor";
        break;
      }
      const cv::Mat image = render(fr.camera);
      const CorridorDeviceFrame& d = device.process(image);
      const hc::GuideFrame g =
          guide.process(d.acc, first_frame ? std::nullopt : std::optional<double>(odometry_m));
      first_frame = false;
      odometry_m = 0.0;
      fr.status = g.status;
      fr.lines = static_cast<int>(g.lines.size());
      fr.axis_lines = static_cast<int>(g.pan.axis.inliers.size());
      fr.edges = d.edges;
      fr.pan_rad = g.pan.pan_rad;
      fr.delta_phi_rad = g.delta_phi_rad;
      // The command: the whole law with a shift; the heading term alone
      // with a pan only (hold the heading); straight without a pan.
      double turn = 0.0;
      if (g.status == hc::GuideStatus::ok) {
        fr.shift_m = g.shift.shift_m;
        fr.shift_sigma_m = g.shift.sigma_m;
        turn = g.turn_rad;
      } else if (g.status == hc::GuideStatus::pan_only) {
        turn = hc::heading_term(g.delta_phi_rad, gp.turn);
      }
      fr.turn_rad = turn;
      fr.yaw_rate_cmd_rad_s = hc::yaw_rate(turn, robot.speed_m_s(), gp.turn);
      pending.push_back({t + frame_period, fr.yaw_rate_cmd_rad_s});
      if (on_frame) on_frame(fr, image);
      r.frames.push_back(fr);
      next_frame_t += frame_period;
    }
    while (!pending.empty() && pending.front().t_s <= t + 1e-9) {
      omega_cmd = pending.front().omega;
      pending.pop_front();
    }
    const nav::OdometryStep step = robot.step(dt, params.speed_m_s, omega_cmd);
    odometry_m += 0.5 * (step.left_m + step.right_m);
    const double e = robot.pose().y_m - path_y;
    sum2 += e * e;
    ++samples;
    if (robot.pose().x_m >= start.x_m + 5.0) {
      held_sum2 += e * e;
      ++held_samples;
      r.held_max_m = std::max(r.held_max_m, std::abs(e));
    }
    r.lateral_max_m = std::max(r.lateral_max_m, std::abs(e));
    r.final_lateral_m = e;
  }
  r.completed = robot.pose().x_m >= x_end;
  r.lateral_rms_m = samples > 0 ? std::sqrt(sum2 / static_cast<double>(samples)) : 0.0;
  r.held_rms_m = held_samples > 0 ? std::sqrt(held_sum2 / static_cast<double>(held_samples)) : 0.0;
  r.distance_m = robot.pose().x_m - start.x_m;
  r.time_s = robot.time_s();
  return r;
}

}  // namespace ceilnav::sim
