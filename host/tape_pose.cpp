#include "host/tape_pose.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace ceilnav::host {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

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

LineFit fit_x_on_y(const Points& pts, const Mask& use) {
  const size_t m = pts.size();
  int n = 0;
  double sw = 0.0, sy = 0.0, sx = 0.0;
  for (size_t k = 0; k < m; ++k) {
    if (use[k] == 0) continue;
    ++n;
    sw += pts.weight[k];
    sy += pts.weight[k] * pts.y[k];
    sx += pts.weight[k] * pts.x[k];
  }
  LineFit f;
  if (n < 2 || !(sw > 0.0)) return f;
  const double my = sy / sw, mx = sx / sw;
  double syy = 0.0, sxy = 0.0;
  for (size_t k = 0; k < m; ++k) {
    if (use[k] == 0) continue;
    syy += pts.weight[k] * (pts.y[k] - my) * (pts.y[k] - my);
    sxy += pts.weight[k] * (pts.y[k] - my) * (pts.x[k] - mx);
  }
  if (!(syy > 1e-18 * sw)) return f;  // all points on one row: slope undefined
  f.a = sxy / syy;
  f.b = mx - f.a * my;
  f.ok = std::isfinite(f.a) && std::isfinite(f.b);
  return f;
}

// Noise of a run centre x_c = sum_xw / sum_w: each of the n pixels of the run
// and its margins carries independent noise sigma, so
//   var(x_c) = sigma^2 sum_i (x_i - x_c)^2 / sum_w^2.
// The relative inverse variance sum_w^2 / sum_i (x_i - x_c)^2 weights the fit;
// the sum has the closed form n (n^2 - 1) / 12 + n (mean - x_c)^2.
double weight_of_run(const stream::RunRecord& r, double xc, int width) {
  const int a = std::max(0, r.x_start - 1), b = std::min(width - 1, r.x_end + 1);
  const double n = b - a + 1.0, mean = 0.5 * (a + b);
  const double spread = n * (n * n - 1.0) / 12.0 + n * (mean - xc) * (mean - xc);
  const double w = static_cast<double>(r.sum_w);
  return spread > 0.0 && w > 0.0 ? w * w / spread : 0.0;
}

// Root of i's tree, halving the path on the way. Every link points from a
// higher index to a lower one, so a root is its tree's lowest index.
int find_root(std::vector<int>& parent, int i) {
  int* const up = parent.data();
  while (up[i] != i) {
    const int grand = up[up[i]];
    if (grand != up[i]) up[i] = grand;
    i = grand;
  }
  return i;
}

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
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// ---------------------------------------------------------------- the steps
// estimate_tape_pose in order: sort_runs, link_chains, chain_extents,
// undistort_run_centres, fit_chain_headings, gate_centre_points,
// collect_points, largest_chains, status_when_too_few, fit_candidates,
// choose_tape, inlier_statistics, yaw_sigma, set_vanishing_point,
// pitch_from_edges (docs/host_maths.md section 4).

// The pitch, the ceiling height and the image size every step reads.
struct Geometry {
  double sp = 0.0, cp = 1.0;  // sin, cos of the pitch
  double c = 0.0;             // ceiling above the camera, metres
  int width = 0, height = 0;
};

// Runs in (row, x_start) order; the scanner emits them so, but do not rely
// on it. Their geometry is copied in that order (k) into sc.row, sc.x_start,
// sc.x_end for the scans below; sc.order[k] is the run's index i in the input.
void sort_runs(std::span<const stream::RunRecord> runs, Scratch& sc) {
  const size_t n = runs.size();
  std::vector<int>& idx = sc.order;
  idx.resize(n);
  std::iota(idx.begin(), idx.end(), 0);
  const auto run_less = [&](int i, int j) {
    const auto& a = runs[static_cast<size_t>(i)];
    const auto& b = runs[static_cast<size_t>(j)];
    return a.row != b.row ? a.row < b.row : a.x_start < b.x_start;
  };
  if (!std::is_sorted(idx.begin(), idx.end(), run_less)) {
    std::sort(idx.begin(), idx.end(), run_less);
  }
  sc.row.resize(n);
  sc.x_start.resize(n);
  sc.x_end.resize(n);
  int* const row_k = sc.row.data();
  int* const xs_k = sc.x_start.data();
  int* const xe_k = sc.x_end.data();
  const int* const idx_k = idx.data();
  for (size_t k = 0; k < n; ++k) {
    const auto& r = runs[static_cast<size_t>(idx_k[k])];
    row_k[k] = r.row;
    xs_k[k] = r.x_start;
    xe_k[k] = r.x_end;
  }
}

// Connected chains of runs (after sort_runs): a run joins a run of the row
// above when their pixel spans touch (8-connectivity). Fills sc.parent, the
// union-find links (from a higher run index i to a lower one; the root of a
// chain is its lowest run index).
void link_chains(size_t n, Scratch& sc) {
  const int* const row_k = sc.row.data();
  const int* const xs_k = sc.x_start.data();
  const int* const xe_k = sc.x_end.data();
  const int* const idx_k = sc.order.data();
  std::vector<int>& parent = sc.parent;
  parent.resize(n);
  std::iota(parent.begin(), parent.end(), 0);
  // label_k[k]: a run of run k's chain, set to the chain's root when k was
  // joined, so that finding the root from it is short.
  sc.label.resize(n);
  int* const label_k = sc.label.data();
  for (size_t k = 0; k < n; ++k) label_k[k] = idx_k[k];
  size_t prev_begin = 0, prev_end = 0, cur_begin = 0;
  while (cur_begin < n) {
    const int row = row_k[cur_begin];
    size_t cur_end = cur_begin;
    while (cur_end < n && row_k[cur_end] == row) ++cur_end;
    const bool adjacent = prev_end > prev_begin && row_k[prev_begin] + 1 == row;
    if (adjacent) {
      size_t p = prev_begin;
      for (size_t k = cur_begin; k < cur_end; ++k) {
        while (p < prev_end && xe_k[p] + 1 < xs_k[k]) ++p;
        int ra = idx_k[k];  // root of run k (a fresh run is its own), tracked
        for (size_t q = p; q < prev_end; ++q) {
          if (xs_k[q] > xe_k[k] + 1) break;
          const int rb = find_root(parent, label_k[q]);
          if (ra != rb) {
            parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
            ra = std::min(ra, rb);
          }
        }
        label_k[k] = ra;
      }
    }
    prev_begin = cur_begin;
    prev_end = cur_end;
    cur_begin = cur_end;
  }
}

// Chain of every run (after link_chains): sc.root by run index i, sc.root_k
// in sorted order k, and per chain (indexed by its root) its row and column
// extent.
void chain_extents(size_t n, Scratch& sc) {
  const int* const row_k = sc.row.data();
  const int* const xs_k = sc.x_start.data();
  const int* const xe_k = sc.x_end.data();
  const int* const idx_k = sc.order.data();
  const std::vector<int>& parent = sc.parent;
  sc.root.resize(n);
  sc.root_k.resize(n);
  sc.comp_min_row.assign(n, 1 << 30);
  sc.comp_max_row.assign(n, -1);
  sc.comp_min_col.assign(n, 1 << 30);
  sc.comp_max_col.assign(n, -1);
  int* const root = sc.root.data();
  int* const root_k = sc.root_k.data();
  int* const comp_min_row = sc.comp_min_row.data();
  int* const comp_max_row = sc.comp_max_row.data();
  int* const comp_min_col = sc.comp_min_col.data();
  int* const comp_max_col = sc.comp_max_col.data();
  // Links point to lower indices: one pass upwards finds every root.
  for (size_t i = 0; i < n; ++i) {
    const int up = parent[i];
    root[i] = up == static_cast<int>(i) ? up : root[static_cast<size_t>(up)];
  }
  for (size_t k = 0; k < n; ++k) {
    const int rt = root[static_cast<size_t>(idx_k[k])];
    root_k[k] = rt;
    const size_t r = static_cast<size_t>(rt);
    comp_min_row[r] = std::min(comp_min_row[r], row_k[k]);
    comp_max_row[r] = std::max(comp_max_row[r], row_k[k]);
    comp_min_col[r] = std::min(comp_min_col[r], xs_k[k]);
    comp_max_col[r] = std::max(comp_max_col[r], xe_k[k]);
  }
}

// Run centres x_c = sum_xw / sum_w (the span's middle when sum_w is 0) in
// pixels (sc.u, sc.v) and undistorted all at once (sc.x, sc.y), by run index.
void undistort_run_centres(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                           Scratch& sc) {
  const size_t n = runs.size();
  sc.u.resize(n);
  sc.v.resize(n);
  sc.x.resize(n);
  sc.y.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& r = runs[i];
    sc.u[i] = r.sum_w > 0 ? static_cast<double>(r.sum_xw) / static_cast<double>(r.sum_w)
                          : 0.5 * (r.x_start + r.x_end);
    sc.v[i] = r.row;
  }
  cam.normalise(sc.u, sc.v, sc.x, sc.y);
}

// The chain (sc.chains) of a run's root.
ChainStats& chain_of_run(Scratch& sc, int rt) {
  return sc.chains[static_cast<size_t>(sc.chain_of_root[static_cast<size_t>(rt)])];
}

// Heading of each chain, for the width gate: a tape at heading psi is
// 1 / cos psi wider along a row than at psi = 0 (host_maths.md section 3).
// Each chain's run centres (ceiling rows only) are fitted with x = a y + b,
// tan psi = a sin p + b cos p; |psi| is capped at max_abs_yaw_deg. A branch
// crossing or a merge adds a few rows to a chain; the fit is its tape's.
// Numbers the chains (sc.chain_of_root, sc.chain_root) and fills sc.chains'
// sums and headings.
void fit_chain_headings(size_t n, const Geometry& g, const TapePoseOptions& opt, Scratch& sc) {
  const double sp = g.sp, cp = g.cp;
  const int* const root = sc.root.data();
  const double max_tan_yaw = std::tan(std::min(opt.max_abs_yaw_deg, 89.0) * kDegToRad);
  sc.chain_of_root.resize(n);
  sc.chain_root.clear();
  int* const chain_of_root = sc.chain_of_root.data();
  for (size_t i = 0; i < n; ++i) {
    if (root[i] != static_cast<int>(i)) continue;
    chain_of_root[i] = static_cast<int>(sc.chain_root.size());
    sc.chain_root.push_back(static_cast<int>(i));
  }
  std::vector<ChainStats>& chains = sc.chains;
  chains.assign(sc.chain_root.size(), ChainStats{});
  {
    // Runs of one chain mostly come in a row: sum in registers, store on a change.
    ChainStats acc;
    int acc_root = -1;
    const auto flush = [&] {
      if (acc_root < 0) return;
      ChainStats& ch = chain_of_run(sc, acc_root);
      ch.n += acc.n;
      ch.sy += acc.sy;
      ch.sx += acc.sx;
      ch.syy += acc.syy;
      ch.sxy += acc.sxy;
      acc = ChainStats{};
    };
    for (size_t i = 0; i < n; ++i) {
      const double px = sc.x[i], py = sc.y[i];
      if (!(sp - py * cp > 1e-9) || !std::isfinite(px) || !std::isfinite(py)) continue;
      if (root[i] != acc_root) {
        flush();
        acc_root = root[i];
      }
      acc.n += 1.0;
      acc.sy += py;
      acc.sx += px;
      acc.syy += py * py;
      acc.sxy += py * px;
    }
    flush();
  }
  for (ChainStats& ch : chains) {
    if (ch.n < 2.0) continue;
    const double my = ch.sy / ch.n, mx = ch.sx / ch.n;
    const double syy = ch.syy - ch.n * my * my, sxy = ch.sxy - ch.n * my * mx;
    if (!(syy > 1e-18 * ch.n)) {
      ch.steep = true;  // one row
      continue;
    }
    const double a = sxy / syy, b = mx - a * my;
    const double tan_yaw = a * sp + b * cp;
    if (!std::isfinite(tan_yaw)) continue;
    ch.steep = std::abs(tan_yaw) > max_tan_yaw;
    ch.inv_cos_yaw = std::sqrt(1.0 + std::min(tan_yaw * tan_yaw, max_tan_yaw * max_tan_yaw));
  }
}

// Centre-line points: sc.usable[i] = 1 and sc.w[i] = its weight for a run
// that passes every gate. Gates: runs touching the left/right image border
// lose their margin (biased centre); the end rows of a chain inside the image
// are partly covered by the tape end; rows where a chain splits into several
// runs; runs wider than the tape can be (T-branch, merged tapes); rows at or
// below the horizon cannot hold a ceiling point. Also counts each chain's
// pixels on ceiling rows and those in too-wide runs (ChainStats).
void gate_centre_points(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                        const CameraConfig& cfg, const TapePoseOptions& opt, const Geometry& g,
                        Scratch& sc) {
  const size_t n = runs.size();
  const double sp = g.sp, cp = g.cp, c = g.c;
  const int width = g.width, height = g.height;
  const int* const row_k = sc.row.data();
  const int* const xs_k = sc.x_start.data();
  const int* const xe_k = sc.x_end.data();
  const int* const idx_k = sc.order.data();
  const int* const root_k = sc.root_k.data();
  const int* const comp_min_row = sc.comp_min_row.data();
  const int* const comp_max_row = sc.comp_max_row.data();
  sc.usable.assign(n, 0);
  sc.w.resize(n);
  uint8_t* const usable = sc.usable.data();
  double* const weight_i = sc.w.data();
  const double* const xc_i = sc.u.data();
  const double* const x_i = sc.x.data();
  const double* const y_i = sc.y.data();
  const bool weighted = opt.weighted_fit;
  const double max_width_factor = opt.max_width_factor, width_slack_px = opt.width_slack_px;
  const double width_scale = cam.fx() * cfg.tape_width_m;
  for (size_t k = 0; k < n; ++k) {
    const size_t i = static_cast<size_t>(idx_k[k]);
    const int row = row_k[k], xs = xs_k[k], xe = xe_k[k];
    const double px = x_i[i], py = y_i[i];
    const double weight = weighted ? weight_of_run(runs[i], xc_i[i], width) : 1.0;
    const int rt = root_k[k];
    const size_t rts = static_cast<size_t>(rt);
    bool ok = xs > 0 && xe + 1 < width && xe >= xs;
    if (row == comp_min_row[rts] && row > 0) ok = false;
    if (row == comp_max_row[rts] && row + 1 < height) ok = false;
    const bool same_row_before = k > 0 && row_k[k - 1] == row && root_k[k - 1] == rt;
    const bool same_row_after = k + 1 < n && row_k[k + 1] == row && root_k[k + 1] == rt;
    if (same_row_before || same_row_after) ok = false;
    // Horizontal width of the tape image at normalised row y: W (sin p - y cos p) / (c cos psi).
    const double depth = sp - py * cp;
    if (!(depth > 1e-9)) ok = false;
    ChainStats& ch = chain_of_run(sc, rt);
    if (depth > 1e-9) ch.pixels += xe - xs + 1;
    if (depth > 1e-9 && max_width_factor > 0.0) {
      const double expected_px = width_scale * depth / c * ch.inv_cos_yaw;
      const double run_px = xe - xs + 1.0;
      if (run_px > max_width_factor * expected_px + width_slack_px) {
        ok = false;
        ch.too_wide_pixels += xe - xs + 1;
      }
    }
    if (ok && std::isfinite(px) && std::isfinite(py) && weight > 0.0) {
      usable[i] = 1;
      weight_i[i] = weight;
    }
  }
}

// The usable points (gate_centre_points) into sc.pts, in run index order
// (the order every sum below runs in).
void collect_points(std::span<const stream::RunRecord> runs, Scratch& sc) {
  const size_t n = runs.size();
  Points& pts = sc.pts;
  pts.resize(static_cast<size_t>(std::count(sc.usable.begin(), sc.usable.end(), uint8_t{1})));
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {
    if (sc.usable[i] == 0) continue;
    pts.x[k] = sc.x[i];
    pts.y[k] = sc.y[i];
    pts.weight[k] = sc.w[i];
    pts.row[k] = runs[i].row;
    pts.run[k] = static_cast<int>(i);
    pts.comp[k] = sc.root[i];
    ++k;
  }
}

// The (at most 4) chains with most usable points, at least 2, into sc.comps
// as (usable points, root), most first.
void largest_chains(size_t n, Scratch& sc) {
  const Points& pts = sc.pts;
  std::vector<std::pair<int, int>>& comps = sc.comps;
  comps.clear();
  std::vector<int>& usable_count = sc.usable_count;
  usable_count.assign(n, 0);
  for (size_t k = 0; k < pts.size(); ++k) ++usable_count[static_cast<size_t>(pts.comp[k])];
  for (size_t i = 0; i < n; ++i) {
    if (usable_count[i] >= 2) comps.emplace_back(usable_count[i], static_cast<int>(i));
  }
  std::sort(comps.begin(), comps.end(), std::greater<>());
  if (comps.size() > 4) comps.resize(4);
}

// The status when too few centre-line points remain. A chain spanning
// min_row_span_px rows or columns is tape-like, smaller ones are noise
// specks: none -> no_tape. A tape-like chain runs along the horizon when its
// heading is beyond max_abs_yaw_deg, it lies on one row, or most of its
// pixels are in runs too wide even for that heading: all of them -> degenerate.
// Otherwise too_few_points.
Status status_when_too_few(const TapePoseOptions& opt, const Scratch& sc) {
  int tape_like = 0, along_horizon = 0;
  for (size_t ci = 0; ci < sc.chain_root.size(); ++ci) {
    const size_t r = static_cast<size_t>(sc.chain_root[ci]);
    if (sc.comp_max_row[r] - sc.comp_min_row[r] < opt.min_row_span_px &&
        sc.comp_max_col[r] - sc.comp_min_col[r] < opt.min_row_span_px) {
      continue;
    }
    ++tape_like;
    const ChainStats& ch = sc.chains[ci];
    if (ch.steep || 2 * ch.too_wide_pixels > ch.pixels) ++along_horizon;
  }
  return tape_like == 0               ? Status::no_tape
         : along_horizon == tape_like ? Status::degenerate
                                      : Status::too_few_points;
}

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
void fit_candidates(const TapePoseOptions& opt, InlierFits& fits, Scratch& sc) {
  const Points& pts = sc.pts;
  const size_t m = pts.size();
  Mask& cur = sc.mask_a;
  Mask& next = sc.mask_b;
  std::vector<Candidate>& cands = sc.cands;
  cands.clear();
  for (const auto& [count, comp_root] : sc.comps) {
    cur.resize(m);
    uint8_t* const in = cur.data();
    const int* const pc = pts.comp.data();
    for (size_t k = 0; k < m; ++k) in[k] = pc[k] == comp_root ? 1 : 0;
    LineFit f = fits.fit(cur);
    if (!f.ok) continue;
    // Trim the chain's own outliers (noise stuck to the tape) before growing.
    // `cur` is the set f was fitted on; `next` is inlier(f).
    bool next_is_inliers = false;
    for (int it = 0; it < opt.refine_iterations && f.ok; ++it) {
      fits.inliers(f, next);
      next_is_inliers = true;
      if (next == cur) break;  // the refit would give f again
      const LineFit g = fits.fit(next);
      if (!g.ok) break;
      f = g;
      std::swap(cur, next);
      next_is_inliers = false;
    }
    if (!f.ok) continue;
    if (!next_is_inliers) fits.inliers(f, next);
    Candidate cand;
    cand.line = f;
    cand.support = static_cast<int>(std::count(next.begin(), next.end(), uint8_t{1}));
    // Distance of the principal point (0, 0) from the line x = a y + b.
    cand.dist_to_centre = std::abs(f.b) / std::sqrt(1.0 + f.a * f.a);
    cands.push_back(cand);
  }
}

// The tape among non-empty candidates: the most support; those within
// tie_fraction of it are tied and the one nearest the principal point wins.
LineFit choose_tape(const std::vector<Candidate>& cands, double tie_fraction) {
  int best_support = 0;
  for (const Candidate& cd : cands) best_support = std::max(best_support, cd.support);
  const Candidate* best = nullptr;
  for (const Candidate& cd : cands) {
    if (cd.support < (1.0 - tie_fraction) * best_support) continue;
    if (best == nullptr || cd.dist_to_centre < best->dist_to_centre) best = &cd;
  }
  return best->line;
}

// Sums over the final inliers of the chosen line.
struct InlierStats {
  int used = 0;
  int row_min = 1 << 30, row_max = -1;
  double ss = 0.0;  // sum of squared residuals, pixels^2
  double sy = 0.0, syy = 0.0;
};

InlierStats inlier_statistics(const Points& pts, const Mask& inliers, const LineFit& line,
                              double fx) {
  InlierStats s;
  for (size_t k = 0; k < pts.size(); ++k) {
    if (inliers[k] == 0) continue;
    ++s.used;
    s.row_min = std::min(s.row_min, pts.row[k]);
    s.row_max = std::max(s.row_max, pts.row[k]);
    const double r = (pts.x[k] - (line.a * pts.y[k] + line.b)) * fx;
    s.ss += r * r;
    s.sy += pts.y[k];
    s.syy += pts.y[k] * pts.y[k];
  }
  return s;
}

// Standard error of the yaw from the scatter of the inliers about the line
// (unweighted least squares, residuals taken as independent): with
// s^2 = sum r^2 / (N - 2), var a = s^2 / S_yy, var b = s^2 (1/N + mean_y^2 / S_yy),
// cov(a, b) = -mean_y s^2 / S_yy, and tan psi = a sin p + b cos p.
// 0 when it cannot be computed (used > 0 required).
double yaw_sigma(const InlierStats& s, const LineFit& line, double fx, const Geometry& g) {
  const double sp = g.sp, cp = g.cp;
  const double nn = s.used, mean_y = s.sy / nn, s_yy = s.syy - nn * mean_y * mean_y;
  const double s2 = s.used > 2 ? s.ss / (fx * fx) / (nn - 2.0) : 0.0;
  const double tan_yaw = line.a * sp + line.b * cp;
  if (s_yy > 0.0) {
    const double var_tan = s2 * (sp * sp / s_yy + cp * cp * (1.0 / nn + mean_y * mean_y / s_yy) -
                                 2.0 * sp * cp * mean_y / s_yy);
    const double sigma = std::sqrt(std::max(0.0, var_tan)) / (1.0 + tan_yaw * tan_yaw);
    if (std::isfinite(sigma)) return sigma;
  }
  return 0.0;
}

// out.vp_* from the vanishing point of +X in normalised coordinates, when its
// ideal pixel is finite and within 1e9 px.
void set_vanishing_point(const Eigen::Vector2d& vp, const CameraModel& cam, TapePose& out) {
  const Eigen::Vector2d vp_px = cam.ideal_pixel(vp);
  if (vp_px.allFinite() && vp_px.cwiseAbs().maxCoeff() < 1e9) {
    out.vp_finite = true;
    out.vp_u_px = vp_px.x();
    out.vp_v_px = vp_px.y();
  }
}

// Pitch from the left/right edge lines of the inlier runs, intersected. The
// +X direction in camera axes is (sin psi, sin p cos psi, cos p cos psi) so the
// homogeneous intersection V (scaled to V_y > 0) gives p = atan2(V_y, V_z).
// Sets out.pitch_est_* when the intersection gives a pitch in (0, 90 deg + 0.2).
// Reuses sc.u, sc.v, sc.left, sc.right, sc.mask_b.
void pitch_from_edges(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                      const Mask& final_inliers, int used, Scratch& sc, TapePose& out) {
  const Points& pts = sc.pts;
  const size_t m = pts.size();
  // The estimate is biased far beyond its noise (docs), so 48 rows suffice.
  // Edge positions are quantised to pixels: equal noise, unit weights.
  const size_t stride = static_cast<size_t>(std::max(1, used / 48));
  size_t edges = 0;  // sampled inliers
  {
    size_t phase = 0;  // inliers seen, modulo stride
    for (size_t k = 0; k < m; ++k) {
      if (final_inliers[k] == 0) continue;
      if (phase == 0) ++edges;
      if (++phase == stride) phase = 0;
    }
  }
  // Left edges in u/v [0, edges), right edges in [edges, 2 edges).
  sc.u.resize(2 * edges);
  sc.v.resize(2 * edges);
  {
    size_t e = 0, phase = 0;
    for (size_t k = 0; k < m; ++k) {
      if (final_inliers[k] == 0) continue;
      const bool take = phase == 0;
      if (++phase == stride) phase = 0;
      if (!take) continue;
      const auto& r = runs[static_cast<size_t>(pts.run[k])];
      sc.u[e] = r.x_start - 0.5;
      sc.u[edges + e] = r.x_end + 0.5;
      sc.v[e] = sc.v[edges + e] = r.row;
      ++e;
    }
  }
  Points& left = sc.left;
  Points& right = sc.right;
  left.resize(edges);
  right.resize(edges);
  const std::span<const double> u_all(sc.u), v_all(sc.v);
  cam.normalise(u_all.first(edges), v_all.first(edges), left.x, left.y);
  cam.normalise(u_all.last(edges), v_all.last(edges), right.x, right.y);
  std::fill(left.weight.begin(), left.weight.end(), 1.0);
  std::fill(right.weight.begin(), right.weight.end(), 1.0);
  Mask& all = sc.mask_b;
  all.assign(edges, 1);
  const LineFit fl = fit_x_on_y(left, all), fr = fit_x_on_y(right, all);
  if (!fl.ok || !fr.ok) return;
  Eigen::Vector3d v = Eigen::Vector3d(1.0, -fl.a, -fl.b).cross(Eigen::Vector3d(1.0, -fr.a, -fr.b));
  if (v.y() < 0.0) v = -v;
  if (v.allFinite() && v.y() > 1e-12 * v.norm()) {
    const double pe = std::atan2(v.y(), v.z());
    if (pe > 0.0 && pe < 0.5 * kPi + 0.2) {
      out.pitch_est_valid = true;
      out.pitch_est_rad = pe;
    }
  }
}

}  // namespace

Status pose_from_centre_line(const Eigen::Vector3d& line, double pitch_rad,
                             double ceiling_above_camera_m, double max_abs_yaw_rad, double& yaw_rad,
                             double& offset_m) {
  if (!line.allFinite()) return Status::degenerate;
  const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
  const double l1 = line.x(), l2 = line.y(), l3 = line.z();
  // The back-projected plane has world normal n = R^T l; it contains +X:
  //   n_x = l1 sin psi + cos psi (l2 sin p + l3 cos p) = 0.
  const double num = -(l2 * sp + l3 * cp);
  if (!(std::abs(l1) > 0.0) || std::abs(num) > std::tan(max_abs_yaw_rad) * std::abs(l1)) {
    return Status::degenerate;
  }
  const double yaw = std::atan(num / l1);
  // It contains the tape (s, -offset, c) relative to the camera:
  //   offset = n_z c / n_y,  n_y = -l1 / cos psi,  n_z = -l2 cos p + l3 sin p.
  const double offset = ceiling_above_camera_m * std::cos(yaw) * (l2 * cp - l3 * sp) / l1;
  if (!std::isfinite(yaw) || !std::isfinite(offset)) return Status::degenerate;
  yaw_rad = yaw;
  offset_m = offset;
  return Status::ok;
}

TapePose estimate_tape_pose(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                            const CameraConfig& cfg, const TapePoseOptions& opt) {
  TapePose out;
  out.method = "runs_centre_line";
  out.pitch_rad = cfg.camera_pitch_deg * kDegToRad;
  out.points_total = static_cast<int>(runs.size());
  if (runs.empty()) {
    out.status = Status::no_tape;
    return out;
  }
  Geometry g;
  g.sp = std::sin(out.pitch_rad);
  g.cp = std::cos(out.pitch_rad);
  g.c = cfg.ceiling_above_camera_m();
  if (!(g.c > 0.0)) {
    out.status = Status::bad_config;
    return out;
  }
  g.width = cfg.image_width;
  g.height = cfg.image_height;

  Scratch& sc = scratch();
  const size_t n = runs.size();
  // Runs into chains, each chain's heading, the centre-line points.
  sort_runs(runs, sc);
  link_chains(n, sc);
  chain_extents(n, sc);
  undistort_run_centres(runs, cam, sc);
  fit_chain_headings(n, g, opt, sc);
  gate_centre_points(runs, cam, cfg, opt, g, sc);
  collect_points(runs, sc);
  const Points& pts = sc.pts;
  const int usable_total = static_cast<int>(pts.size());

  // Candidate lines from the largest chains; the tape among them.
  largest_chains(n, sc);
  const Status too_few = status_when_too_few(opt, sc);
  if (usable_total < opt.min_points || sc.comps.empty()) {
    out.status = too_few;
    out.points_used = usable_total;
    return out;
  }
  InlierFits fits(pts, opt.max_residual_px / cam.fx(), sc.memo);
  fit_candidates(opt, fits, sc);
  if (sc.cands.empty()) {
    out.status = Status::degenerate;
    return out;
  }
  const LineFit line = choose_tape(sc.cands, opt.tie_fraction);

  // Final statistics on the inliers; the gates on them.
  Mask& final_inliers = sc.mask_a;
  fits.inliers(line, final_inliers);
  const InlierStats stats = inlier_statistics(pts, final_inliers, line, cam.fx());
  out.points_used = stats.used;
  out.residual_rms_px = stats.used > 0 ? std::sqrt(stats.ss / stats.used) : 0.0;
  {
    const double norm = std::sqrt(1.0 + line.a * line.a);
    out.line_norm = Eigen::Vector3d(1.0, -line.a, -line.b) / norm;
  }
  if (stats.used < opt.min_points) {
    out.status = too_few;
    return out;
  }
  if (stats.row_max - stats.row_min < opt.min_row_span_px) {
    out.status = Status::degenerate;
    return out;
  }
  out.yaw_sigma_rad = yaw_sigma(stats, line, cam.fx(), g);
  if (out.yaw_sigma_rad > opt.max_yaw_sigma_deg * kDegToRad) {
    out.status = Status::too_few_points;
    return out;
  }

  // Yaw and offset, the vanishing point, the pitch estimate.
  const Status st =
      pose_from_centre_line(out.line_norm, out.pitch_rad, g.c, opt.max_abs_yaw_deg * kDegToRad,
                            out.yaw_rad, out.offset_m);
  if (st != Status::ok) {
    out.status = st;
    return out;
  }
  // Vanishing point of +X: normalised (tan psi / cos p, tan p) (seed 000 eq. 24-25,
  // with y down). At the zenith it is at infinity.
  if (g.cp > 1e-6) {
    set_vanishing_point(Eigen::Vector2d(std::tan(out.yaw_rad) / g.cp, g.sp / g.cp), cam, out);
  }
  if (opt.estimate_pitch) pitch_from_edges(runs, cam, final_inliers, stats.used, sc, out);
  out.status = Status::ok;
  return out;
}

TapePose zenith_pose_from_moments(const stream::MomentResults& m, const CameraModel& cam,
                                  const CameraConfig& cfg, bool use_mask) {
  TapePose out;
  out.method = "zenith_moments";
  out.pitch_rad = cfg.camera_pitch_deg * kDegToRad;
  const auto& mm = use_mask ? m.mask : m.grey;
  if (mm[stream::kM00] == 0) {
    out.status = Status::no_tape;
    return out;
  }
  const double m00 = static_cast<double>(mm[stream::kM00]);
  const double xb = static_cast<double>(mm[stream::kM10]) / m00;
  const double yb = static_cast<double>(mm[stream::kM01]) / m00;
  const double mu20 = static_cast<double>(mm[stream::kM20]) / m00 - xb * xb;
  const double mu11 = static_cast<double>(mm[stream::kM11]) / m00 - xb * yb;
  const double mu02 = static_cast<double>(mm[stream::kM02]) / m00 - yb * yb;
  const double trace = mu20 + mu02;
  const double aniso = std::hypot(mu20 - mu02, 2.0 * mu11);
  // (l1 - l2) / (l1 + l2) of the covariance: 0 for a disc, -> 1 for a thin band.
  if (!(trace > 0.0) || !(aniso > 0.5 * trace)) {
    out.status = Status::degenerate;
    return out;
  }
  // Major axis at angle theta from the +u axis towards +v (rows down), in pixels.
  const double theta = 0.5 * std::atan2(2.0 * mu11, mu20 - mu02);
  const Eigen::Vector2d dir(std::cos(theta) / cam.fx(), std::sin(theta) / cam.fy());
  const Eigen::Vector2d pt((xb - cam.cx()) / cam.fx(), (yb - cam.cy()) / cam.fy());
  const Eigen::Vector3d l(dir.y(), -dir.x(), dir.x() * pt.y() - dir.y() * pt.x());
  out.line_norm = l / l.head<2>().norm();
  if (out.line_norm.x() < 0.0) out.line_norm = -out.line_norm;
  out.points_total = out.points_used = 0;
  const Status st =
      pose_from_centre_line(out.line_norm, out.pitch_rad, cfg.ceiling_above_camera_m(),
                            85.0 * kDegToRad, out.yaw_rad, out.offset_m);
  out.status = st;
  if (st != Status::ok) return out;
  const double cp = std::cos(out.pitch_rad);
  if (cp > 1e-6) {
    set_vanishing_point(Eigen::Vector2d(std::tan(out.yaw_rad) / cp, std::tan(out.pitch_rad)), cam,
                        out);
  }
  return out;
}

}  // namespace ceilnav::host
