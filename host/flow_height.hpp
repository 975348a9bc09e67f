// Ceiling height above the camera from the image flow of one ceiling feature
// while the robot travels a known distance (seed 000, eq. 5, 44, 57), and a
// trackable feature for it: the end of the tape at a gap.
#pragma once

#include <optional>
#include <span>

#include <Eigen/Core>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/status.hpp"
#include "host/tape_pose.hpp"

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

}  // namespace ceilnav::host
