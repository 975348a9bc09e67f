// The bar codes of seed 003's pattern read from the run records: along the
// image rows (read_barcode) or, with the disc's pose, on the pattern plane
// (read_barcode_with_pose) (docs/pattern.md).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/pattern_pose_types.hpp"

namespace ceilnav::host::pattern {

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

}  // namespace ceilnav::host::pattern
