// The built-in scene of `ceilnav demo` and `ceilnav render`: a camera on a robot
// driving down a taped corridor (gaps, a T-branch), weaving left and right.
#pragma once

#include <vector>

#include "common/camera_config.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"

namespace ceilnav::golden {

host::CameraConfig default_camera();
CeilingScene default_corridor(const host::CameraConfig& camera);
RenderParams default_render_params();

struct DrivePose {
  CameraPose pose;
  double odometry_m = 0.0;  // distance travelled since the previous frame
};
// `frames` poses, `step_m` apart along X, lateral offset and yaw weaving.
std::vector<DrivePose> default_drive(int frames, double step_m = 0.4);

}  // namespace ceilnav::golden
