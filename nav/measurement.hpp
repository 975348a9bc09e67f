// The measurement contract between the estimators (host/) and the navigation
// filter (BRIEF section 7): what one frame concludes, its covariance, when its
// frame was exposed, when the result became available, and a status. An
// estimator never sees the robot's state; the filter never sees pixels.
// Frames and signs: docs/navigation.md, "Measurement contract".
#pragma once

#include <Eigen/Core>

namespace ceilnav::nav {

// Outcome of the estimator for this frame. Only `ok` measurements carry a
// quantity; the filter counts the others and does not use them.
enum class MeasurementStatus {
  ok,
  not_found,     // nothing to measure in the frame (no tape, no pattern)
  degenerate,    // the geometry could not be solved
  inconsistent,  // something was found but failed the estimator's evidence checks
  invalid,       // the frame itself was flagged (malformed stream, overflow)
};

// Times on the robot's clock (the odometry's clock), seconds.
struct MeasurementTime {
  double exposure_s = 0.0;   // mid-exposure of the frame the quantity describes
  double available_s = 0.0;  // when the result reached the filter (>= exposure_s)
};

// A ceiling tape seen by the camera (host::TapePose): the camera's yaw relative
// to the tape's direction and the camera's lateral offset from the tape's
// centre line, positive when the camera is left of the tape looking along that
// direction. The direction is the one the camera faces (|yaw| < 90 deg) for a
// forward-looking camera; in zenith mode (pitch 90) the yaw is known only
// modulo pi, and the offset is relative to whichever direction the yaw names.
// Either way the tape map's segments are undirected, so the filter picks the
// branch (segment direction or its reverse) nearest its predicted yaw.
struct TapeMeasurement {
  MeasurementTime time;
  MeasurementStatus status = MeasurementStatus::ok;
  double yaw_rad = 0.0;
  double offset_m = 0.0;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  // (yaw, offset)
  bool zenith = false;                                       // yaw known modulo pi only
};

// A pattern station's fix (host/pattern, seed 003): the camera's position on
// the floor plane and its heading in the world, from the station's known pose.
struct PatternFix {
  MeasurementTime time;
  MeasurementStatus status = MeasurementStatus::ok;
  double x_m = 0.0, y_m = 0.0, yaw_rad = 0.0;                // camera, world frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // (x, y, yaw)
};

// A point of the followed tape whose place on the map is known — where a
// tape ends at a gap, or a junction (host::detect_junctions) — seen at a
// distance along the tape: the component, along the tape's direction the
// camera faces, of the point minus the camera's floor position. The tape
// measurements fix the lateral position and the yaw; these fix the position
// along the tape, which odometry alone lets drift (docs/navigation.md).
struct LandmarkMeasurement {
  enum class Kind { tape_end, junction };
  MeasurementTime time;
  MeasurementStatus status = MeasurementStatus::ok;
  Kind kind = Kind::tape_end;
  double along_m = 0.0;
  double variance_m2 = 1e-4;
};

// Ceiling height above the camera (host/flow_height): the flow of a tracked
// ceiling feature against the odometry (host::FlowTrack, seed 000 eq. 44) or
// the tape's image width (host::ceiling_height_from_tape_width). The filter
// compares it with used_m, the height the vision measured its offsets and
// distances with at that time (the map's): it observes the ceiling scale
// state. A flow height measured against the raw wheel odometry also carries
// the wheels' scale error (true travel = (1 + e) measured), so
//   z = used / ((1 + kappa) (1 + (e_l + e_r) / 2))   (against_odometry)
//   z = used / (1 + kappa)                           (otherwise).
struct CeilingHeight {
  MeasurementTime time;
  MeasurementStatus status = MeasurementStatus::ok;
  double height_m = 0.0;
  double sigma_m = 0.0;
  double used_m = 0.0;
  bool against_odometry = true;
};

// A homing site seen by the camera looking up (host::homing, seed 004): the
// site's camera position (where the camera was when the site was recorded)
// relative to the current camera, in the robot's frame (forward along its
// heading, left), and the turn that would give the robot the site's heading
// (site heading - current heading, counter-clockwise +). Covariance of
// (forward, left, turn).
struct HomingMeasurement {
  MeasurementTime time;
  MeasurementStatus status = MeasurementStatus::ok;
  int site = -1;
  double forward_m = 0.0, left_m = 0.0;
  double turn_rad = 0.0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
};

}  // namespace ceilnav::nav
