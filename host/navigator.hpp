// The host's per-frame loop on the device: program the threshold LUT from
// the histogram, stream the frame through the pipeline, collect the runs and
// turn them into a pose.
//
// Threshold policy — seed 000's histogram correction table: the LUT is
// reprogrammed between frames from the previous frame's histogram, so the
// threshold and the run-weight background follow the exposure (a camera
// stream changes slowly). With ThresholdPolicy::previous_frame_rerun (the
// default), if this frame's own histogram asks for a threshold that differs by
// more than `threshold_tolerance_grey` (or on the first frame), the frame is
// processed again with the new settings — a second pass, counted in
// FrameOutcome::passes. Measured on exposure steps of x0.5-x2 between frames
// (`ceilnav exposure`) in docs/results.md.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "common/camera_config.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "host/auto_threshold.hpp"
#include "host/camera_model.hpp"
#include "host/frame_processor.hpp"
#include "host/tape_pose.hpp"

namespace ceilnav::host {

// When the LUT is reprogrammed from a histogram. Every policy processes the
// first frame twice (there is no earlier histogram to program it from).
enum class ThresholdPolicy {
  first_frame,           // chosen on the first frame, then fixed (no correction table)
  previous_frame,        // seed 000: from the previous frame's histogram, one pass
  previous_frame_rerun,  // ... and a second pass when this frame's own histogram disagrees
};

// Continuity with the previous frame (off by default: a folder of frames is
// not always one sequence, e.g. `ceilnav render --random-poses`). While a
// track is held (the previous frame was ok), a centre-line pose whose yaw or
// offset moved more than the robot can between two frames is `jump`, and the
// track is dropped: the next ok frame locks again, as does the first frame.
// Tunables from the robot: max_yaw_step_deg = turn rate x frame interval
// (90 deg/s at 30 frames/s: 3 deg; with margin 5), max_offset_step_m = lateral
// speed x frame interval (1.5 m/s at 30 frames/s: 0.05 m; with margin 0.1).
struct TrackOptions {
  bool enabled = false;
  double max_yaw_step_deg = 5.0;
  double max_offset_step_m = 0.1;
};

struct NavigatorOptions {
  ThresholdOptions threshold;
  ThresholdPolicy threshold_policy = ThresholdPolicy::previous_frame_rerun;
  TapePoseOptions pose;
  ZenithOptions zenith;
  TrackOptions track;
  int threshold_tolerance_grey = 4;  // tunable: re-run a frame when the threshold moves more
  uint16_t min_run_length = 2;       // tunable: single-pixel runs are noise
  uint16_t max_runs_per_row = 16;
};

struct FrameOutcome {
  stream::FrameResults results;         // the device's result registers for the frame
  std::vector<stream::RunRecord> runs;  // the runs read from the run stream
  ThresholdSettings settings;           // settings the frame was processed with
  int passes = 0;                       // 1, or 2 when the threshold was re-chosen
  uint64_t cycles = 0;                  // bus backends: device clock cycles spent on the frame
  TapePose pose;                        // the centre-line method (every pitch)
  std::optional<TapePose> zenith;       // the moments method, when the pitch is 90 deg
};

// The pose a navigation filter takes from a frame: the centre line when it is
// ok (it undistorts the run centres and is the more precise at every pitch,
// the zenith included: docs/host_maths.md section 5), else the zenith
// moments' pose when that is ok, else the centre line's (not ok) status.
const TapePose& navigation_pose(const FrameOutcome& out);

class Navigator {
 public:
  // `device` runs the frames: drivers::make_device() for one of the
  // simulated backends, or a program's own FrameProcessor on hardware.
  Navigator(const CameraConfig& camera, std::unique_ptr<FrameProcessor> device,
            const NavigatorOptions& options = {});

  // `grey` must be CV_8UC1 of the configured size (std::invalid_argument otherwise).
  FrameOutcome process(const cv::Mat& grey);

  const CameraConfig& camera() const { return camera_; }
  const CameraModel& camera_model() const { return model_; }
  const NavigatorOptions& options() const { return options_; }

 private:
  // Tracking (TrackOptions): `jump` when the pose left the held track.
  void apply_track(TapePose& pose);
  stream::FrameResults run_pipeline(const cv::Mat& grey, const ThresholdSettings& s,
                                    std::vector<stream::RunRecord>& runs, uint64_t& cycles);

  CameraConfig camera_;
  CameraModel model_;
  NavigatorOptions options_;
  std::unique_ptr<FrameProcessor> device_;
  std::optional<ThresholdSettings> previous_;
  std::optional<TapePose> track_;  // the previous frame's pose while it was ok (tracking)
};

}  // namespace ceilnav::host
