// The standard pattern of seed 003 (Kabuka & Arenas): a disc of radius R standing
// off a wall by T (its visible side wall is the "shadow"), with a vertical bar
// code block at each side of it, and its renderer. Geometry, code, radiometry,
// class levels and the renderer are described in docs/pattern.md.
//
// Pattern frame: origin at the centre of the disc's face, x to the right and y
// up as seen by a viewer facing the wall, z out of the wall toward the viewer
// (right-handed). The disc face and the bar-code plates lie in the plane z = 0,
// the wall in z = -T. A camera at distance D, elevation theta (from +z) and
// co-azimuth beta (from +y, toward +x) sits at
//   C = D (sin(theta) sin(beta), sin(theta) cos(beta), cos(theta)).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "common/camera_config.hpp"
#include "common/pattern/disc_coverage_model.hpp"
#include "common/pipeline_config.hpp"
#include "common/run_record.hpp"
#include "golden/renderer.hpp"

namespace ceilnav::golden::pattern {

// Pixel classes, fixed codes shared with the hardware class-moment block.
enum class PixelClass : uint8_t { background = 0, pattern = 1, shadow = 2, bar = 3 };
inline constexpr int kClassCount = 4;

struct PatternGeometry {
  double radius_m = 0.25;  // R: the white disc
  // A dark rim (wall albedo) on the face around the disc, so that the disc's
  // edge borders one grey level everywhere; the cylinder's radius is R + rim.
  double rim_m = 0.025;
  double thickness_m = 0.05;     // T: the cylinder's stand-off from the wall
  double bar_unit_m = 0.02;      // u: thin bar = u, thick bar = 2u, start/stop bar = 3u, gap = u
  double bar_gap_m = 0.04;       // from the disc's edge to the inner end of a block
  double bar_height_m = 0.70;    // taller than the diameter (seed §V)
  double plate_margin_m = 0.02;  // dark plate around each block beyond its bars
};

// Bar code: each block is [start/stop bar 3u] then 5 data bars (outer to inner),
// of which exactly two are thick (a 2-of-5 code: 10 values per block, any single
// width misread breaks the weight). The left block's wide bar is at its left
// (the "start"), the right block's at its right (the "stop"), so a block seen
// alone tells on which side the disc lies. Identity i in [0, kIdentityCount):
// left value L = i / 5, right value V = 2 (i mod 5) + ((L + i mod 5) mod 2) -- a
// parity check across the two blocks.
inline constexpr int kIdentityCount = 50;
inline constexpr int kBlockValues = 10;
inline constexpr int kDataBars = 5;
// Data-bar widths in units (1 or 2), outer to inner, of block value v in [0, 10).
std::array<int, kDataBars> block_widths(int value);
// Inverse of block_widths; nullopt unless exactly two widths are 2 and the rest 1.
std::optional<int> block_value(const std::array<int, kDataBars>& widths);
// (left value, right value) of an identity; throws std::invalid_argument out of range.
std::pair<int, int> block_values(int identity);
// Identity of a pair of block values; nullopt when the parity check fails.
std::optional<int> identity_from_blocks(int left_value, int right_value);
// What a mirror-image print (x -> -x on the pattern) of `identity` reads as:
// each block moves to the other side and, its wide bar still outermost and
// its data bars still read outer to inner, keeps its value, so (L, V) becomes
// (V, L). The identity of that pair, nullopt when it fails the parity (the
// mirrored print is unreadable). docs/pattern.md, "Mirrored print".
std::optional<int> mirrored_identity(int identity);

// One bar: pattern-frame x extent (the bar spans y in +-bar_height/2).
struct BarSpan {
  double x0_m, x1_m;
};
// The 12 bars of an identity, left to right: left block (wide bar first), right
// block (wide bar last). Positions in units follow from the widths.
std::vector<BarSpan> bar_layout(const PatternGeometry& g, int identity);
// Outer x of the left block's wide bar (the right block is its mirror image).
double block_outer_x_m(const PatternGeometry& g);
double block_inner_x_m(const PatternGeometry& g);

// Radiometry: grey = black_level + gain * albedo * falloff, falloff =
// (lamp distance to the disc centre / lamp distance to the point)^2 for a lamp
// on the pattern axis (x = y = 0, z = lamp_distance_m); a Lambertian surface's
// grey does not depend on the camera's distance. Beyond the wall panel the
// surroundings have the wall's grey at falloff 1.
struct Radiometry {
  double black_level = 4.0;
  double gain = 250.0;
  double albedo_bar = 0.0;      // black ink
  double albedo_wall = 0.18;    // wall and bar-code plates
  double albedo_shadow = 0.32;  // the disc's side wall
  double albedo_disc = 0.98;
  double lamp_distance_m = 6.0;
  double wall_half_width_m = 3.0, wall_half_height_m = 1.5;
  // Nominal grey level (falloff 1) of a class. May lie outside 0..255 for a
  // radiometry estimated from a frame (host::pattern::calibrate_photometry):
  // the camera then clips, and the LUT works on the clipped levels.
  double level(PixelClass c) const;
  // The level as the camera delivers it: level(c) clipped to 0..255.
  double observed_level(PixelClass c) const;
};

// The camera's own photometry, applied by the renderer on top of the scene's
// radiometry: grey = black_level + offset_grey + gain * vignetting(r) *
// (radiometry gain * albedo * falloff), vignetting(r) = 1 - vignetting *
// (r / r_corner)^2 with r the distance from the image centre and r_corner
// that of the corner pixel (a quadratic radial falloff reaching `vignetting`
// at the corner). Then the blur and the noise (golden::finish_render). The
// host is not told it: it calibrates from the frame (docs/pattern.md §2).
struct CameraPhotometry {
  double gain = 1.0;
  double offset_grey = 0.0;
  double vignetting = 0.0;  // fraction lost at the image corner, [0, 1)
};
// The camera's vignetting factor at pixel (x, y) of a width x height image.
double vignetting_factor(const CameraPhotometry& p, int width, int height, double x, double y);

// The class LUT: grey -> class code. Levels in grey order bar < wall < shadow <
// disc; thresholds a third of the way from bar to wall, at the midpoints of
// wall/shadow and wall/disc (the disc borders only the dark rim, so its
// thresholded edge is unbiased; docs/pattern.md).
struct ClassThresholds {
  int bar_below;     // grey < bar_below -> bar
  int shadow_from;   // shadow_from <= grey < pattern_from -> shadow
  int pattern_from;  // grey >= pattern_from -> pattern (disc)
};
ClassThresholds class_thresholds(const Radiometry& r);
std::array<uint8_t, 256> class_lut(const Radiometry& r);
// The device's LUT for a pattern frame: remap = 255 - grey up to the wall
// level + kCoverageDeadZone (bars are dark, so w = remap - background is a
// bar's ink), above it background + disc_coverage_weight x the disc's
// coverage (grey - wall) / (disc - wall), full from disc - kCoverageDeadZone
// (a disc run's weight is its sub-pixel chord); mask = (class == bar or
// disc), CLASS = class_lut.
std::array<stream::LutEntry, 256> bar_mask_lut(const Radiometry& r);
// Background level for the run weights with bar_mask_lut: 255 - wall level.
uint8_t bar_run_background(const Radiometry& r);
// cv::LUT of a grey frame through class_lut: CV_8UC1 of class codes.
cv::Mat classify(const cv::Mat& grey, const std::array<uint8_t, 256>& lut);

// The device configuration for a pattern frame (docs/pattern.md): LUT
// bar_mask_lut, CLASS = class_lut (class_moments of disc, shadow and bars)
// and mask = bar or disc class; run background bar_run_background, so a bar
// run's weight is its ink and a disc run's its chord x disc_coverage_weight
// (the host tells them apart by position, host::pattern::split_disc_runs);
// class window = the whole frame; min run length 1, 32 runs per row.
stream::PipelineConfig device_config(int width, int height, const Radiometry& r);
// The least weight of a bar run with device_config: one bar pixel's ink
// (grey bar_below - 1); the bar reader skips lighter runs.
uint32_t bar_run_min_weight(const Radiometry& r);
// Grey levels within this of the wall weigh nothing on the bright side, and
// within this of the disc count as full disc (bar_mask_lut).
inline constexpr double kCoverageDeadZone = 9.0;
// The grey from which bar_mask_lut weighs a pixel as full disc: the disc
// level as the camera delivers it (clipped to 255) less kCoverageDeadZone.
double disc_full_grey(const Radiometry& r);
// A full disc pixel's run weight with device_config (255 - background): a
// disc run's sum_w / this is its chord in pixels, sum_xw / sum_w its centroid.
uint32_t disc_coverage_weight(const Radiometry& r);

// How bar_mask_lut weighs a disc pixel (host::pattern::fit_disc_coverage's
// model), for a camera of pixel noise noise_grey and blur blur_sigma_px (on
// pixel values, as finish_render renders it, or a continuous PSF).
host::pattern::DiscCoverageModel disc_coverage_model(const Radiometry& r, double noise_grey,
                                                     double blur_sigma_px, bool blur_on_pixels);

// Camera pose in the pattern frame: X_cam = R (X_pat - C), OpenCV camera axes.
struct PatternView {
  Eigen::Vector3d centre;
  Eigen::Matrix3d rotation;
};
// Camera at C looking at `target` with swing (roll about the optical axis,
// positive = clockwise in the image); swing 0: the camera's x axis is
// horizontal (perpendicular to +y), so the wall's vertical projects vertical.
PatternView look_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& target, double swing_rad);
Eigen::Vector3d spherical_position(double d_m, double theta_rad, double beta_rad);
// The seed's set-up: the optical axis through the disc centre.
PatternView spherical_view(double d_m, double theta_rad, double beta_rad, double swing_rad = 0.0);

// A pattern placed in the world (BRIEF §5 frame, Z up): centre of the disc face
// at (x, y, z), facing the horizontal direction facing_rad (CCW from +X) = the
// pattern's +z axis; its +y is world +Z.
struct PatternPlacement {
  int identity = 0;
  double x_m = 0.0, y_m = 0.0, z_m = 1.0;
  double facing_rad = 0.0;
};
// Pattern-frame axes in world coordinates: columns x_p, y_p, z_p.
Eigen::Matrix3d pattern_axes(const PatternPlacement& p);
Eigen::Vector3d world_to_pattern(const PatternPlacement& p, const Eigen::Vector3d& world);
Eigen::Vector3d pattern_to_world(const PatternPlacement& p, const Eigen::Vector3d& local);

// A robot's camera: centre (x, y, height) in the world, optical axis horizontal
// and heading camera_yaw_rad (CCW from +X; robot heading + pan), tilt up by
// tilt_rad, swing about the optical axis.
struct RobotCamera {
  double x_m = 0.0, y_m = 0.0, height_m = 1.0;
  double camera_yaw_rad = 0.0, tilt_rad = 0.0, swing_rad = 0.0;
};
PatternView robot_view(const PatternPlacement& p, const RobotCamera& cam);

// The pattern database: identity -> placement, plus the shared geometry.
struct PatternDatabase {
  PatternGeometry geometry;
  std::vector<PatternPlacement> patterns;
  const PatternPlacement* find(int identity) const;
};
// OpenCV FileStorage YAML; throws std::runtime_error naming file and key,
// also for a database without patterns (an empty `patterns` sequence).
PatternDatabase load_pattern_database(const std::string& path);
// Written to a temporary file and renamed.
void save_pattern_database(const std::string& path, const PatternDatabase& db);

struct PatternRenderParams {
  int supersample = 4;  // N x N jittered samples near an edge
  double blur_sigma_px = 0.5;
  double noise_sigma_grey = 2.0;
  uint64_t noise_seed = 1;
  bool apply_distortion = true;
  CameraPhotometry photometry;  // the camera's gain, offset and vignetting
};

// Truth of one frame.
struct PatternTruth {
  double d_m, theta_rad, beta_rad, swing_rad;
  int identity;
  Eigen::Vector2d centre_px;  // distorted pixel of the disc centre (NaN if behind)
  bool disc_in_view;          // every point of the disc's rim projects inside the image
  bool code_in_view;          // every bar corner projects inside the image (1 px margin)
  double min_bar_width_px;    // narrowest thin bar along the rows, ideal pixels
};
PatternTruth pattern_truth(const host::CameraConfig& camera, const PatternGeometry& g, int identity,
                           const PatternView& view);

// The frame (CV_8UC1) the camera sees of the pattern. Throws
// std::invalid_argument on bad parameters or a camera behind the face plane.
cv::Mat render_pattern(const host::CameraConfig& camera, const PatternGeometry& g,
                       const Radiometry& radiometry, int identity, const PatternView& view,
                       const PatternRenderParams& params);
// The class (0..3) the exact (noise-free, unblurred) scene shows along the ray
// through normalised coordinates (x, y); for tests.
PixelClass class_along_ray(const PatternGeometry& g, int identity, const PatternView& view,
                           double x, double y);

}  // namespace ceilnav::golden::pattern
