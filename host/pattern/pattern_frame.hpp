// The host's whole analysis of one pattern frame from what the device
// delivers (class moments and run records): the disc's runs told from the
// bars', the disc's ellipse (moments -> sub-pixel outline -> coverage fit),
// the three pose methods, the bar code (rows, else on the pattern plane) and
// the pose refined with the bars (docs/pattern.md). Used by `ceilnav pattern`,
// `pattern-accuracy` and the benchmark.
#pragma once

#include <optional>
#include <span>

#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/disc_coverage.hpp"
#include "host/pattern/pattern_pose.hpp"

namespace ceilnav::host::pattern {

struct PatternAnalysis {
  Extents disc;           // the disc's runs' bounding box
  bool disc_cut = false;  // ... touches the image border: poses are `partial`
  PatternPose conic, moment, projection;
  PatternPose conic_bars;  // the conic pose refined with the bar edges: the result
  BarcodeRead code;
  std::optional<CoverageFit> fit;  // the disc's coverage fit, when it converged
};

// runs: every run of the frame (disc and bars); code: the reader's options
// (its up_cam is taken from pose.up_cam); coverage: how the LUT weighs a
// disc pixel (its k is the disc run weight of a full pixel).
PatternAnalysis analyse_pattern(std::span<const stream::RunRecord> runs, const FrameMoments& m,
                                const CameraModel& camera, int width, int height,
                                const PoseOptions& pose, BarcodeOptions code,
                                const DiscCoverageModel& coverage);

}  // namespace ceilnav::host::pattern
