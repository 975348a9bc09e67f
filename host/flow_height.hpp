// Ceiling height above the camera from the image flow of one ceiling feature
// while the robot travels a known distance (seed 000, eq. 5, 44, 57), and a
// trackable feature for it: the end of the tape at a gap.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/status.hpp"
#include "host/tape_pose.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::host {

struct HeightEstimate {
  Status status = Status::degenerate;
  double ceiling_above_camera_m = 0.0;
  double range_m =
      0.0;  // horizontal distance of the feature ahead of the camera at frame 1 (eq. 57)
};

// A ceiling feature seen at undistorted normalised rows v1_norm, v2_norm (y down)
// before and after the camera moved distance_m horizontally in a direction at
// motion_angle_rad from its heading (0: straight ahead; moving along the tape
// with yaw psi: -psi). With g(y) = (cos p + y sin p) / (sin p - y cos p) = w / c,
//   c = distance_m cos(motion_angle) / (g(v1) - g(v2)),
// which for p < 90 deg equals eq. 44 with v' = tan p - y, and for p = 90 deg is
// eq. 5, c = d / d'. Valid for pitch in (0, 90]. degenerate: non-finite input,
// no forward motion, a row at or below the horizon, no parallax, c <= 0.
HeightEstimate ceiling_height_from_flow(double v1_norm, double v2_norm, double pitch_rad,
                                        double distance_m, double motion_angle_rad = 0.0);

struct TapeEndOptions {
  double max_residual_px = 2.0;       // run centre to centre line, plus half the run width
  int min_rows = 6;                   // rows of tape before the end
  int reference_rows = 8;             // full rows used to extrapolate the full-row mass
  double min_visible_width_px = 2.0;  // narrower expected tape: a fade, not an end
  // Grey variant only: the window around the centre line (the widest reference
  // run plus this each side), the background pixels beyond it, and the rows
  // past the last run that the blurred end still reaches.
  double grey_margin_px = 3.0;
  int grey_background_px = 4;
  int tail_rows = 3;
};

// The end of the tape where it stops at a gap, in undistorted normalised
// coordinates: walking the rows of the centre line `pose.line_norm` from the
// top of the image, the first place where the chain of tape runs stops inside
// the image while the tape would still be visibly wide. The row is sub-pixel:
// the end lies at the last full row's lower boundary plus the sum over the end
// rows of (run mass / extrapolated full-row mass), which puts a straight cut at
// its centre-line crossing whatever its tilt. nullopt if there is no such end.
std::optional<Eigen::Vector2d> find_tape_end(std::span<const stream::RunRecord> runs,
                                             const CameraModel& cam, const CameraConfig& cfg,
                                             const TapePose& pose, const TapeEndOptions& opt = {});
// The same end with the row masses taken from the grey frame (grey minus the
// local background in a window around the centre line) instead of the runs:
// the rows of the blurred end below the threshold count too, which removes the
// threshold's bias towards the tape (docs/host_maths.md section 6a).
std::optional<Eigen::Vector2d> find_tape_end(const cv::Mat& grey,
                                             std::span<const stream::RunRecord> runs,
                                             const CameraModel& cam, const CameraConfig& cfg,
                                             const TapePose& pose, const TapeEndOptions& opt = {});

// Ceiling height above the camera from the tape's image width, without any
// odometry: along a row of the image the tape's two edges are
//   dx = W (sin p - y cos p) / (c cos psi)
// apart (undistorted normalised x, W = the configured tape width, psi = the
// yaw to the tape), so c = W (sin p - y cos p) / (dx cos psi). dx comes from the
// grey frame, per row of the tape's runs on the centre line: the tape's mass
// (sum of grey minus the local background over the run and a margin) divided by
// its plateau (mean grey minus background of the pixels well inside the tape),
// which neither the threshold nor the blur biases; the pixel width is turned
// into dx with the undistortion's local Jacobian and the centre line's normal.
// The frame's value is the mean of the rows within 3 MADs of their median.
struct WidthHeightOptions {
  double max_residual_px = 2.0;   // run centre to centre line, plus half the run width
  double min_width_px = 7.0;      // narrower tape has no plateau: row skipped
  double plateau_inset_px = 2.5;  // plateau pixels at least this far inside an edge
  int margin_px = 3;              // mass window: the tape's edges +- this
  int background_px = 4;          // background: this many pixels beyond each margin
  int min_rows = 10;
};
struct WidthHeight {
  Status status = Status::degenerate;  // degenerate: fewer than min_rows rows measured
  double ceiling_above_camera_m = 0.0;
  double std_error_m = 0.0;  // of the mean, from the rows' scatter
  int rows = 0;
};
WidthHeight ceiling_height_from_tape_width(const cv::Mat& grey,
                                           std::span<const stream::RunRecord> runs,
                                           const CameraModel& cam, const CameraConfig& cfg,
                                           const TapePose& pose,
                                           const WidthHeightOptions& opt = {});

// The robot's planar pose from odometry (x forward, y left, yaw CCW), with the
// camera at its origin and looking along its heading: the navigation layer's.
using PlanarPose = nav::Pose2;

// One ceiling feature seen over several frames while the robot moves: the
// least-squares ceiling height from the whole track. Frame k sees the feature
// at undistorted normalised (x_k, y_k); the feature then lies c q_k from the
// camera in the heading frame, q_k = (g(y_k), -x_k / (sin p - y_k cos p))
// (forward, left; eq. 44's geometry, docs/host_maths.md), so with the odometry
// poses P_k, psi_k:  P_k + c R(psi_k) q_k = F  for the unknown feature F. The
// fit solves for (c, F) by weighted linear least squares, weights
// (sin p - y_k cos p)^4 (the inverse variance of g(y_k) for a constant row
// noise). Needs >= 3 frames and >= min_travel_m between the first and last.
struct FlowTrackOptions {
  int min_frames = 3;
  double min_travel_m = 0.3;
  // A new observation joins the track when the feature position it implies
  // (with the configured height) is within gate_m + gate_fraction * range of
  // the one the previous observation implies.
  double gate_m = 0.05;
  double gate_fraction = 0.02;
};
struct FlowFit {
  Status status = Status::degenerate;
  double ceiling_above_camera_m = 0.0;
  double range_m = 0.0;  // horizontal distance ahead of the camera at the last frame (eq. 57)
  double std_error_m = 0.0;
  int frames = 0;
  double travel_m = 0.0;
};

class FlowTrack {
 public:
  FlowTrack(double pitch_rad, double configured_ceiling_m, const FlowTrackOptions& opt = {})
      : pitch_(pitch_rad), c0_(configured_ceiling_m), opt_(opt) {}
  // Adds the feature seen at `feature_norm` from `pose`; starts a new track
  // when it does not continue the current one (returns true if it did).
  bool add(const PlanarPose& pose, const Eigen::Vector2d& feature_norm);
  void reset() { obs_.clear(); }
  FlowFit fit() const;
  int size() const { return static_cast<int>(obs_.size()); }

 private:
  struct Obs {
    PlanarPose pose;
    Eigen::Vector2d q;  // c q = the feature in the heading frame (forward, left)
    double weight;
  };
  double pitch_, c0_;
  FlowTrackOptions opt_;
  std::vector<Obs> obs_;
};

}  // namespace ceilnav::host
