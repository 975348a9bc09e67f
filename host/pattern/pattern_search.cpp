#include "host/pattern/pattern_search.hpp"

#include <algorithm>
#include <cmath>

namespace ceilnav::host::pattern {

double pattern_angle_rad(const ScanParams& p) {
  if (!(p.d_min_m > 0.0) || !(p.pattern_half_width_m >= 0.0)) return 0.0;
  return 2.0 * std::atan(p.pattern_half_width_m / p.d_min_m);
}

double motion_angle_rad(const ScanParams& p) {
  if (!(p.d_min_m > 0.0) || !(p.video_rate_hz > 0.0)) return 0.0;
  return std::atan(std::abs(p.robot_speed_mps) / (p.video_rate_hz * p.d_min_m));
}

double max_pan_rate(const ScanParams& p) {
  if (!(p.video_rate_hz > 0.0) || !(p.fov_rad > 0.0)) return 0.0;
  const double per_frame = p.fov_rad - pattern_angle_rad(p) - motion_angle_rad(p);
  return std::max(0.0, per_frame) * p.video_rate_hz;
}

}  // namespace ceilnav::host::pattern
