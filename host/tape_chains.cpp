#include <algorithm>
#include <cmath>
#include <numeric>

#include "host/tape_pose_steps.hpp"

namespace ceilnav::host::tape_steps {

double weight_of_run(const stream::RunRecord& r, double xc, int width) {
  const int a = std::max(0, r.x_start - 1), b = std::min(width - 1, r.x_end + 1);
  const double n = b - a + 1.0, mean = 0.5 * (a + b);
  const double spread = n * (n * n - 1.0) / 12.0 + n * (mean - xc) * (mean - xc);
  const double w = static_cast<double>(r.sum_w);
  return spread > 0.0 && w > 0.0 ? w * w / spread : 0.0;
}

int find_root(std::vector<int>& parent, int i) {
  int* const up = parent.data();
  while (up[i] != i) {
    const int grand = up[up[i]];
    if (grand != up[i]) up[i] = grand;
    i = grand;
  }
  return i;
}

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

ChainStats& chain_of_run(Scratch& sc, int rt) {
  return sc.chains[static_cast<size_t>(sc.chain_of_root[static_cast<size_t>(rt)])];
}

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

}  // namespace ceilnav::host::tape_steps
