// Host maths of seed 003's standard pattern (docs/pattern.md): the disc's
// ellipse from class moments (eq. 17-19, 29-32), the pose (D, theta, beta) by
// the seed's moment method (eq. 6, 10, 13-14), its projection method
// (beta = +-90 deg, extents of the projections) and the exact pose of a circle
// from its image conic; the beta ambiguity resolved by the side of the shadow;
// the bar-code reader on the run records; the robot's position from the
// pattern database. Every failure is a status, never a NaN.
//
// The front header: the pose methods below, and every part of the pattern's
// host maths from its own header (class moments, the ellipse from moments,
// the circle poses of a conic, the disc's sub-pixel outline, the bar-code
// readers, the refinement with the bars, the world fix).
#pragma once

#include <Eigen/Core>

#include "host/camera_model.hpp"
#include "host/pattern/bar_refinement.hpp"
#include "host/pattern/barcode.hpp"
#include "host/pattern/circle_pose.hpp"
#include "host/pattern/class_moments.hpp"
#include "host/pattern/disc_outline.hpp"
#include "host/pattern/ellipse_from_moments.hpp"
#include "host/pattern/pattern_pose_types.hpp"
#include "host/pattern/world_fix.hpp"

namespace ceilnav::host::pattern {

// The seed's moment method: D = R / b (eq. 6, f = 1 in normalised units),
// theta = arccos(a / b) (eq. 10), beta from psi (eq. 13-14) and the shadow.
// Assumes the optical axis through the disc centre and R sin(theta) << D.
PatternPose moment_method(const FrameMoments& m, const CameraModel& camera, const PoseOptions& o);
// The seed's projection method (Section IV, VII): beta = +-90 deg; a and b
// from the horizontal and vertical extents of the disc.
PatternPose projection_method(const Extents& disc, const FrameMoments& m, const CameraModel& camera,
                              const PoseOptions& o);
// Exact: the image conic of the disc (from its moments), the two circle poses
// of that cone with radius R, the one whose predicted side-wall image matches
// the shadow's side. No centring and no R sin(theta) << D assumption.
PatternPose conic_method(const FrameMoments& m, const CameraModel& camera, const PoseOptions& o);
// conic_method with a given disc ellipse (e.g. ellipse_from_disc_runs); the
// shadow from the moments as conic_method.
PatternPose conic_method(const Ellipse& e, const FrameMoments& m, const CameraModel& camera,
                         const PoseOptions& o);

}  // namespace ceilnav::host::pattern
