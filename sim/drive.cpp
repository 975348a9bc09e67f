#include "sim/drive.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "golden/pattern/pattern.hpp"
#include "host/flow_height.hpp"
#include "host/junction.hpp"
#include "host/pattern/world_fix.hpp"
#include "nav/chi_square.hpp"
#include "sim/pattern_analysis.hpp"
#include "stream/ceilnav_top.hpp"

namespace ceilnav::sim {
namespace {

Eigen::Vector2d point_at_arc(const TapePolyline& t, double s) {
  for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
    const Eigen::Vector2d a(t.points[k].x_m, t.points[k].y_m);
    const Eigen::Vector2d b(t.points[k + 1].x_m, t.points[k + 1].y_m);
    const double len = (b - a).norm();
    if (s <= len || k + 2 == t.points.size()) return a + (b - a) * std::min(1.0, s / len);
    s -= len;
  }
  return {t.points.back().x_m, t.points.back().y_m};
}

double distance_to_path(const std::vector<Eigen::Vector2d>& w, const Eigen::Vector2d& p) {
  double best = 1e300;
  for (std::size_t k = 0; k + 1 < w.size(); ++k) {
    const Eigen::Vector2d ab = w[k + 1] - w[k];
    const double u = std::clamp((p - w[k]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (w[k] + u * ab - p).norm());
  }
  return best;
}

const char* outcome_name(nav::Outcome o) {
  switch (o) {
    case nav::Outcome::accepted:
      return "accepted";
    case nav::Outcome::pending:
      return "pending";
    case nav::Outcome::rejected_gate:
      return "rejected_gate";
    case nav::Outcome::unassociated:
      return "unassociated";
    case nav::Outcome::too_old:
      return "too_old";
    case nav::Outcome::not_ok:
      return "not_ok";
  }
  return "unknown";
}

// The camera the filter believes in: its mount, without pitch or roll errors.
CameraMount believed(const nav::CameraMount& m) {
  CameraMount c;
  c.forward_m = m.forward_m;
  c.left_m = m.left_m;
  c.yaw_error_rad = m.yaw_rad;
  return c;
}

// The Navigator's view of the drive's device, which the stations' windows
// also use.
class SharedDevice : public host::FrameProcessor {
 public:
  explicit SharedDevice(drivers::Device& device) : device_(device) {}
  stream::FrameResults process(const cv::Mat& grey, const stream::PipelineConfig& cfg,
                               std::vector<stream::RunRecord>& runs, uint64_t& cycles) override {
    return device_.process(grey, cfg, runs, cycles);
  }

 private:
  drivers::Device& device_;
};

// The true start: the course's start pose plus a draw from the start sigmas
// the filter is told (so its initial covariance is a real one).
nav::Pose2 true_start(const DriveConfig& c) {
  std::mt19937_64 rng(c.robot.seed ^ 0x5354415254ull);
  std::normal_distribution<double> n(0.0, 1.0);
  nav::Pose2 p = c.course.start;
  p.x_m += c.start_sigma_m * n(rng);
  p.y_m += c.start_sigma_m * n(rng);
  p.yaw_rad += c.start_sigma_yaw_rad * n(rng);
  return p;
}

}  // namespace

Drive::Drive(const DriveConfig& config)
    : config_(config),
      plan_(plan_route(config.course)),
      strips_(ceiling_scene(config.course)),
      robot_(config.robot, true_start(config), 0.0),
      follower_(plan_.waypoints, config.follower) {
  config_.camera.ceiling_height_m = config_.course.ceiling_height_m;
  config_.camera.camera_height_m = config_.camera_height_m;
  if (!(config_.ceiling.map_scale > 0.0))
    throw std::invalid_argument("drive: ceiling.map_scale must be > 0");
  map_course_ = config_.course;
  map_course_.ceiling_height_m *= config_.ceiling.map_scale;
  for (HeightZone& z : map_course_.zones) z.height_m *= config_.ceiling.map_scale;
  flow_ =
      std::make_unique<host::FlowTrack>(config_.camera.camera_pitch_deg * std::numbers::pi / 180.0,
                                        config_.camera.ceiling_above_camera_m());
  if (!(config_.odometry_rate_hz > 0.0) || !(config_.frame_rate_hz > 0.0) ||
      !(config_.exposure_s >= 0.0) || config_.exposure_s >= 1.0 / config_.frame_rate_hz) {
    throw std::invalid_argument(
        "drive: odometry and frame rates must be positive and the exposure shorter than a frame");
  }
  dt_ = 1.0 / config_.odometry_rate_hz;
  for (const TapePolyline& t : config_.course.tapes) {
    for (std::size_t k = 0; k + 1 < t.points.size(); ++k) {
      map_.add({{t.points[k].x_m, t.points[k].y_m},
                {t.points[k + 1].x_m, t.points[k + 1].y_m},
                t.width_m});
    }
  }
  // Landmarks: both ends of every gap, the ends of every tape that do not
  // lie on another tape (those are junctions), and every junction.
  const std::vector<Junction> junctions_of_course = junctions(config_.course);
  for (const Junction& j : junctions_of_course)
    map_.add_landmark({nav::LandmarkMeasurement::Kind::junction, {j.position.x_m, j.position.y_m}});
  for (const TapePolyline& t : config_.course.tapes) {
    for (const auto& [g0, g1] : t.gaps_m) {
      map_.add_landmark({nav::LandmarkMeasurement::Kind::tape_end, point_at_arc(t, g0)});
      map_.add_landmark({nav::LandmarkMeasurement::Kind::tape_end, point_at_arc(t, g1)});
    }
    for (const Point2& e : {t.points.front(), t.points.back()}) {
      bool on_junction = false;
      for (const Junction& j : junctions_of_course)
        on_junction |= std::hypot(j.position.x_m - e.x_m, j.position.y_m - e.y_m) <= t.width_m;
      if (!on_junction)
        map_.add_landmark({nav::LandmarkMeasurement::Kind::tape_end, {e.x_m, e.y_m}});
    }
  }
  nav::EkfOptions eo = config_.ekf;
  eo.mount = config_.believed_mount;
  eo.odometry.wheel_base_m = config_.robot.wheel_base_m;
  nav::State x0 = nav::State::Zero();
  x0(nav::state::x) = config_.course.start.x_m;
  x0(nav::state::y) = config_.course.start.y_m;
  x0(nav::state::yaw) = config_.course.start.yaw_rad;
  nav::Covariance p0 = nav::Ekf::calibration_prior(eo.odometry) + nav::Ekf::bias_prior(eo.bias);
  p0(nav::state::x, nav::state::x) = p0(nav::state::y, nav::state::y) =
      config_.start_sigma_m * config_.start_sigma_m;
  p0(nav::state::yaw, nav::state::yaw) = config_.start_sigma_yaw_rad * config_.start_sigma_yaw_rad;
  ekf_ = std::make_unique<nav::Ekf>(eo, &map_, 0.0, x0, p0);
  // One device for the tape frames and the stations' windows (one Verilated
  // top on the rtl backend; a second top in the process stalls its start).
  device_ = std::make_unique<drivers::Device>(config_.device);
  navigator_ = std::make_unique<host::Navigator>(
      config_.camera, std::make_unique<SharedDevice>(*device_), config_.navigator);
  stations_ = config_.station_map ? *config_.station_map : config_.course.patterns;
  if (config_.station_fixes.enabled && !stations_.empty()) {
    pattern_device_ = device_.get();
    // The full-resolution sensor's model, built once (its undistortion
    // tables cost what a few frames do).
    sensor_model_ = std::make_unique<host::CameraModel>(sensor_camera());
  }
  track_.add(0.0, robot_.pose());
  odometry_pose_ = config_.course.start;
  odometry_track_.add(0.0, odometry_pose_);
  t_end_ = config_.max_time_s > 0.0
               ? config_.max_time_s
               : 3.0 * plan_.length_m / std::max(0.05, config_.follower.cruise_speed_mps) + 60.0;
}

Drive::~Drive() = default;

double Drive::pass_time_s(int pixels) const {
  // The pipeline's own timing: a pass streams its pixels at one per clock
  // and raises its interrupt kEofToIntrCycles after the last (docs/profile.md);
  // the same on every backend, since they are cycle-true to one another.
  return (static_cast<double>(pixels) + stream::CeilnavTop::kEofToIntrCycles) /
         config_.pixel_clock_hz;
}

double Drive::frame_latency_s(const host::FrameOutcome& o) const {
  return std::max(1, o.passes) *
             pass_time_s(config_.camera.image_width * config_.camera.image_height) +
         config_.host_time_s;
}

std::optional<Drive::StationView> Drive::station_in_view() const {
  if (!pattern_device_) return std::nullopt;
  const golden::pattern::PatternGeometry& g = config_.render.pattern_geometry;
  const golden::CameraView view =
      camera_view(config_.camera, believed(config_.believed_mount), ekf_->pose());
  const host::CameraConfig sensor = sensor_camera();
  const host::CameraModel& model = *sensor_model_;
  const double half_w = std::abs(golden::pattern::block_outer_x_m(g)) + g.plate_margin_m;
  const double half_h = 0.5 * g.bar_height_m + g.plate_margin_m;
  const double m = config_.station_fixes.margin_px * config_.station_fixes.window_scale;
  const double w = sensor.image_width, h = sensor.image_height;
  std::optional<StationView> best;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < stations_.size(); ++k) {
    const StationFrame f = station_frame(config_.course, stations_[k], g);
    bool inside = true;
    double u0 = w, u1 = 0.0, v0 = h, v1 = 0.0;
    for (int c = 0; c < 4 && inside; ++c) {
      const Eigen::Vector3d local((c & 1) ? half_w : -half_w, (c & 2) ? half_h : -half_h, 0.0);
      const Eigen::Vector3d p = view.world_to_camera * (f.origin + f.axes * local - view.centre);
      if (!(p.z() > 0.0)) {
        inside = false;
        break;
      }
      const Eigen::Vector2d xy(p.x() / p.z(), p.y() / p.z());
      // The pinhole image first: the distortion model folds far outside it.
      const Eigen::Vector2d ideal = model.ideal_pixel(xy);
      if (ideal.x() < -0.5 * w || ideal.x() > 1.5 * w || ideal.y() < -0.5 * h ||
          ideal.y() > 1.5 * h) {
        inside = false;
        break;
      }
      const Eigen::Vector2d px = model.distort_to_pixel(xy);
      inside = px.x() >= m && px.x() <= w - 1.0 - m && px.y() >= m && px.y() <= h - 1.0 - m;
      u0 = std::min(u0, px.x());
      u1 = std::max(u1, px.x());
      v0 = std::min(v0, px.y());
      v1 = std::max(v1, px.y());
    }
    const double d = (f.origin - view.centre).norm();
    if (!inside || !(d < nearest)) continue;
    nearest = d;
    // The region the pattern passes stream: the panel's box grown by a
    // quarter of its size (the prediction's error) and the margin.
    const double gu = 0.25 * (u1 - u0) + m, gv = 0.25 * (v1 - v0) + m;
    const int x0 = std::max(0, static_cast<int>(std::floor(u0 - gu)));
    const int y0 = std::max(0, static_cast<int>(std::floor(v0 - gv)));
    const int x1 = std::min(static_cast<int>(w), static_cast<int>(std::ceil(u1 + gu)) + 1);
    const int y1 = std::min(static_cast<int>(h), static_cast<int>(std::ceil(v1 + gv)) + 1);
    best = StationView{static_cast<int>(k), cv::Rect(x0, y0, x1 - x0, y1 - y0)};
  }
  return best;
}

host::CameraConfig Drive::sensor_camera() const {
  const int k = config_.station_fixes.window_scale;
  host::CameraConfig c = config_.camera;
  c.image_width *= k;
  c.image_height *= k;
  c.camera_matrix[0] *= k;
  c.camera_matrix[4] *= k;
  c.camera_matrix[2] = (c.camera_matrix[2] + 0.5) * k - 0.5;
  c.camera_matrix[5] = (c.camera_matrix[5] + 0.5) * k - 0.5;
  return c;
}

void Drive::analyse_station(int index, const StationView& sv, double t0, double tape_latency_s) {
  const int station = sv.station;
  namespace hp = host::pattern;
  const DriveConfig::StationFixes& sf = config_.station_fixes;
  const golden::pattern::PatternGeometry& g = config_.render.pattern_geometry;
  const StationFrame f =
      station_frame(config_.course, stations_[static_cast<std::size_t>(station)], g);
  hp::PoseOptions po = pose_options_for(g);
  // The camera's calibrated noise and blur.
  po.noise_grey = config_.render.render.noise_sigma_grey;
  po.psf_sigma_px = config_.render.render.blur_sigma_px;
  // The pattern's +y in the camera as the filter predicts it; the bars
  // measure it (PatternPose::up_cam), and the fix takes the measured one.
  const golden::CameraView view =
      camera_view(config_.camera, believed(config_.believed_mount), ekf_->pose());
  po.up_cam = (view.world_to_camera * f.axes.col(1)).normalized();
  // The window of the same exposure at the sensor's full resolution where
  // the panel is predicted (the tape frame is binned window_scale times):
  // the sensor's camera with the principal point moved into the window.
  host::CameraConfig window = sensor_camera();
  window.image_width = sv.region.width;
  window.image_height = sv.region.height;
  window.camera_matrix[2] -= sv.region.x;
  window.camera_matrix[5] -= sv.region.y;
  DriveRenderParams rp = config_.render;
  rp.render.noise_seed = config_.render.render.noise_seed * 1000003u + static_cast<uint64_t>(index);
  const PoseTrack& track = track_;
  const cv::Mat crop = render_drive_frame(
      window, config_.course, config_.mount, [&track](double t) { return track.at(t); }, t0,
      config_.exposure_s, rp);
  // The bar-code reader reads the blocks along the image rows: a station
  // seen with its +x pointing left in the image (its +y along the robot's
  // heading under a camera pitched up) may read as its mirror print, its
  // pose then turned 180 deg about the face normal, or not read at all (it
  // depends on the identity). The host analyses the window as it is and,
  // when that gives no code or no bars' fit, turned 180 deg: the camera
  // turned about its optical axis (x, y -> -x, -y: principal point
  // mirrored, tangential distortion negated), the pose brought back to the
  // camera's axes. Both analyses' passes count in the latency.
  const Eigen::Vector3d predicted_y = po.up_cam;
  auto analyse = [&](bool turn, PatternFrameAnalysis& out) {
    host::CameraConfig cam = window;
    hp::PoseOptions o = po;
    cv::Mat img = crop;
    const Eigen::Vector3d flip(turn ? -1.0 : 1.0, turn ? -1.0 : 1.0, 1.0);
    if (turn) {
      cv::rotate(crop, img, cv::ROTATE_180);
      cam.camera_matrix[2] = cam.image_width - 1.0 - cam.camera_matrix[2];
      cam.camera_matrix[5] = cam.image_height - 1.0 - cam.camera_matrix[5];
      cam.distortion_coefficients[2] = -cam.distortion_coefficients[2];
      cam.distortion_coefficients[3] = -cam.distortion_coefficients[3];
      o.up_cam = flip.asDiagonal() * o.up_cam;
    }
    out = analyse_pattern_frame(*pattern_device_, img, config_.render.pattern_radiometry,
                                host::CameraModel(cam), o);
    hp::PatternPose q = out.conic_bars;  // the conic pose refined with the bars
    q.centre_cam = flip.asDiagonal() * q.centre_cam;
    q.normal_cam = flip.asDiagonal() * q.normal_cam;
    if (q.up_cam) q.up_cam = Eigen::Vector3d(flip.asDiagonal() * *q.up_cam);
    return q;
  };
  PatternFrameAnalysis a;
  hp::PatternPose p = analyse(false, a);
  int passes = a.passes;
  if (a.code.status != hp::PatternStatus::ok || !p.up_cam) {
    PatternFrameAnalysis b;
    const hp::PatternPose q = analyse(true, b);
    passes += b.passes;
    if (b.code.status == hp::PatternStatus::ok && q.up_cam) {
      a = std::move(b);
      p = q;
    }
  }
  // A pose whose measured +y points against the predicted one was read
  // turned: the station's mirror identity (when it has one), and its frame
  // turned the same way for the fix.
  const bool turned = p.up_cam && p.up_cam->dot(predicted_y) < 0.0;

  PatternFixRecord r;
  r.frame = index;
  r.station = station;
  r.exposure_s = t0 + 0.5 * config_.exposure_s;
  r.available_s = t0 + config_.exposure_s + tape_latency_s +
                  passes * pass_time_s(sv.region.area()) + sf.host_time_s;
  const CameraWorldPose truth = camera_pose(config_.camera, config_.mount, track_.at(r.exposure_s));
  r.truth = {truth.centre.x(), truth.centre.y(), truth.heading_rad()};
  const int id = stations_[static_cast<std::size_t>(station)].id;
  const int expected = turned ? golden::pattern::mirrored_identity(id).value_or(id) : id;
  r.d_m = p.d_m;
  r.code_read = a.code.status == hp::PatternStatus::ok;
  r.theta_rad = p.theta_rad;
  nav::PatternFix& fix = r.fix;
  fix.time.exposure_s = r.exposure_s;
  fix.time.available_s = r.available_s;
  if (p.status != hp::PatternStatus::ok) {
    r.status = std::string(hp::to_string(p.status));
  } else if (!p.up_cam) {
    r.status = "no_bars";
  } else if (a.code.status == hp::PatternStatus::ok && a.code.identity != expected) {
    r.status = "wrong_identity";
  } else {
    r.status = "ok";
  }
  if (r.status != "ok") {
    fix.status = p.status == hp::PatternStatus::no_pattern ? nav::MeasurementStatus::not_found
                                                           : nav::MeasurementStatus::inconsistent;
  } else {
    const Eigen::Matrix3d axes =
        turned ? Eigen::Matrix3d(f.axes * Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal()) : f.axes;
    const hp::WorldFix w = hp::world_fix(p, axes, f.origin, *p.up_cam);
    // The heading the filter's camera yaw is (CameraWorldPose::heading_rad):
    // the horizontal direction of the camera's forward + down axes, defined
    // at any pitch up to the zenith.
    const Eigen::Vector3d look = w.world_from_camera.col(2) + w.world_from_camera.col(1);
    fix.x_m = w.x_m;
    fix.y_m = w.y_m;
    fix.yaw_rad = std::atan2(look.y(), look.x());
    // The noise model: along and across the horizontal line of sight.
    Eigen::Vector2d u(f.origin.x() - w.x_m, f.origin.y() - w.y_m);
    u = u.norm() > 1e-9 ? Eigen::Vector2d(u.normalized())
                        : Eigen::Vector2d(std::cos(fix.yaw_rad), std::sin(fix.yaw_rad));
    const Eigen::Vector2d v(-u.y(), u.x());
    const double sa = sf.along_sigma_m + sf.along_sigma_per_m * p.d_m;
    const double sc = sf.across_sigma_m + sf.across_sigma_per_m * p.d_m;
    fix.covariance.setZero();
    fix.covariance.topLeftCorner<2, 2>() =
        sa * sa * u * u.transpose() + sc * sc * v * v.transpose();
    fix.covariance(2, 2) = sf.yaw_sigma_rad * sf.yaw_sigma_rad;
  }
  Pending pm;
  pm.kind = Pending::Kind::pattern;
  pm.pattern = fix;
  pm.frame = index;
  pm.record = static_cast<int>(pattern_records_.size());
  pattern_records_.push_back(std::move(r));
  pending_.push_back(pm);
}

void Drive::expose_frame(int index, double t0) {
  const PoseTrack& track = track_;
  const PoseAt pose_at = [&track](double t) { return track.at(t); };
  DriveRenderParams rp = config_.render;
  rp.frame_index = index;  // each frame its own noise
  const cv::Mat frame = render_drive_frame(config_.camera, config_.course, config_.mount, pose_at,
                                           t0, config_.exposure_s, rp);
  const host::FrameOutcome out = navigator_->process(frame);
  if (const std::optional<StationView> sv = station_in_view())
    analyse_station(index, *sv, t0, frame_latency_s(out));
  const host::TapePose& pose = host::navigation_pose(out);
  ++frames_;
  frames_ok_ += pose.status == host::Status::ok;
  exposed_frame_ = index;
  exposed_status_ = std::string(host::to_string(pose.status));
  nav::MeasurementTime time;
  time.exposure_s = t0 + 0.5 * config_.exposure_s;
  time.available_s = t0 + config_.exposure_s + frame_latency_s(out);
  nav::TapeMeasurement m = host::tape_measurement(pose, time, config_.tape_noise);
  // The host measured at the configured ceiling height; the map's height
  // where the camera looks scales the offset (it is proportional to the
  // ceiling above the camera), and the landmarks are measured at that
  // height. The filter's ceiling scale state holds that height's error.
  const CeilingView ceiling = ceiling_view(ekf_->camera_pose(ekf_->state()));
  const double above_cfg = config_.camera.ceiling_above_camera_m();
  const double height_factor = ceiling.map_m / above_cfg;
  if (m.status == nav::MeasurementStatus::ok) {
    m.offset_m *= height_factor;
    m.covariance(1, 1) *= height_factor * height_factor;
    m.covariance(0, 1) *= height_factor;
    m.covariance(1, 0) *= height_factor;
  }
  if (config_.ceiling.flow && m.status == nav::MeasurementStatus::ok &&
      pose.method == std::string_view("runs_centre_line")) {
    track_tape_end(index, frame, out, pose, time);
  } else {
    flow_idle();
  }
  Pending tape;
  tape.m = m;
  tape.frame = index;
  pending_.push_back(tape);
  if (!config_.landmarks || m.status != nav::MeasurementStatus::ok ||
      pose.method != std::string_view("runs_centre_line"))
    return;
  // The junctions and tape ends of the followed tape in view, measured with
  // the ceiling at the map's height (the tape-end detector compares the
  // tape's measured width with its configured one, so scaling its distance
  // afterwards is not the same: docs/navigation.md, "Ceiling height").
  host::CameraConfig at_height = config_.camera;
  at_height.ceiling_height_m = config_.camera.camera_height_m + ceiling.map_m;
  host::TapePose scaled = out.pose;
  scaled.offset_m *= height_factor;
  for (const host::Junction& j : host::detect_junctions(
           out.runs, out.settings, navigator_->camera_model(), at_height, scaled)) {
    if (j.kind == host::JunctionKind::none) continue;
    Pending l;
    l.kind = Pending::Kind::landmark;
    l.frame = index;
    l.landmark.time = time;
    l.landmark.kind = j.kind == host::JunctionKind::tape_end
                          ? nav::LandmarkMeasurement::Kind::tape_end
                          : nav::LandmarkMeasurement::Kind::junction;
    l.landmark.along_m = j.distance_m;
    const double smear = odometry_speed_mps_ * config_.exposure_s;
    l.landmark.variance_m2 =
        j.distance_sigma_m * j.distance_sigma_m + smear * smear / 12.0 +
        config_.landmark_noise.floor_sigma_m * config_.landmark_noise.floor_sigma_m;
    pending_.push_back(l);
  }
}

Drive::CeilingView Drive::ceiling_view(const nav::Pose2& cam) const {
  // The look point: where the optical axis meets the ceiling at the
  // configured height (the zone is what matters).
  const double above_cfg = config_.camera.ceiling_above_camera_m();
  const double p = config_.camera.camera_pitch_deg * std::numbers::pi / 180.0;
  const double reach = std::abs(std::cos(p)) < 1e-9 ? 0.0 : above_cfg / std::tan(p);
  const double x = cam.x_m + reach * std::cos(cam.yaw_rad),
               y = cam.y_m + reach * std::sin(cam.yaw_rad);
  CeilingView v;
  v.zone = map_course_.zone_at(x, y);
  v.map_m = map_course_.ceiling_height_at(x, y) - config_.camera.camera_height_m;
  v.truth_m = config_.course.ceiling_height_at(x, y) - config_.camera.camera_height_m;
  v.estimate_m = ekf_->ceiling_height(v.map_m);
  v.sigma_m = ekf_->ceiling_height_sigma(v.map_m);
  return v;
}

void Drive::submit_flow_fit() {
  // A finished track's fit is one measurement (the fits of a growing track
  // share its frames: only the last counts), taken at its last frame. Its
  // feature lies range_m ahead of the camera there; a feature under another
  // zone than the one the camera looks at (a zone's border) is not used.
  if (flow_fit_ && flow_fit_->status == host::Status::ok &&
      flow_fit_->std_error_m <= 0.02 * flow_fit_->ceiling_above_camera_m) {
    const nav::Pose2 cam = ekf_->camera_pose(ekf_->state());
    const CeilingView look = ceiling_view(cam);
    const double fx = cam.x_m + flow_fit_->range_m * std::cos(cam.yaw_rad);
    const double fy = cam.y_m + flow_fit_->range_m * std::sin(cam.yaw_rad);
    if (map_course_.zone_at(fx, fy) == look.zone) {
      Pending h;
      h.kind = Pending::Kind::height;
      h.frame = flow_frame_;
      h.height.time = flow_time_;
      h.height.height_m = flow_fit_->ceiling_above_camera_m;
      h.height.sigma_m = flow_fit_->std_error_m;
      h.height.used_m = look.map_m;
      h.height.against_odometry = true;
      pending_.push_back(h);
    }
  }
  flow_fit_.reset();
  flow_idle_frames_ = 0;
}

void Drive::flow_idle() {
  // Five frames without the tape end: its track is over.
  if (flow_fit_ && ++flow_idle_frames_ > 5) {
    submit_flow_fit();
    flow_->reset();
  }
}

void Drive::track_tape_end(int index, const cv::Mat& frame, const host::FrameOutcome& out,
                           const host::TapePose& pose, const nav::MeasurementTime& time) {
  // A tape end's flow against the odometry's own dead reckoning (the raw
  // wheel readings: the filter relates the fit to its wheel scale states).
  const std::optional<Eigen::Vector2d> end =
      host::find_tape_end(frame, out.runs, navigator_->camera_model(), config_.camera, pose);
  if (!end) {
    flow_idle();
    return;
  }
  // The camera of the dead-reckoned pose, through the filter's mount.
  const nav::Pose2 o = odometry_track_.at(time.exposure_s);
  nav::State odometry_state = nav::State::Zero();
  odometry_state(nav::state::x) = o.x_m;
  odometry_state(nav::state::y) = o.y_m;
  odometry_state(nav::state::yaw) = o.yaw_rad;
  const nav::Pose2 camera = ekf_->camera_pose(odometry_state);
  // A new track begins with this observation when it does not continue the
  // current one: the previous track is over.
  if (!flow_->add(camera, *end)) submit_flow_fit();
  flow_idle_frames_ = 0;
  const host::FlowFit f = flow_->fit();
  if (f.status == host::Status::ok) {
    flow_fit_ = f;
    flow_time_ = time;
    flow_frame_ = index;
  }
}

bool Drive::step() {
  if (over_) return false;
  const auto wall0 = std::chrono::steady_clock::now();
  const nav::Command cmd = follower_.update(ekf_->pose(), dt_, blind_m_);
  DriveRow row;
  if (cmd.mode == nav::FollowerMode::finished || cmd.mode == nav::FollowerMode::lost ||
      t_ >= t_end_) {
    over_ = true;
  }
  const nav::OdometryStep odo =
      over_ ? robot_.step(dt_, 0.0, 0.0) : robot_.step(dt_, cmd.v_mps, cmd.omega_radps);
  const nav::Pose2 before = track_.at(t_);
  t_ = robot_.time_s();
  track_.add(t_, robot_.pose());
  driven_m_ += std::hypot(robot_.pose().x_m - before.x_m, robot_.pose().y_m - before.y_m);
  ekf_->predict(odo);
  odometry_pose_ = nav::advance(odometry_pose_, nav::motion_of(odo, config_.robot.wheel_base_m));
  odometry_track_.add(t_, odometry_pose_);
  const double travel = std::abs(nav::motion_of(odo, config_.robot.wheel_base_m).distance_m);
  blind_m_ += travel;
  odometry_speed_mps_ = travel / dt_;
  exposed_frame_ = -1;
  exposed_status_.clear();
  if (config_.vision) {
    while (next_frame_ / config_.frame_rate_hz + config_.exposure_s <= t_ + 1e-9) {
      expose_frame(next_frame_, next_frame_ / config_.frame_rate_hz);
      ++next_frame_;
    }
  }
  std::sort(pending_.begin(), pending_.end(),
            [](const Pending& a, const Pending& b) { return a.available_s() < b.available_s(); });
  std::size_t used = 0;
  for (; used < pending_.size() && pending_[used].available_s() <= t_ + 1e-9; ++used) {
    const Pending& pm = pending_[used];
    const nav::Outcome o = pm.kind == Pending::Kind::landmark  ? ekf_->update(pm.landmark)
                           : pm.kind == Pending::Kind::pattern ? ekf_->update(pm.pattern)
                           : pm.kind == Pending::Kind::height  ? ekf_->update(pm.height)
                                                               : ekf_->update(pm.m);
    // A landmark's or height's outcome shows when it was accepted, else the
    // tape's does; a pattern fix's always does.
    if ((pm.kind == Pending::Kind::landmark || pm.kind == Pending::Kind::height) &&
        o != nav::Outcome::accepted)
      continue;
    row.frame = pm.frame;
    row.outcome = outcome_name(o);
    if (pm.kind == Pending::Kind::landmark) row.outcome += "_landmark";
    if (pm.kind == Pending::Kind::height) row.outcome += "_height";
    if (pm.kind == Pending::Kind::pattern) {
      row.outcome += "_pattern";
      row.station = pattern_records_[static_cast<std::size_t>(pm.record)].station;
      pattern_records_[static_cast<std::size_t>(pm.record)].outcome = outcome_name(o);
    }
    if (pm.kind == Pending::Kind::tape && o == nav::Outcome::accepted) blind_m_ = 0.0;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(used));

  row.t_s = t_;
  row.truth = robot_.pose();
  row.estimate = ekf_->pose();
  const nav::Covariance& p = ekf_->covariance();
  row.sigma_x_m = std::sqrt(p(nav::state::x, nav::state::x));
  row.sigma_y_m = std::sqrt(p(nav::state::y, nav::state::y));
  row.sigma_yaw_rad = std::sqrt(p(nav::state::yaw, nav::state::yaw));
  row.v_cmd_mps = cmd.v_mps;
  row.omega_cmd_radps = cmd.omega_radps;
  row.mode = cmd.mode;
  row.leg = cmd.leg;
  const auto li = static_cast<std::size_t>(
      std::min<int>(cmd.leg, static_cast<int>(plan_.waypoints.size()) - 2));
  const nav::LineError truth_err =
      nav::line_error(robot_.pose(), plan_.waypoints[li], plan_.waypoints[li + 1]);
  row.lateral_error_m = truth_err.lateral_m;
  row.heading_error_rad = truth_err.heading_rad;
  row.pose_nees = ekf_->pose_nees(robot_.pose());
  row.left_scale_error = ekf_->state()(nav::state::left_scale);
  row.right_scale_error = ekf_->state()(nav::state::right_scale);
  row.yaw_scale_error = ekf_->state()(nav::state::yaw_scale);
  row.distance_m = driven_m_;
  row.blind_m = blind_m_;
  const CeilingView cv = ceiling_view(ekf_->camera_pose(ekf_->state()));
  row.ceiling_est_m = cv.estimate_m;
  row.ceiling_sigma_m = cv.sigma_m;
  row.ceiling_map_m = cv.map_m;
  row.ceiling_true_m = cv.truth_m;
  if (exposed_frame_ >= 0 && row.frame < 0) row.frame_status = exposed_status_;
  if (exposed_frame_ >= 0) row.frame_status = exposed_status_;
  rows_.push_back(std::move(row));
  wall_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return !over_;
}

void Drive::run(const std::function<void(double, double)>& progress) {
  int last = -1;
  while (step()) {
    if (progress && next_frame_ != last) {
      last = next_frame_;
      progress(driven_m_, plan_.length_m);
    }
  }
  if (progress) progress(driven_m_, plan_.length_m);
}

DriveSummary Drive::summary() const {
  DriveSummary s;
  s.course = config_.course.name;
  s.backend = config_.backend;
  s.route_length_m = plan_.length_m;
  s.driven_m = driven_m_;
  s.sim_time_s = t_;
  s.finished = follower_.mode() == nav::FollowerMode::finished;
  s.lost = follower_.mode() == nav::FollowerMode::lost;
  s.frames = frames_;
  s.frames_ok = frames_ok_;
  double ss_lat = 0.0, ss_head = 0.0;
  int n = 0, in_band = 0;
  const double lo = nav::chi_square_quantile(0.025, 3.0), hi = nav::chi_square_quantile(0.975, 3.0);
  for (const DriveRow& r : rows_) {
    if (r.pose_nees >= lo && r.pose_nees <= hi) ++in_band;
    if (r.mode != nav::FollowerMode::follow) continue;
    ++n;
    ss_lat += r.lateral_error_m * r.lateral_error_m;
    ss_head += r.heading_error_rad * r.heading_error_rad;
    s.lateral_max_m = std::max(s.lateral_max_m, std::abs(r.lateral_error_m));
  }
  if (n > 0) {
    s.lateral_rms_m = std::sqrt(ss_lat / n);
    s.heading_rms_rad = std::sqrt(ss_head / n);
  }
  if (!rows_.empty())
    s.nees_in_band = static_cast<double>(in_band) / static_cast<double>(rows_.size());
  // A junction is taken when the robot passed within 5 cm of it and drove on
  // onto the leg after it.
  s.junctions_planned = static_cast<int>(plan_.junctions.size());
  for (const RouteJunction& j : plan_.junctions) {
    bool near = false, beyond = false;
    for (const DriveRow& r : rows_) {
      near |= std::hypot(r.truth.x_m - j.position.x(), r.truth.y_m - j.position.y()) <= 0.05;
      beyond |= near && r.leg >= j.waypoint && r.mode == nav::FollowerMode::follow;
    }
    s.junctions_taken += near && beyond;
  }
  // Gaps whose middle lies on the route; crossed when the robot passed
  // within 5 cm of the middle.
  for (const TapePolyline& t : config_.course.tapes) {
    for (const auto& [g0, g1] : t.gaps_m) {
      const Eigen::Vector2d mid = point_at_arc(t, 0.5 * (g0 + g1));
      if (distance_to_path(plan_.waypoints, mid) > 0.05) continue;
      ++s.gaps_on_route;
      bool crossed = false;
      for (const DriveRow& r : rows_)
        crossed |= std::hypot(r.truth.x_m - mid.x(), r.truth.y_m - mid.y()) <= 0.05;
      s.gaps_crossed += crossed;
    }
  }
  s.counters = ekf_->counters();
  // The ceiling height where the camera looks: relative errors of the
  // estimate and of the map over the ticks.
  double ss_c = 0.0, ss_map = 0.0;
  for (const DriveRow& r : rows_) {
    const double e = r.ceiling_est_m / r.ceiling_true_m - 1.0;
    ss_c += e * e;
    ss_map += std::pow(r.ceiling_map_m / r.ceiling_true_m - 1.0, 2);
    s.ceiling_error_max = std::max(s.ceiling_error_max, std::abs(e));
  }
  if (!rows_.empty()) {
    s.ceiling_error_rms = std::sqrt(ss_c / static_cast<double>(rows_.size()));
    s.ceiling_map_error_rms = std::sqrt(ss_map / static_cast<double>(rows_.size()));
  }
  for (std::size_t k = 0; k < stations_.size(); ++k) {
    DriveSummary::Station st;
    st.id = stations_[k].id;
    for (const PatternFixRecord& r : pattern_records_) {
      if (r.station != static_cast<int>(k)) continue;
      ++st.frames_analysed;
      st.fixes_ok += r.status == "ok";
      st.fixes_accepted += r.outcome == "accepted";
    }
    auto error = [](const DriveRow& r) {
      return std::hypot(r.truth.x_m - r.estimate.x_m, r.truth.y_m - r.estimate.y_m);
    };
    bool first = true;
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const DriveRow& r = rows_[i];
      if (r.station != static_cast<int>(k) || r.outcome != "accepted_pattern") continue;
      if (first) st.error_before_m = error(rows_[i > 0 ? i - 1 : 0]);
      first = false;
      st.error_after_m = error(r);
    }
    s.stations.push_back(st);
  }
  if (!rows_.empty()) {
    const DriveRow& r = rows_.back();
    s.final_position_error_m =
        std::hypot(r.truth.x_m - r.estimate.x_m, r.truth.y_m - r.estimate.y_m);
    s.final_position_sigma_m = std::hypot(r.sigma_x_m, r.sigma_y_m);
    s.final_pose_nees = r.pose_nees;
  }
  s.wall_time_s = wall_s_;
  s.realtime_factor = wall_s_ > 0.0 ? t_ / wall_s_ : 0.0;
  return s;
}

void write_trajectory_csv(const std::string& path, const std::vector<DriveRow>& rows) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write " + tmp);
    f << "t_s,x_m,y_m,yaw_rad,est_x_m,est_y_m,est_yaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,"
         "v_cmd_mps,omega_cmd_radps,mode,leg,lateral_error_m,heading_error_rad,pose_nees,"
         "distance_m,blind_m,frame_status,applied_frame,outcome,left_scale_error,right_scale_error,"
         "yaw_scale_error,ceiling_est_m,ceiling_sigma_m,ceiling_map_m,ceiling_true_m\n";
    for (const DriveRow& r : rows) {
      f << fmt::format(
          "{:.4f},{:.6f},{:.6f},{:.7f},{:.6f},{:.6f},{:.7f},{:.3e},{:.3e},{:.3e},"
          "{:.4f},{:.5f},{},{},{:.3e},{:.3e},{:.4g},{:.4f},{:.4f},{},{},{},{:.5f},{:.5f},{:.5f},"
          "{:.5f},{:.3e},{:.5f},{:.5f}\n",
          r.t_s, r.truth.x_m, r.truth.y_m, r.truth.yaw_rad, r.estimate.x_m, r.estimate.y_m,
          r.estimate.yaw_rad, r.sigma_x_m, r.sigma_y_m, r.sigma_yaw_rad, r.v_cmd_mps,
          r.omega_cmd_radps, nav::to_string(r.mode), r.leg, r.lateral_error_m, r.heading_error_rad,
          r.pose_nees, r.distance_m, r.blind_m, r.frame_status,
          r.frame >= 0 ? std::to_string(r.frame) : "", r.outcome, r.left_scale_error,
          r.right_scale_error, r.yaw_scale_error, r.ceiling_est_m, r.ceiling_sigma_m,
          r.ceiling_map_m, r.ceiling_true_m);
    }
    if (!f.flush()) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace ceilnav::sim
