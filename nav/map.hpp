// The host's view of a ceiling course: its tape lines as world segments, and
// the association of a tape measurement with one of them (docs/navigation.md,
// "Fusion filter", association rule). Built by whoever loads a course file.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/measurement.hpp"
#include "nav/odometry_step.hpp"

namespace ceilnav::nav {

// A straight piece of tape on the ceiling, world XY of its centre line's end
// points (undirected: a tape can be followed either way).
struct TapeSegment {
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::UnitX();
  double width_m = 0.05;
};

// What a tape measurement predicts for a camera pose (x, y, yaw in the world):
// h = (wrap(yaw - d), n . (p - a)) for the direction d = phi + branch * pi
// (phi: the direction a -> b), n = (-sin d, cos d) the left normal; and
// H = dh / d(x, y, yaw).
struct TapePrediction {
  int branch = 0;  // 0: along a -> b, 1: along b -> a
  Eigen::Vector2d h = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> jacobian = Eigen::Matrix<double, 2, 3>::Zero();
};

// The branch whose predicted yaw is nearest the measured one (the zenith
// ambiguity and the undirected segment resolved by the prediction).
TapePrediction predict_tape(const TapeSegment& segment, const Pose2& camera,
                            double measured_yaw_rad);

// The innovation z - h (yaw wrapped to [-pi, pi)).
Eigen::Vector2d tape_innovation(const TapeMeasurement& m, const TapePrediction& p);

struct AssociationOptions {
  // A segment could be in view when its distance from the camera's floor
  // position is at most view_radius_m plus gate_sigmas position standard
  // deviations (sqrt of the largest eigenvalue of the camera's xy covariance).
  double view_radius_m = 2.0;
  double gate_sigmas = 3.0;
};

struct Association {
  int segment = -1;
  TapePrediction prediction;
  Eigen::Vector2d innovation = Eigen::Vector2d::Zero();
  Eigen::Matrix2d innovation_covariance = Eigen::Matrix2d::Identity();  // H P H^T + R
  double mahalanobis2 = 0.0;  // innovation^T S^-1 innovation
};

// A point of the map a LandmarkMeasurement can name: a tape end (either end
// of a gap, or of a tape) or a junction, with the directions of the tape
// through it (unit vectors, one per tape direction at the point).
struct Landmark {
  LandmarkMeasurement::Kind kind = LandmarkMeasurement::Kind::tape_end;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
};

class TapeMap {
 public:
  TapeMap() = default;
  explicit TapeMap(std::vector<TapeSegment> segments) : segments_(std::move(segments)) {}

  void add(const TapeSegment& s) { segments_.push_back(s); }
  const std::vector<TapeSegment>& segments() const { return segments_; }
  void add_landmark(const Landmark& l) { landmarks_.push_back(l); }
  const std::vector<Landmark>& landmarks() const { return landmarks_; }
  // The direction along which a camera at `camera` facing `yaw` measures the
  // distance to `point`: the direction (either way) of the segment nearest
  // the point that is closest to the yaw; nullopt without a segment within
  // `reach_m` of the point.
  std::optional<Eigen::Vector2d> along_direction(const Eigen::Vector2d& point, double yaw_rad,
                                                 double reach_m = 0.1) const;

  // The segment (and branch) with the smallest squared Mahalanobis innovation
  // among the segments that could be in view of the predicted camera pose
  // (x, y, yaw; covariance `camera_cov`); nullopt when none could be (the
  // measurement is unassociated). The gate is the caller's (the filter's).
  std::optional<Association> associate(const TapeMeasurement& m, const Pose2& camera,
                                       const Eigen::Matrix3d& camera_cov,
                                       const AssociationOptions& opt = {}) const;

 private:
  std::vector<TapeSegment> segments_;
  std::vector<Landmark> landmarks_;
};

// Distance from p to the segment [a, b].
double distance_to_segment(const Eigen::Vector2d& p, const TapeSegment& s);

}  // namespace ceilnav::nav
