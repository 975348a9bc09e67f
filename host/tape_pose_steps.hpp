// The steps of host::estimate_tape_pose (tape_pose.cpp) and their working
// storage: runs into chains and centre-line points (tape_chains.cpp), the
// centre-line candidates, the tape among them and its statistics
// (tape_centre_line.cpp). Internal to the host library (and its tests);
// docs/host_maths.md section 4.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "host/camera_model.hpp"
#include "host/status.hpp"
#include "host/tape_pose.hpp"

namespace ceilnav::host::tape_steps {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kDegToRad = kPi / 180.0;

// Centre-line candidate points (runs' intensity-weighted centres), as columns.
struct Points {
  std::vector<double> x, y;    // normalised
  std::vector<double> weight;  // inverse variance of x (relative), see weight_of_run
  std::vector<int> row;
  std::vector<int> run;   // index into the input span
  std::vector<int> comp;  // root of the run's chain
  size_t size() const { return x.size(); }
  void resize(size_t m) {
    x.resize(m);
    y.resize(m);
    weight.resize(m);
    row.resize(m);
    run.resize(m);
    comp.resize(m);
  }
};

// A subset of Points: 1 = in.
using Mask = std::vector<uint8_t>;

// Least squares x = a y + b in normalised coordinates (rows are exact, the
// measured quantity is the run centre along x).
struct LineFit {
  bool ok = false;
  double a = 0.0, b = 0.0;
};

struct Candidate {
  LineFit line;
  int support = 0;
  double dist_to_centre = 0.0;
};

// Per chain of runs: its own line fit (sums over its run centres on ceiling
// rows), the width allowance 1 / cos psi from that fit, and width-gate counts.
struct ChainStats {
  double n = 0.0, sy = 0.0, sx = 0.0, syy = 0.0, sxy = 0.0;
  double inv_cos_yaw = 1.0;
  bool steep = false;                   // heading beyond max_abs_yaw_deg, or no slope (one row)
  int pixels = 0, too_wide_pixels = 0;  // in its runs on ceiling rows; in those too wide
};

struct MaskFit {
  Mask mask;
  LineFit fit;
};

// Working storage of estimate_tape_pose, kept per thread so that a call
// allocates nothing once the buffers have grown to the frame's run count.
struct Scratch {
  std::vector<int> order, row, x_start, x_end, parent, label, root, root_k, comp_min_row,
      comp_max_row, comp_min_col, comp_max_col, usable_count;
  std::vector<double> u, v, x, y, w;
  std::vector<ChainStats> chains;  // by chain number
  std::vector<int> chain_of_root;  // run index of a chain's root -> chain number
  std::vector<int> chain_root;     // chain number -> run index of its root
  std::vector<uint8_t> usable;
  Points pts, left, right;
  std::vector<std::pair<int, int>> comps;
  Mask mask_a, mask_b;
  std::vector<MaskFit> memo;
  std::vector<Candidate> cands;
  std::vector<std::pair<double, int>> along;      // (position along the tape, point), sorted
  std::vector<double> ratios;                     // measured / predicted run widths
  std::vector<double> weights;                    // sum_w per run pixel
  std::vector<double> excess;                     // measured - predicted run widths, pixels
  std::vector<std::pair<double, double>> widths;  // (predicted, measured) run widths, pixels
  std::vector<size_t> piece_begin;                // index into `along` where each piece starts
  std::vector<int> sampled;                       // points whose width is compared
};

// The pitch, the ceiling height and the image size every step reads.
struct Geometry {
  double sp = 0.0, cp = 1.0;  // sin, cos of the pitch
  double c = 0.0;             // ceiling above the camera, metres
  int width = 0, height = 0;
};

// ---------------------------------------------------------------- the steps
// estimate_tape_pose in order: sort_runs, link_chains, chain_extents,
// undistort_run_centres, fit_chain_headings, gate_centre_points,
// collect_points, largest_chains, status_when_too_few, fit_candidates,
// choose_tape, inlier_statistics, yaw_sigma, set_vanishing_point (tape_pose.cpp),
// pitch_from_edges (docs/host_maths.md section 4).

// Noise of a run centre x_c = sum_xw / sum_w: each of the n pixels of the run
// and its margins carries independent noise sigma, so
//   var(x_c) = sigma^2 sum_i (x_i - x_c)^2 / sum_w^2.
// The relative inverse variance sum_w^2 / sum_i (x_i - x_c)^2 weights the fit;
// the sum has the closed form n (n^2 - 1) / 12 + n (mean - x_c)^2.
double weight_of_run(const stream::RunRecord& r, double xc, int width);

// Root of i's tree, halving the path on the way. Every link points from a
// higher index to a lower one, so a root is its tree's lowest index.
int find_root(std::vector<int>& parent, int i);

// Runs in (row, x_start) order; the scanner emits them so, but do not rely
// on it. Their geometry is copied in that order (k) into sc.row, sc.x_start,
// sc.x_end for the scans below; sc.order[k] is the run's index i in the input.
void sort_runs(std::span<const stream::RunRecord> runs, Scratch& sc);

// Connected chains of runs (after sort_runs): a run joins a run of the row
// above when their pixel spans touch (8-connectivity). Fills sc.parent, the
// union-find links (from a higher run index i to a lower one; the root of a
// chain is its lowest run index).
void link_chains(size_t n, Scratch& sc);

// Chain of every run (after link_chains): sc.root by run index i, sc.root_k
// in sorted order k, and per chain (indexed by its root) its row and column
// extent.
void chain_extents(size_t n, Scratch& sc);

// Run centres x_c = sum_xw / sum_w (the span's middle when sum_w is 0) in
// pixels (sc.u, sc.v) and undistorted all at once (sc.x, sc.y), by run index.
void undistort_run_centres(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                           Scratch& sc);

// The chain (sc.chains) of a run's root.
ChainStats& chain_of_run(Scratch& sc, int rt);

// Heading of each chain, for the width gate: a tape at heading psi is
// 1 / cos psi wider along a row than at psi = 0 (host_maths.md section 3).
// Each chain's run centres (ceiling rows only) are fitted with x = a y + b,
// tan psi = a sin p + b cos p; |psi| is capped at max_abs_yaw_deg. A branch
// crossing or a merge adds a few rows to a chain; the fit is its tape's.
// Numbers the chains (sc.chain_of_root, sc.chain_root) and fills sc.chains'
// sums and headings.
void fit_chain_headings(size_t n, const Geometry& g, const TapePoseOptions& opt, Scratch& sc);

// Centre-line points: sc.usable[i] = 1 and sc.w[i] = its weight for a run
// that passes every gate. Gates: runs touching the left/right image border
// lose their margin (biased centre); the end rows of a chain inside the image
// are partly covered by the tape end; rows where a chain splits into several
// runs; runs wider than the tape can be (T-branch, merged tapes); rows at or
// below the horizon cannot hold a ceiling point. Also counts each chain's
// pixels on ceiling rows and those in too-wide runs (ChainStats).
void gate_centre_points(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                        const CameraConfig& cfg, const TapePoseOptions& opt, const Geometry& g,
                        Scratch& sc);

// The usable points (gate_centre_points) into sc.pts, in run index order
// (the order every sum below runs in).
void collect_points(std::span<const stream::RunRecord> runs, Scratch& sc);

// The (at most 4) chains with most usable points, at least 2, into sc.comps
// as (usable points, root), most first.
void largest_chains(size_t n, Scratch& sc);

// The status when too few centre-line points remain. A chain spanning
// min_row_span_px rows or columns is tape-like, smaller ones are noise
// specks: none -> no_tape. A tape-like chain runs along the horizon when its
// heading is beyond max_abs_yaw_deg, it lies on one row, or most of its
// pixels are in runs too wide even for that heading: all of them -> degenerate.
// Otherwise too_few_points.
Status status_when_too_few(const TapePoseOptions& opt, const Scratch& sc);

// Sums over the final inliers of the chosen line.
struct InlierStats {
  int used = 0;
  int row_min = 1 << 30, row_max = -1;
  double ss = 0.0;  // sum of squared residuals, pixels^2
  double sy = 0.0, syy = 0.0;
};

// Weighted least squares of the masked points (LineFit); not ok with fewer than
// two points, all on one row, or a non-finite result.
LineFit fit_x_on_y(const Points& pts, const Mask& use);

// Inlier sets are masks over pts. A fit depends only on its set (the sums
// run in index order), so a refinement whose set did not change has
// converged, and a set fitted before (another chain of the same tape) is
// not fitted again: the lines are the ones a plain loop would give.
class InlierFits {
 public:
  InlierFits(const Points& pts, double gate, std::vector<MaskFit>& memo)
      : pts_(pts), gate_(gate), memo_(memo) {}
  // mask[k] = 1 where point k lies within the gate of the line f.
  void inliers(const LineFit& f, Mask& mask) const {
    const size_t m = pts_.size();
    mask.resize(m);
    uint8_t* const in = mask.data();
    const double* const px = pts_.x.data();
    const double* const py = pts_.y.data();
    for (size_t k = 0; k < m; ++k) {
      in[k] = std::abs(px[k] - (f.a * py[k] + f.b)) <= gate_ ? 1 : 0;
    }
  }
  // fit_x_on_y of the set, remembered.
  LineFit fit(const Mask& mask) {
    for (size_t e = 0; e < used_; ++e) {
      if (memo_[e].mask == mask) return memo_[e].fit;
    }
    const LineFit f = fit_x_on_y(pts_, mask);
    if (used_ == memo_.size()) memo_.emplace_back();
    memo_[used_].mask = mask;
    memo_[used_].fit = f;
    ++used_;
    return f;
  }

 private:
  const Points& pts_;
  double gate_;
  std::vector<MaskFit>& memo_;
  size_t used_ = 0;
};

// Candidate lines into sc.cands: one per chain of sc.comps, each fitted on
// its chain, trimmed of its own outliers, then grown to every usable point
// within the residual gate over refine_iterations rounds (so that a tape
// broken by a gap counts once). Support = its inliers.
void fit_candidates(const TapePoseOptions& opt, InlierFits& fits, Scratch& sc);

// The tape among non-empty candidates: the most support; those within
// tie_fraction of it are tied and the one nearest the principal point wins.
LineFit choose_tape(const std::vector<Candidate>& cands, double tie_fraction);

// Sums over the points of the mask about the line (residuals in pixels, fx).
InlierStats inlier_statistics(const Points& pts, const Mask& inliers, const LineFit& line,
                              double fx);

// Standard error of the yaw from the scatter of the inliers about the line
// (unweighted least squares, residuals taken as independent): with
// s^2 = sum r^2 / (N - 2), var a = s^2 / S_yy, var b = s^2 (1/N + mean_y^2 / S_yy),
// cov(a, b) = -mean_y s^2 / S_yy, and tan psi = a sin p + b cos p.
// 0 when it cannot be computed (used > 0 required).
double yaw_sigma(const InlierStats& s, const LineFit& line, double fx, const Geometry& g);

// The covariance of (yaw, offset) from the same scatter (TapePose::covariance):
// with t = tan psi = a sin p + b cos p and offset = c cos psi (b sin p - a cos p)
// (pose_from_centre_line for the line x = a y + b), J = d(psi, offset)/d(a, b),
//   d psi/da = sin p / (1 + t^2),  d psi/db = cos p / (1 + t^2),
//   d offset/da = -c (sin psi (b sin p - a cos p) d psi/da + cos psi cos p),
//   d offset/db = -c (sin psi (b sin p - a cos p) d psi/db - cos psi sin p),
// and cov = J cov(a, b) J^T. Zero when it cannot be computed.
Eigen::Matrix2d pose_covariance(const InlierStats& s, const LineFit& line, double fx,
                                const Geometry& g);

// Position along the tape (metres, from the camera's foot point) of a
// ceiling point seen on normalised row y, for a tape at yaw psi: the heading
// frame's forward distance c (cos p + y sin p) / (sin p - y cos p) (section
// 6; the lateral coordinate does not enter) over cos psi.
double along_tape_m(double y, const Geometry& g, double cos_yaw);

// Pieces of the inliers along the line: sorted by position along the tape,
// split where consecutive inliers are more than 2 rows and more than 2 tape
// widths apart (a branch crossing or a chain end gates a few rows; a gap is
// longer). The longest piece and the pieces chained to it by gaps of at most
// max_gap_m carry the line: the others are cleared from `inliers`. Fills the
// piece fields of `ev` (pieces, pieces_dropped, visible_length_m, span_m,
// max_gap_m). Returns true when a piece was dropped.
bool select_pieces(const Points& pts, double tape_width_m, const TapePoseOptions& opt,
                   const Geometry& g, double yaw_rad, Mask& inliers, Scratch& sc, TapeEvidence& ev);

// Width evidence: up to 32 evenly spaced inlier runs, their edges
// (x_start - 0.5, x_end + 0.5 on their row) undistorted; measured normalised
// width against W (sin p - y cos p) / (c cos psi) (section 3). Slack
// width_slack_px converted at the run's own distorted-to-undistorted scale.
// Fills width_sampled, width_consistent, width_ratio_median of `ev`. Reuses
// sc.u, sc.v, sc.left, sc.right, sc.ratios.
void width_evidence(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                    const CameraConfig& cfg, const TapePoseOptions& opt, const Geometry& g,
                    double yaw_rad, const Mask& inliers, int used, Scratch& sc, TapeEvidence& ev);

// Pitch from the left/right edge lines of the inlier runs, intersected. The
// +X direction in camera axes is (sin psi, sin p cos psi, cos p cos psi) so the
// homogeneous intersection V (scaled to V_y > 0) gives p = atan2(V_y, V_z).
// Sets out.pitch_est_* when the intersection gives a pitch in (0, 90 deg].
// Reuses sc.u, sc.v, sc.left, sc.right, sc.mask_b.
void pitch_from_edges(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                      const Mask& final_inliers, int used, Scratch& sc, TapePose& out);

}  // namespace ceilnav::host::tape_steps
