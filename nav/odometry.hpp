// Measured odometry for the host: the odometry file a robot logs, the robot's
// wheel parameters, and the odometry track (the integrated planar pose at any
// time, and the relative motion between two times). Formats: docs/navigation_io.md.
#pragma once

#include <istream>
#include <stdexcept>
#include <string>
#include <vector>

#include "nav/odometry_step.hpp"

namespace ceilnav::nav {

// A malformed odometry, robot or frame-time file; what() names the file and
// the line ("odo.csv:7: time 0.5 is not after the previous 0.5").
class OdometryFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Wheel parameters of a differential-drive robot (the `--robot` file).
struct RobotParams {
  double wheel_base_m = 0.0;       // distance between the wheels' contact points
  double left_m_per_count = 0.0;   // nominal travel of the left wheel per encoder count
  double right_m_per_count = 0.0;  // likewise, right wheel
};

// Flat YAML subset: one `key: value` per line, `#` comments, blank lines; the
// keys wheel_base_m, left_m_per_count, right_m_per_count are required, all > 0
// and finite, no other key and no key twice. `name` prefixes the messages.
RobotParams parse_robot_params(std::istream& in, const std::string& name);
RobotParams load_robot_params(const std::string& path);

// One odometry sample: the pose integrated up to t_s from the first sample.
struct OdometrySample {
  double t_s = 0.0;
  Pose2 pose;
};

enum class OdometryFormat { encoder_counts, body_velocity };

// The odometry file, CSV with a header row:
//   t_s,left_ticks,right_ticks   cumulative encoder counts (integers; robot needed)
//   t_s,v_mps,omega_radps        body velocity held from this row to the next
// Times strictly increasing and finite, at least two rows. Whitespace around
// fields is ignored; `\r\n` line ends are accepted. Throws OdometryFileError
// with the line number; nothing is returned on error.
class OdometryTrack {
 public:
  // `robot` is used (and must be valid) for the counts format only.
  static OdometryTrack parse(std::istream& in, const std::string& name, const RobotParams* robot);
  static OdometryTrack load(const std::string& path, const RobotParams* robot);
  // The pose at the samples' times; the first is the origin (0, 0, 0).
  explicit OdometryTrack(std::vector<OdometrySample> samples);

  OdometryFormat format() const { return format_; }
  double t_begin() const { return samples_.front().t_s; }
  double t_end() const { return samples_.back().t_s; }
  bool covers(double t_s) const { return t_s >= t_begin() && t_s <= t_end(); }
  const std::vector<OdometrySample>& samples() const { return samples_; }

  // The pose at t_s: along the constant-curvature arc of the segment holding
  // t_s, at the fraction of the segment's time (uniform speed within a tick).
  // Throws std::out_of_range outside [t_begin, t_end].
  Pose2 pose_at(double t_s) const;
  // The pose at t2_s in the frame of the pose at t1_s (x forward, y left).
  Pose2 relative(double t1_s, double t2_s) const;

 private:
  std::vector<OdometrySample> samples_;
  OdometryFormat format_ = OdometryFormat::body_velocity;
};

// The frame-time file `--frame-times`, CSV with the header `frame,t_s`: the
// frame's PNG file name (no folder) and the mid-exposure time of the frame on
// the odometry's clock. Names unique, times finite and strictly increasing in
// file order. Throws OdometryFileError with the line number.
struct FrameTime {
  std::string frame;
  double t_s = 0.0;
};
std::vector<FrameTime> parse_frame_times(std::istream& in, const std::string& name);
std::vector<FrameTime> load_frame_times(const std::string& path);

// `b` expressed in the frame of `a`.
Pose2 relative_pose(const Pose2& a, const Pose2& b);

}  // namespace ceilnav::nav
