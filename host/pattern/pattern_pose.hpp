// Host maths of seed 003's standard pattern (docs/pattern.md): the disc's
// ellipse from class moments (eq. 17-19, 29-32), the pose (D, theta, beta) by
// the seed's moment method (eq. 6, 10, 13-14), its projection method
// (beta = +-90 deg, extents of the projections) and the exact pose of a circle
// from its image conic; the beta ambiguity resolved by the side of the shadow;
// the bar-code reader on the run records; the robot's position from the
// pattern database. Every failure is a status, never a NaN.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "host/camera_model.hpp"
#include "stream/results.hpp"
#include "stream/run_record.hpp"

namespace ceilnav::host::pattern {

// Pixel classes (the hardware's fixed codes).
inline constexpr int kBackground = 0, kDisc = 1, kShadow = 2, kBar = 3, kClasses = 4;

// Raw moments of one class's mask, sums over the pixels (x = column, y = row)
// of x^a y^b: what the class-moment block delivers (and cv::moments of the
// 0/1 mask with binaryImage = true, exactly).
struct ClassMoments {
  int64_t m00 = 0, m10 = 0, m01 = 0;
  int64_t m20 = 0, m11 = 0, m02 = 0;
  friend bool operator==(const ClassMoments&, const ClassMoments&) = default;
};
using FrameMoments = std::array<ClassMoments, kClasses>;
// The moments of every class of a class image (CV_8UC1 of codes 0..3), exact
// in 64-bit integers (tools and tests; the hardware supplies the same numbers).
FrameMoments class_moments(const uint8_t* classes, int width, int height, std::size_t stride);

// The device's class moments (stream::FrameResults::class_moments) in the
// same form; the background (not measured by the device) is left zero.
FrameMoments device_moments(const stream::ClassMomentResults& r);

// Bounding box of a class's pixels (the seed's projections), inclusive.
struct Extents {
  int u_min = 0, u_max = -1, v_min = 0, v_max = -1;
  bool empty() const { return u_max < u_min; }
};
Extents class_extents(const uint8_t* classes, int width, int height, std::size_t stride, int cls);
// The same for the disc from its run records (split_disc_runs).
Extents disc_extents_from_runs(std::span<const stream::RunRecord> disc_runs);

// With the coverage LUT (golden::pattern::bar_mask_lut) the disc's runs weigh
// their chords: they are told from the bars' by position. A run is the
// disc's when its midpoint lies inside the disc class's moment ellipse
// (pixel coordinates, 1.1 x its size); the bars start 4 cm beyond the disc.
// Splits runs into (disc runs, other runs); no disc class -> all are other.
std::pair<std::vector<stream::RunRecord>, std::vector<stream::RunRecord>> split_disc_runs(
    std::span<const stream::RunRecord> runs, const ClassMoments& disc);

enum class PatternStatus {
  ok,
  no_pattern,       // no disc (and no bars)
  partial,          // the disc or the code is cut by the image border
  unreadable,       // bars seen but no identity can be read consistently
  ambiguous,        // beta's two-way ambiguity not resolved (no usable shadow)
  degenerate,       // the ellipse cannot be solved
  unknown_pattern,  // identity read but not in the database
};
std::string_view to_string(PatternStatus s);

// An ellipse in normalised (undistorted) coordinates: centre, semi-axes
// a <= b, and psi = angle of the minor axis from image "up" (-y) toward +x,
// in [0, pi) (seed Fig. 2, eq. 19).
struct Ellipse {
  double cx = 0, cy = 0, a = 0, b = 0, psi = 0;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();  // second central moments / m00
  // Uncertainty of (cx, cy, S11, S12, S22), S = 4 cov, when the estimate
  // comes with one (fit_disc_coverage); zero = not known.
  Eigen::Matrix<double, 5, 5> param_cov = Eigen::Matrix<double, 5, 5>::Zero();
};
// The ellipse of a uniform region with centre c and covariance cov (both in
// normalised coordinates); empty unless cov is positive definite.
std::optional<Ellipse> ellipse_from_covariance(const Eigen::Vector2d& c,
                                               const Eigen::Matrix2d& cov);
// Eq. 29-32 (with Sheppard's 1/12 px^2) then eq. 17-19 on the moments mapped
// to normalised coordinates: the centroid through the camera model, the
// covariance through the local Jacobian of the undistortion, refined with a
// distortion present until the lens image of the ellipse has the measured
// moments (docs/pattern.md).
std::optional<Ellipse> ellipse_from_moments(const ClassMoments& m, const CameraModel& camera);

struct PatternPose {
  PatternStatus status = PatternStatus::no_pattern;
  double d_m = 0, theta_rad = 0, beta_rad = 0;
  bool beta_resolved = false;
  // Disc centre and face normal (toward the camera) in camera coordinates;
  // the moment and projection methods fill them from D, theta, beta.
  Eigen::Vector3d centre_cam = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_cam = Eigen::Vector3d::UnitZ();
  Ellipse ellipse;
  // The pattern's +y (the world's up) in camera coordinates as the bars
  // measured it (refine_with_bars); empty when only assumed (PoseOptions::up_cam).
  std::optional<Eigen::Vector3d> up_cam;
};

struct PoseOptions {
  double radius_m = 0.25;
  double rim_m = 0.025;  // dark rim: the side wall's radius is R + rim
  double thickness_m = 0.05;
  int min_disc_pixels = 50;
  // Shadow: offset of its centroid from the disc's, relative to b, needed to
  // decide beta; below it beta stays unresolved (status ambiguous when
  // theta > small_theta_rad, else ok: beta is then meaningless).
  double min_shadow_offset = 0.02;
  int min_shadow_pixels = 8;
  double small_theta_rad = 0.05;
  // World vertical ("up") in camera coordinates, for beta of the conic method
  // (the mount's tilt and swing). Default: camera level, no swing.
  Eigen::Vector3d up_cam{0.0, -1.0, 0.0};
  // Known swing (rad) subtracted from the moment method's beta (eq. 70).
  double swing_rad = 0.0;
  // The lens's blur (Gaussian sigma, px; a calibrated camera property) for
  // the sub-pixel disc outline's chord correction (ellipse_from_disc_runs).
  double psf_sigma_px = 0.5;
  // For the coverage fit (fit_disc_coverage): whether that blur acts on pixel
  // values (a sampled Gaussian kernel, the form golden::finish_render renders)
  // rather than as a continuous PSF before the pixels integrate, and the
  // camera's pixel noise (sigma, grey levels). Both calibrated properties.
  bool blur_on_pixels = true;
  double noise_grey = 3.0;
};

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
// The disc's ellipse (normalised) from the sub-pixel outline of its runs
// (docs/pattern.md §2, sub-pixel outline): per row the chord sum_w / k (k =
// golden::pattern::disc_coverage_weight), the left edge solving
// sum_xw / k = integral of round(x) over the chord, less the strip-average
// bias of the chord (pixel rows and the lens's Gaussian blur psf_sigma_px:
// chord'' (1/24 + sigma^2/2)); rows within 1 px of the ellipse's top and bottom and
// runs at the image border are left out. The edge points go through the
// camera model and a conic is fitted (algebraic, Sampson-reweighted). Empty
// when fewer than 24 rows remain (a flat disc: the moments are better) or
// the fit is not an ellipse.
std::optional<Ellipse> ellipse_from_disc_runs(std::span<const stream::RunRecord> disc_runs,
                                              const ClassMoments& disc, uint32_t k, int width,
                                              double psf_sigma_px, const CameraModel& camera);
// conic_method with a given disc ellipse (e.g. ellipse_from_disc_runs); the
// shadow from the moments as conic_method.
PatternPose conic_method(const Ellipse& e, const FrameMoments& m, const CameraModel& camera,
                         const PoseOptions& o);

// The two poses (centre, unit normal toward the camera) of a circle of radius
// r whose image is the conic q (3x3 symmetric, [x y 1] q [x y 1]^T = 0 in
// normalised coordinates). Empty when q is not a real ellipse.
struct CirclePose {
  Eigen::Vector3d centre, normal;
};
std::vector<CirclePose> circle_poses_from_conic(const Eigen::Matrix3d& q, double r);
Eigen::Matrix3d conic_from_ellipse(const Ellipse& e);
// The other circle pose of a pose's disc ellipse (the seed's two-way
// ambiguity, eq. 14): the one of circle_poses_from_conic whose normal is not
// the pose's; empty when the ellipse has only one.
std::optional<CirclePose> mirror_pose(const PatternPose& p, double radius_m);

// Bar-code reader on the run records (mask = bar class; with bar_contrast > 0
// runs lighter than min_bar_run_weight, the disc's, are skipped),
// docs/pattern.md.
struct BarcodeOptions {
  int min_full_rows = 3;              // rows with both blocks decoded
  double max_bad_row_fraction = 0.1;  // rows disagreeing with the majority -> unreadable
  double max_fit_residual = 0.12;     // RMS edge residual of the best code, in units
  double min_fit_ratio = 2.0;         // second-best residual / best
  // Pattern geometry for the edges' pattern-frame x (BarcodeRead::edges).
  double radius_m = 0.25, bar_gap_m = 0.04, bar_unit_m = 0.02;
  // Run weight of a full bar pixel (plate level - bar level in the LUT remap,
  // golden::pattern::bar_mask_lut); > 0: sub-pixel edges from sum_w, sum_xw.
  double bar_contrast = 0.0;
  // With bar_contrast > 0: runs lighter than this are not bars (the disc's
  // runs with golden::pattern::device_config; bar_run_min_weight).
  uint32_t min_bar_run_weight = 1;
  // For read_barcode_with_pose: the bars' height and the world vertical in
  // camera coordinates (PoseOptions::up_cam).
  double bar_height_m = 0.70;
  Eigen::Vector3d up_cam{0.0, -1.0, 0.0};
};
// One bar seen on a row: normalised (undistorted) image point of its ink
// centroid, the bar's pattern-frame x extent, the image row, its width along
// the row (normalised).
struct BarEdge {
  double x, y, x0_m, x1_m;
  int row;
  double width;
};
struct BarcodeRead {
  PatternStatus status = PatternStatus::no_pattern;  // ok, partial, unreadable, no_pattern
  int identity = -1;
  int full_rows = 0, partial_rows = 0, bad_rows = 0;
  // partial: where the disc lies along the rows seen from the code: +1 = to
  // the right (a left block seen), -1 = to the left, 0 = unknown.
  int disc_direction = 0;
  std::vector<BarEdge> edges;  // ok: bar centres of the rows that read the identity
};
BarcodeRead read_barcode(std::span<const stream::RunRecord> runs, const CameraModel& camera,
                         int image_width, const BarcodeOptions& o = {});

// The code read on the pattern plane (docs/pattern.md): with the disc's pose,
// every bar run's ink edges are mapped onto the pattern plane, the runs
// covering each 0.1-unit step along each block are counted, and the block is
// read from that profile (start bar 0..3 units, gaps of 1, bars of 1 or 2,
// ending at 15; each bound within 0.35 unit; three runs across every bar).
// For views where no image row crosses a whole block (steep and slanted):
// ok with the bars' edges (those crossing a whole bar) for refine_with_bars,
// partial (one block), unreadable or no_pattern. Needs bar_contrast > 0.
BarcodeRead read_barcode_with_pose(std::span<const stream::RunRecord> runs, const PatternPose& pose,
                                   const CameraModel& camera, int image_width,
                                   const BarcodeOptions& o);

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

// Camera position and heading in the world from a pose and the pattern's
// placement (the pattern frame of golden/pattern/pattern.hpp).
struct Placement {
  double x_m = 0, y_m = 0, z_m = 0, facing_rad = 0;
};
struct WorldFix {
  double x_m = 0, y_m = 0, z_m = 0;
  double camera_yaw_rad = 0;  // heading of the optical axis, CCW from +X
};
// The camera position from D, theta, beta; its yaw from the direction of the
// disc centre in the camera (pose.centre_cam) and up_cam.
WorldFix world_fix(const PatternPose& pose, const Placement& placement,
                   const Eigen::Vector3d& up_cam);

}  // namespace ceilnav::host::pattern
