#include "host/navigator.hpp"

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace ceilnav::host {

Navigator::Navigator(const CameraConfig& camera, std::unique_ptr<FrameProcessor> device,
                     const NavigatorOptions& options)
    : camera_(camera), model_(camera), options_(options), device_(std::move(device)) {
  if (!device_) throw std::invalid_argument("navigator: no device");
}

stream::FrameResults Navigator::run_pipeline(const cv::Mat& grey, const ThresholdSettings& s,
                                             std::vector<stream::RunRecord>& runs,
                                             uint64_t& cycles) {
  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(grey.cols);
  cfg.height = static_cast<uint16_t>(grey.rows);
  cfg.min_run_length = options_.min_run_length;
  cfg.max_runs_per_row = options_.max_runs_per_row;
  cfg.hist_source_remap = false;
  cfg = apply_threshold(cfg, s);
  return device_->process(grey, cfg, runs, cycles);
}

void Navigator::apply_track(TapePose& pose) {
  if (pose.status != Status::ok) {
    track_.reset();  // lost: the next ok frame locks
    return;
  }
  if (track_) {
    const double dyaw = std::abs(pose.yaw_rad - track_->yaw_rad) * 180.0 / std::numbers::pi;
    const double doff = std::abs(pose.offset_m - track_->offset_m);
    if (dyaw > options_.track.max_yaw_step_deg || doff > options_.track.max_offset_step_m) {
      pose.status = Status::jump;
      pose.yaw_rad = pose.offset_m = 0.0;
      track_.reset();
      return;
    }
  }
  track_ = pose;
}

FrameOutcome Navigator::process(const cv::Mat& grey) {
  if (grey.type() != CV_8UC1 || grey.cols != camera_.image_width ||
      grey.rows != camera_.image_height) {
    throw std::invalid_argument("navigator: frame must be 8-bit grey " +
                                std::to_string(camera_.image_width) + "x" +
                                std::to_string(camera_.image_height));
  }
  FrameOutcome out;
  ThresholdSettings settings = previous_.value_or(ThresholdSettings{});
  ThresholdSettings fresh;  // from this frame's histogram (of the camera grey: same every pass)
  for (int pass = 1; pass <= 2; ++pass) {
    out.results = run_pipeline(grey, settings, out.runs, out.cycles);
    out.settings = settings;
    out.passes = pass;
    fresh = choose_threshold(out.results.histogram, options_.threshold);
    const bool first = !previous_.has_value();
    const bool stale = first ||
                       std::abs(static_cast<int>(fresh.threshold) - settings.threshold) >
                           options_.threshold_tolerance_grey ||
                       std::abs(static_cast<int>(fresh.background_level) -
                                settings.background_level) > options_.threshold_tolerance_grey;
    const bool reprogram = first || options_.threshold_policy != ThresholdPolicy::first_frame;
    const bool rerun = first || options_.threshold_policy == ThresholdPolicy::previous_frame_rerun;
    if (reprogram) previous_ = fresh;
    if (!stale || !rerun || pass == 2) break;
    settings = fresh;
  }

  if (!out.results.valid) {
    out.pose.status = Status::frame_invalid;
    return out;
  }
  // Saturated frame: the background (median grey) is at full scale, so no
  // threshold can rise above it and the mask is the background itself.
  if (fresh.threshold <= fresh.background_grey) {
    out.pose.status = Status::no_tape;
    return out;
  }
  out.pose = estimate_tape_pose(out.runs, model_, camera_, options_.pose);
  // Contrast of the compared runs (evidence, reported, not gated: an
  // over-exposed ceiling with the tape 1.7 sigma above it still gives the pose
  // within the bar, docs/scene_faults.md). Weight per run pixel = grey - background_level.
  TapeEvidence& ev = out.pose.evidence;
  if (ev.width_sampled > 0 && fresh.noise_sigma_grey > 0.0) {
    ev.contrast_sigma =
        (ev.run_weight_median + out.settings.background_level - fresh.background_grey) /
        fresh.noise_sigma_grey;
  }
  if (options_.track.enabled) apply_track(out.pose);
  if (camera_.camera_pitch_deg >= 89.999) {
    out.zenith =
        zenith_pose_from_moments(out.results.moments, model_, camera_, true, options_.zenith);
  }
  return out;
}

const TapePose& navigation_pose(const FrameOutcome& out) {
  if (out.pose.status != Status::ok && out.zenith && out.zenith->status == Status::ok)
    return *out.zenith;
  return out.pose;
}

}  // namespace ceilnav::host
