#include "apps/odometry_height.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace ceilnav::app {
namespace {
// Tracks whose height has a larger relative standard error do not count
// towards the odometry scale (a short track, or a feature that is not fixed).
constexpr double kMaxRelativeError = 0.02;
}  // namespace

OdometryHeight::OdometryHeight(const host::CameraConfig& camera)
    : camera_(camera),
      track_(camera.camera_pitch_deg * std::numbers::pi / 180.0, camera.ceiling_above_camera_m()) {}

void OdometryHeight::close_track() {
  if (current_) closed_.push_back(*current_);
  current_.reset();
}

OdometryColumns OdometryHeight::add(const nav::Pose2& pose, const cv::Mat& grey,
                                    const host::FrameOutcome& r, const host::CameraModel& cam) {
  OdometryColumns out;
  if (!r.results.valid || r.pose.status != host::Status::ok) return out;
  const host::WidthHeight w =
      host::ceiling_height_from_tape_width(grey, r.runs, cam, camera_, r.pose);
  if (w.status == host::Status::ok) {
    out.width_ceiling_m = w.ceiling_above_camera_m;
    width_sum_ += w.ceiling_above_camera_m;
    ++width_n_;
  }
  if (const auto end = host::find_tape_end(grey, r.runs, cam, camera_, r.pose)) {
    if (!track_.add({pose.x_m, pose.y_m, pose.yaw_rad}, *end)) close_track();
    const host::FlowFit f = track_.fit();
    if (f.status == host::Status::ok) {
      current_ = f;
      out.flow_ceiling_m = f.ceiling_above_camera_m;
      out.flow_ceiling_se_m = f.std_error_m;
      out.flow_range_m = f.range_m;
      out.flow_frames = f.frames;
    }
  }
  out.odometry_scale = summary().odometry_scale;
  return out;
}

OdometryHeightSummary OdometryHeight::summary() const {
  OdometryHeightSummary s;
  s.width_frames = width_n_;
  if (width_n_ > 0) s.width_ceiling_m = width_sum_ / width_n_;
  std::vector<host::FlowFit> fits = closed_;
  if (current_) fits.push_back(*current_);
  double sw = 0.0, swc = 0.0;
  for (const host::FlowFit& f : fits) {
    // A track counts when its fit is within 2 % (standard error); then by inverse variance
    if (!(f.std_error_m <= kMaxRelativeError * f.ceiling_above_camera_m)) continue;
    ++s.tracks;
    // Inverse variance, with a floor of 0.1 % of c on the standard error.
    const double se = std::max(f.std_error_m, 1e-3 * f.ceiling_above_camera_m);
    sw += 1.0 / (se * se);
    swc += f.ceiling_above_camera_m / (se * se);
  }
  if (sw > 0.0) s.flow_ceiling_m = swc / sw;
  if (s.tracks > 0 && width_n_ > 0) s.odometry_scale = s.flow_ceiling_m / s.width_ceiling_m;
  return s;
}

std::vector<double> frame_times(const std::vector<std::string>& frames,
                                const std::string& frame_times_file, double fps,
                                const nav::OdometryTrack& odometry) {
  std::vector<double> t(frames.size());
  if (!frame_times_file.empty()) {
    std::map<std::string, double> by_name;
    for (const nav::FrameTime& ft : nav::load_frame_times(frame_times_file)) {
      by_name[ft.frame] = ft.t_s;
    }
    for (size_t i = 0; i < frames.size(); ++i) {
      const auto it = by_name.find(frames[i]);
      if (it == by_name.end()) {
        throw nav::OdometryFileError(frame_times_file + ": no time for frame '" + frames[i] + "'");
      }
      t[i] = it->second;
    }
  } else {
    if (!(fps > 0.0) || !std::isfinite(fps)) {
      throw nav::OdometryFileError("--odometry needs --frame-times FILE or --fps F > 0");
    }
    for (size_t i = 0; i < frames.size(); ++i) t[i] = static_cast<double>(i) / fps;
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    if (!odometry.covers(t[i])) {
      throw nav::OdometryFileError("frame '" + frames[i] + "' at t = " + std::to_string(t[i]) +
                                   " s is outside the odometry's span [" +
                                   std::to_string(odometry.t_begin()) + ", " +
                                   std::to_string(odometry.t_end()) + "] s");
    }
  }
  return t;
}

}  // namespace ceilnav::app
