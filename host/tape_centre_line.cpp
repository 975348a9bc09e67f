#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "host/tape_pose_steps.hpp"

namespace ceilnav::host::tape_steps {

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

Eigen::Matrix2d pose_covariance(const InlierStats& s, const LineFit& line, double fx,
                                const Geometry& g) {
  const double sp = g.sp, cp = g.cp;
  const double nn = s.used, mean_y = nn > 0 ? s.sy / nn : 0.0, s_yy = s.syy - nn * mean_y * mean_y;
  if (!(s.used > 2) || !(s_yy > 0.0)) return Eigen::Matrix2d::Zero();
  const double s2 = s.ss / (fx * fx) / (nn - 2.0);
  Eigen::Matrix2d cov_ab;
  cov_ab << s2 / s_yy, -s2 * mean_y / s_yy, -s2 * mean_y / s_yy,
      s2 * (1.0 / nn + mean_y * mean_y / s_yy);
  const double t = line.a * sp + line.b * cp, psi = std::atan(t);
  const double u = line.b * sp - line.a * cp;  // offset = c cos psi u
  const double dpsi_da = sp / (1.0 + t * t), dpsi_db = cp / (1.0 + t * t);
  Eigen::Matrix2d j;
  j << dpsi_da, dpsi_db, -g.c * (std::sin(psi) * u * dpsi_da + std::cos(psi) * cp),
      -g.c * (std::sin(psi) * u * dpsi_db - std::cos(psi) * sp);
  const Eigen::Matrix2d cov = j * cov_ab * j.transpose();
  return cov.allFinite() ? cov : Eigen::Matrix2d::Zero();
}

double along_tape_m(double y, const Geometry& g, double cos_yaw) {
  return g.c * (g.cp + y * g.sp) / ((g.sp - y * g.cp) * cos_yaw);
}

bool select_pieces(const Points& pts, double tape_width_m, const TapePoseOptions& opt,
                   const Geometry& g, double yaw_rad, Mask& inliers, Scratch& sc,
                   TapeEvidence& ev) {
  const double cos_yaw = std::cos(yaw_rad);
  auto& along = sc.along;
  along.clear();
  for (size_t k = 0; k < pts.size(); ++k) {
    if (inliers[k] == 0) continue;
    along.emplace_back(along_tape_m(pts.y[k], g, cos_yaw), static_cast<int>(k));
  }
  // Inliers come in row order and s grows with the row: usually sorted already.
  if (!std::is_sorted(along.begin(), along.end())) std::sort(along.begin(), along.end());
  const size_t m = along.size();
  if (m == 0) return false;
  // Piece boundaries: piece j is along[begin[j], begin[j + 1]).
  std::vector<size_t>& begin = sc.piece_begin;
  begin.assign(1, 0);
  for (size_t i = 1; i < m; ++i) {
    const int drow = std::abs(pts.row[static_cast<size_t>(along[i].second)] -
                              pts.row[static_cast<size_t>(along[i - 1].second)]);
    if (drow > 2 && along[i].first - along[i - 1].first > 2.0 * tape_width_m) begin.push_back(i);
  }
  begin.push_back(m);
  const size_t pieces = begin.size() - 1;
  const auto first = [&](size_t j) { return along[begin[j]].first; };
  const auto last = [&](size_t j) { return along[begin[j + 1] - 1].first; };
  size_t main = 0;
  for (size_t j = 1; j < pieces; ++j) {
    if (last(j) - first(j) > last(main) - first(main)) main = j;
  }
  const bool limit = opt.max_gap_m > 0.0;
  size_t lo = main, hi = main;
  while (lo > 0 && (!limit || first(lo) - last(lo - 1) <= opt.max_gap_m)) --lo;
  while (hi + 1 < pieces && (!limit || first(hi + 1) - last(hi) <= opt.max_gap_m)) ++hi;
  ev.pieces = static_cast<int>(pieces);
  ev.pieces_dropped = static_cast<int>(pieces - (hi - lo + 1));
  ev.visible_length_m = 0.0;
  ev.max_gap_m = 0.0;
  for (size_t j = lo; j <= hi; ++j) {
    ev.visible_length_m += last(j) - first(j);
    if (j > lo) ev.max_gap_m = std::max(ev.max_gap_m, first(j) - last(j - 1));
  }
  ev.span_m = last(hi) - first(lo);
  // Ends: the chain of the first / last carried inlier along the tape reaches the image border.
  const auto at_border = [&](size_t i) {
    const size_t r = static_cast<size_t>(pts.comp[static_cast<size_t>(along[i].second)]);
    return sc.comp_min_row[r] <= 0 || sc.comp_max_row[r] >= g.height - 1 ||
           sc.comp_min_col[r] <= 0 || sc.comp_max_col[r] >= g.width - 1;
  };
  ev.ends_at_border = (at_border(begin[lo]) ? 1 : 0) + (at_border(begin[hi + 1] - 1) ? 1 : 0);
  for (size_t j = 0; j < pieces; ++j) {
    if (j >= lo && j <= hi) continue;
    for (size_t i = begin[j]; i < begin[j + 1]; ++i) {
      inliers[static_cast<size_t>(along[i].second)] = 0;
    }
  }
  return ev.pieces_dropped > 0;
}

void width_evidence(std::span<const stream::RunRecord> runs, const CameraModel& cam,
                    const CameraConfig& cfg, const TapePoseOptions& opt, const Geometry& g,
                    double yaw_rad, const Mask& inliers, int used, Scratch& sc, TapeEvidence& ev) {
  const Points& pts = sc.pts;
  const size_t stride = static_cast<size_t>(std::max(1, (used + 31) / 32));
  sc.u.clear();
  sc.v.clear();
  std::vector<int>& sampled = sc.sampled;
  sampled.clear();
  size_t phase = 0;
  for (size_t k = 0; k < pts.size(); ++k) {
    if (inliers[k] == 0) continue;
    const bool take = phase == 0;
    if (++phase == stride) phase = 0;
    if (!take) continue;
    sampled.push_back(static_cast<int>(k));
  }
  const size_t e = sampled.size();
  sc.u.resize(2 * e);
  sc.v.resize(2 * e);
  for (size_t i = 0; i < e; ++i) {
    const auto& r = runs[static_cast<size_t>(pts.run[static_cast<size_t>(sampled[i])])];
    sc.u[i] = r.x_start - 0.5;
    sc.u[e + i] = r.x_end + 0.5;
    sc.v[i] = sc.v[e + i] = r.row;
  }
  sc.left.resize(e);
  sc.right.resize(e);
  const std::span<const double> u_all(sc.u), v_all(sc.v);
  cam.normalise(u_all.first(e), v_all.first(e), sc.left.x, sc.left.y);
  cam.normalise(u_all.last(e), v_all.last(e), sc.right.x, sc.right.y);
  const double scale = cfg.tape_width_m / (g.c * std::cos(yaw_rad));
  sc.ratios.clear();
  std::vector<double>& excess = sc.excess;
  excess.clear();
  sc.widths.clear();
  std::vector<double>& weights = sc.weights;
  weights.clear();
  int consistent = 0;
  for (size_t i = 0; i < e; ++i) {
    const double y = 0.5 * (sc.left.y[i] + sc.right.y[i]);
    const double predicted = scale * (g.sp - y * g.cp);
    const double measured = sc.right.x[i] - sc.left.x[i];
    const double run_px = sc.u[e + i] - sc.u[i];
    if (!(predicted > 0.0) || !(measured > 0.0) || !std::isfinite(measured)) continue;
    const double px = run_px / measured;  // distorted pixels per normalised unit, locally
    const double predicted_px = predicted * px;
    const double lo = (1.0 - opt.width_tolerance) * predicted_px - opt.width_slack_px;
    const double hi = (1.0 + opt.width_tolerance) * predicted_px + opt.width_slack_px;
    if (run_px >= lo && run_px <= hi) ++consistent;
    sc.ratios.push_back(measured / predicted);
    excess.push_back(run_px - predicted_px);
    sc.widths.emplace_back(predicted_px, run_px);
    const auto& r = runs[static_cast<size_t>(pts.run[static_cast<size_t>(sampled[i])])];
    weights.push_back(static_cast<double>(r.sum_w) / (r.x_end - r.x_start + 1.0));
  }
  ev.width_sampled = static_cast<int>(sc.ratios.size());
  ev.width_consistent = consistent;
  const auto median = [](std::vector<double>& v) {
    if (v.empty()) return 0.0;
    auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  ev.width_ratio_median = median(sc.ratios);
  ev.width_excess_px_median = median(excess);
  ev.run_weight_median = median(weights);
  // Taper: the medians of the wider and the narrower half (by prediction).
  std::vector<std::pair<double, double>>& w = sc.widths;
  std::sort(w.begin(), w.end());
  const size_t half = w.size() / 2;
  ev.taper_predicted_px = ev.taper_measured_px = 0.0;
  if (half >= 2) {
    std::vector<double>& a = sc.ratios;  // reused: its median is taken
    const auto half_median = [&](size_t from, size_t to, bool measured) {
      a.clear();
      for (size_t i = from; i < to; ++i) a.push_back(measured ? w[i].second : w[i].first);
      return median(a);
    };
    ev.taper_predicted_px =
        half_median(w.size() - half, w.size(), false) - half_median(0, half, false);
    ev.taper_measured_px =
        half_median(w.size() - half, w.size(), true) - half_median(0, half, true);
  }
}

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
    if (pe > 0.0 && pe <= 0.5 * kPi) {  // above 90 deg is no camera pitch
      out.pitch_est_valid = true;
      out.pitch_est_rad = pe;
    }
  }
}

}  // namespace ceilnav::host::tape_steps
