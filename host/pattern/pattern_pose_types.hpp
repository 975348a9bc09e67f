// What every pose method of seed 003's pattern returns and takes: the status,
// the pose (D, theta, beta; centre and normal in the camera) and the options
// (pattern dimensions, shadow gates, the world vertical, the lens's blur).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string_view>

#include "host/pattern/ellipse_from_moments.hpp"

namespace ceilnav::host::pattern {

enum class PatternStatus {
  ok,
  no_pattern,       // no disc (and no bars)
  partial,          // the disc or the code is cut by the image border
  unreadable,       // bars seen but no identity can be read consistently
  ambiguous,        // beta's two-way ambiguity not resolved (no usable shadow)
  degenerate,       // the ellipse cannot be solved
  unknown_pattern,  // identity read but not in the database
  uncalibrated,     // the frame's photometry could not be calibrated (host/pattern/photometry.hpp)
};
std::string_view to_string(PatternStatus s);

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

}  // namespace ceilnav::host::pattern
