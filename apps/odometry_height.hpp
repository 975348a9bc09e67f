// Ceiling height from measured odometry for `ceilnav run --odometry`: per frame,
// the tape end at a gap tracked over the frames with the odometry poses
// (host::FlowTrack, seed 000 eq. 44, 57), the odometry-free height from the
// tape's image width (host::ceiling_height_from_tape_width), and from the two
// the odometry's scale over the drive (docs/host_maths.md section 6a).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "apps/results_csv.hpp"
#include "host/flow_height.hpp"
#include "host/navigator.hpp"
#include "nav/odometry.hpp"

namespace ceilnav::app {

struct OdometryHeightSummary {
  int width_frames = 0;
  double width_ceiling_m = 0.0;  // mean over the frames
  int tracks = 0;                // tape-end tracks whose fit has a standard error <= 2 % of c
  double flow_ceiling_m = 0.0;   // inverse-variance mean of the tracks' fits
  std::optional<double> odometry_scale;
};

class OdometryHeight {
 public:
  explicit OdometryHeight(const host::CameraConfig& camera);
  // One frame, in time order: `pose` is the odometry's pose at its exposure.
  OdometryColumns add(const nav::Pose2& pose, const cv::Mat& grey,
                      const host::FrameOutcome& outcome, const host::CameraModel& cam);
  OdometryHeightSummary summary() const;

 private:
  void close_track();

  host::CameraConfig camera_;
  host::FlowTrack track_;
  std::optional<host::FlowFit> current_;  // the current track's latest fit
  std::vector<host::FlowFit> closed_;     // fits of finished tracks
  double width_sum_ = 0.0;
  int width_n_ = 0;
};

// The exposure times of `frames` (PNG file names, processing order): from the
// frame-time file when `frame_times_file` is set, else frame i at i / fps.
// Throws nav::OdometryFileError when a frame has no time or a time lies
// outside the odometry's span.
std::vector<double> frame_times(const std::vector<std::string>& frames,
                                const std::string& frame_times_file, double fps,
                                const nav::OdometryTrack& odometry);

}  // namespace ceilnav::app
