// The frames a robot's camera sees of a course during a drive: motion blur
// over the exposure, ceiling height zones, mount errors, pattern stations;
// and the truth of the tape in view. docs/navigation.md, "Rendering a drive".
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <vector>

#include "common/camera_config.hpp"
#include "golden/pattern/pattern.hpp"
#include "golden/renderer.hpp"
#include "nav/odometry_step.hpp"
#include "sim/course.hpp"
#include "sim/robot.hpp"

namespace ceilnav::sim {

// The robot's true pose as a function of time.
using PoseAt = std::function<nav::Pose2(double t_s)>;

// Timed true poses (e.g. Robot::pose() after every step), interpolated
// linearly in x, y and (the shorter way) in yaw; held before the first and
// after the last. Times must increase.
class PoseTrack {
 public:
  void add(double t_s, const nav::Pose2& pose);
  nav::Pose2 at(double t_s) const;
  bool empty() const { return times_.empty(); }

 private:
  std::vector<double> times_;
  std::vector<nav::Pose2> poses_;
};

struct DriveRenderParams {
  golden::RenderParams render;  // gain, background, blur, noise, sampling
  // Sub-exposures: K = ceil(image motion over the exposure / max_step_px),
  // 1 <= K <= max_subexposures. Steps of one pixel: each sub-exposure
  // integrates its pixel's area, so pixel-spaced copies of an edge add up to
  // the continuous ramp (docs/navigation.md, "Rendering a drive").
  double max_step_px = 1.0;
  int max_subexposures = 64;
  // Pattern stations (golden::pattern's renderer).
  golden::pattern::PatternGeometry pattern_geometry;
  golden::pattern::Radiometry pattern_radiometry;
  int pattern_supersample = 4;
  // >= 0: the frame's noise is drawn for this frame of a drive (its own
  // field, a resampling of a pool of normal deviates; see frame_noise),
  // instead of golden's noise field of render.noise_seed, which is the same
  // field for every frame of that seed. -1: golden's.
  int64_t frame_index = -1;
};

// Adds zero-mean Gaussian noise of sigma_grey to a CV_64FC1 image: the
// frame's own field for (seed, frame): pool[(offset + k stride) mod 2^20]
// for pixel k, with a pool of 2^20 standard normal deviates drawn once
// (std::normal_distribution on mt19937_64 seeded 1) and the offset and an
// odd stride hashed from (seed, frame). Within a frame of up to 2^20 pixels
// the deviates are distinct draws; frames get different subsets in
// different orders. A closed-loop drive renders tens of thousands of frames:
// golden's exact per-pixel Box-Muller would be two thirds of a frame's cost.
void add_frame_noise(cv::Mat& image, double sigma_grey, uint64_t seed, int64_t frame);

struct DriveFrameInfo {
  int subexposures = 0;
  double motion_px = 0.0;  // largest image motion of a ceiling point over the exposure
  int pattern_pixels = 0;  // pixels composited from pattern stations (all sub-exposures)
};

// The radiance (CV_64FC1, no background, blur or noise) a camera at `view`
// sees of the course: its tape strips (ceiling_scene) and, where in view,
// its pattern stations composited over them.
cv::Mat course_radiance(const host::CameraConfig& camera, const Course& course,
                        const golden::CeilingScene& strips, const golden::CameraView& view,
                        const DriveRenderParams& params, int* pattern_pixels = nullptr);

// The frame of an exposure that starts at t_s and lasts t_exp_s while the
// robot moves: the average of K sub-exposure radiances at the times
// t + (k + 1/2) t_exp / K, finished once (background, blur, noise:
// golden::finish_render). CV_64FC1; render_drive_frame rounds it to 8 bits.
cv::Mat render_drive_float(const host::CameraConfig& camera, const Course& course,
                           const CameraMount& mount, const PoseAt& robot_pose_at, double t_s,
                           double t_exp_s, const DriveRenderParams& params,
                           DriveFrameInfo* info = nullptr);
cv::Mat render_drive_frame(const host::CameraConfig& camera, const Course& course,
                           const CameraMount& mount, const PoseAt& robot_pose_at, double t_s,
                           double t_exp_s, const DriveRenderParams& params,
                           DriveFrameInfo* info = nullptr);

// Largest image motion, in pixels, of the ceiling points seen on a 5 x 5
// grid over the image, between two camera views (through a third, halfway).
double image_motion_px(const host::CameraConfig& camera, const Course& course,
                       const golden::CameraView& from, const golden::CameraView& mid,
                       const golden::CameraView& to);

// The view of a robot's camera (camera_pose as a golden::CameraView).
golden::CameraView camera_view(const host::CameraConfig& camera, const CameraMount& mount,
                               const nav::Pose2& robot);

// Which tape a camera sees and its pose relative to it, as the host measures
// it: the look point is where the optical axis meets the ceiling (the zone's
// height there); the tape segment nearest to it is the one in view; its
// direction is taken the way the camera faces (|yaw| <= 90 deg).
struct TapeTruth {
  bool in_view = false;           // the segment's point nearest the look point is in the image
  int tape = -1;                  // index in Course::tapes
  int segment = -1;               // its segment (points[segment] -> points[segment + 1])
  double tape_heading_rad = 0.0;  // direction of the tape as taken
  double yaw_rad = 0.0;           // camera heading - tape_heading, wrapped
  double offset_m = 0.0;          // camera centre left of the centre line: positive
  double ceiling_above_camera_m = 0.0;  // at the look point
  Point2 look_point;
};
TapeTruth tape_truth(const host::CameraConfig& camera, const Course& course,
                     const CameraWorldPose& pose);

// A ceiling-mounted pattern station's placement for golden::pattern: face
// down, its face thickness_m below the ceiling, its +y along the station's
// yaw. Pattern-frame axes in world coordinates (columns x, y, z) and origin.
struct StationFrame {
  Eigen::Matrix3d axes;
  Eigen::Vector3d origin;
};
StationFrame station_frame(const Course& course, const PatternStation& station,
                           const golden::pattern::PatternGeometry& geometry);

}  // namespace ceilnav::sim
