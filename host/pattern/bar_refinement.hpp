// The pose of the pattern refined with the bars' edges (docs/pattern.md,
// refinement with the bars).
#pragma once

#include <span>

#include "host/camera_model.hpp"
#include "host/pattern/barcode.hpp"
#include "host/pattern/pattern_pose_types.hpp"

namespace ceilnav::host::pattern {

// The conic pose refined with the bar edges (seed §V: the bar codes' known
// dimensions "for double checking or averaging"): Gauss-Newton on the
// rotation and translation, each bar centroid's distance to the image of its
// bar's edges (rows about their bar's mean, each bar's mean with a common
// error; docs/pattern.md), against the disc: its fitted image with the fit's
// covariance (Ellipse::param_cov) or, without one, the conic's centre and
// normal. Started from both circle poses of the disc's ellipse, the lower
// cost kept (resolves beta where the shadow could not). Returns `conic`
// unchanged unless it is ok or ambiguous and there are >= 48 usable edges.
// The bars fix the pattern's rotation about its normal too: the result's
// up_cam is the measured world up (a camera tilt or swing other than
// PoseOptions::up_cam's is measured, not assumed).
PatternPose refine_with_bars(const PatternPose& conic, std::span<const BarEdge> edges,
                             const CameraModel& camera, const PoseOptions& o);

}  // namespace ceilnav::host::pattern
