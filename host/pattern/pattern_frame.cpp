#include "host/pattern/pattern_frame.hpp"

#include <utility>
#include <vector>

#include "host/pattern/disc_evidence.hpp"

namespace ceilnav::host::pattern {

PatternAnalysis analyse_pattern(std::span<const stream::RunRecord> runs, const FrameMoments& m,
                                const CameraModel& camera, int width, int height,
                                const PoseOptions& pose, BarcodeOptions code,
                                const DiscCoverageModel& coverage) {
  PatternAnalysis a;
  auto [disc_runs, bar_runs] = split_disc_runs(runs, m[kDisc]);
  a.disc = disc_extents_from_runs(disc_runs);
  a.disc_cut = !a.disc.empty() && (a.disc.u_min == 0 || a.disc.v_min == 0 ||
                                   a.disc.u_max == width - 1 || a.disc.v_max == height - 1);
  a.conic = conic_method(m, camera, pose);
  // The disc's fits only where its runs are one convex region's (bounded
  // time on frames without the pattern, docs/pattern.md).
  if (a.conic.status != PatternStatus::no_pattern && one_run_per_row(disc_runs, height)) {
    // The sub-pixel outline from the disc runs' coverage weights when it
    // fits, then every disc run's coverage sums against the exact prediction
    // for a candidate ellipse (coverage fit), started from the outline or,
    // when there is none, the moments' ellipse.
    const auto outline =
        ellipse_from_disc_runs(disc_runs, m[kDisc], coverage.k, width, pose.psf_sigma_px, camera);
    if (outline) a.conic = conic_method(*outline, m, camera, pose);
    const auto start = outline ? outline : ellipse_from_moments(m[kDisc], camera);
    // The fit only where the runs are evidence of one filled ellipse near
    // the start (bounded time on frames without the pattern).
    if (start && runs_fit_ellipse(disc_runs, *start, camera, width, height)) {
      a.fit = fit_disc_coverage(disc_runs, *start, coverage, camera, width, height);
      if (a.fit) a.conic = conic_method(a.fit->ellipse, m, camera, pose);
    }
  }
  a.moment = moment_method(m, camera, pose);
  a.projection = projection_method(a.disc, m, camera, pose);
  if (a.disc_cut) {
    for (PatternPose* p : {&a.conic, &a.moment, &a.projection}) p->status = PatternStatus::partial;
  }
  code.up_cam = pose.up_cam;
  a.code = read_barcode(bar_runs, camera, width, code);
  if (a.code.status != PatternStatus::ok && !a.disc_cut) {
    // No row crossed a whole block: read the code on the pattern plane, with
    // the conic's pose or, where the shadow left beta open, with each of the
    // ellipse's two poses; a read needs them to agree.
    std::vector<PatternPose> poses{a.conic};
    if (a.conic.status == PatternStatus::ambiguous) {
      if (const auto cp = mirror_pose(a.conic, pose.radius_m)) {
        PatternPose other = a.conic;
        other.centre_cam = cp->centre;
        other.normal_cam = cp->normal;
        poses.push_back(other);
      }
    }
    std::optional<BarcodeRead> read;
    bool conflict = false;
    for (const PatternPose& p : poses) {
      BarcodeRead plane = read_barcode_with_pose(bar_runs, p, camera, width, code);
      if (plane.status != PatternStatus::ok) continue;
      if (read && read->identity != plane.identity) conflict = true;
      if (!read) read = std::move(plane);
    }
    if (read && !conflict) a.code = std::move(*read);
  }
  a.conic_bars = refine_with_bars(a.conic, a.code.edges, camera, pose);
  return a;
}

}  // namespace ceilnav::host::pattern
