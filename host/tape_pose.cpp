#include "host/tape_pose.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <Eigen/Geometry>

namespace ceilnav::host {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// One centre-line candidate point: a run's intensity-weighted centre.
struct Point {
  double x = 0.0, y = 0.0;  // normalised
  int run = 0;              // index into the input span
  int row = 0;
  int comp = 0;         // root of the run's chain
  bool usable = false;  // passed the width / border / horizon gates
  double weight = 1.0;  // inverse variance of x (relative), see weight_of_run
};

// Least squares x = a y + b in normalised coordinates (rows are exact, the
// measured quantity is the run centre along x).
struct LineFit {
  bool ok = false;
  double a = 0.0, b = 0.0;
};

template <typename Pred>
LineFit fit_x_on_y(const std::vector<Point>& pts, Pred use) {
  int n = 0;
  double sw = 0.0, sy = 0.0, sx = 0.0;
  for (const Point& p : pts) {
    if (!use(p)) continue;
    ++n;
    sw += p.weight;
    sy += p.weight * p.y;
    sx += p.weight * p.x;
  }
  LineFit f;
  if (n < 2 || !(sw > 0.0)) return f;
  const double my = sy / sw, mx = sx / sw;
  double syy = 0.0, sxy = 0.0;
  for (const Point& p : pts) {
    if (!use(p)) continue;
    syy += p.weight * (p.y - my) * (p.y - my);
    sxy += p.weight * (p.y - my) * (p.x - mx);
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

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

struct Candidate {
  LineFit line;
  int support = 0;
  double dist_to_centre = 0.0;
};

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
  const double sp = std::sin(out.pitch_rad), cp = std::cos(out.pitch_rad);
  const double c = cfg.ceiling_above_camera_m();
  if (!(c > 0.0)) {
    out.status = Status::bad_config;
    return out;
  }
  const int width = cfg.image_width, height = cfg.image_height;

  // Runs in (row, x_start) order; the scanner emits them so, but do not rely on it.
  std::vector<int> order(runs.size());
  std::iota(order.begin(), order.end(), 0);
  const bool sorted = std::is_sorted(order.begin(), order.end(), [&](int i, int j) {
    const auto& a = runs[static_cast<size_t>(i)];
    const auto& b = runs[static_cast<size_t>(j)];
    return a.row != b.row ? a.row < b.row : a.x_start < b.x_start;
  });
  if (!sorted) {
    std::sort(order.begin(), order.end(), [&](int i, int j) {
      const auto& a = runs[static_cast<size_t>(i)];
      const auto& b = runs[static_cast<size_t>(j)];
      return a.row != b.row ? a.row < b.row : a.x_start < b.x_start;
    });
  }

  // Connected chains of runs: a run joins a run of the row above when their
  // pixel spans touch (8-connectivity).
  const size_t n = runs.size();
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  {
    size_t prev_begin = 0, prev_end = 0, cur_begin = 0;
    while (cur_begin < n) {
      const int row = runs[static_cast<size_t>(order[cur_begin])].row;
      size_t cur_end = cur_begin;
      while (cur_end < n && runs[static_cast<size_t>(order[cur_end])].row == row) ++cur_end;
      const bool adjacent =
          prev_end > prev_begin && runs[static_cast<size_t>(order[prev_begin])].row + 1 == row;
      if (adjacent) {
        size_t p = prev_begin;
        for (size_t k = cur_begin; k < cur_end; ++k) {
          const auto& r = runs[static_cast<size_t>(order[k])];
          while (p < prev_end && runs[static_cast<size_t>(order[p])].x_end + 1 < r.x_start) ++p;
          for (size_t q = p; q < prev_end; ++q) {
            const auto& s = runs[static_cast<size_t>(order[q])];
            if (s.x_start > r.x_end + 1) break;
            const int ra = find_root(parent, order[k]), rb = find_root(parent, order[q]);
            if (ra != rb) parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
          }
        }
      }
      prev_begin = cur_begin;
      prev_end = cur_end;
      cur_begin = cur_end;
    }
  }

  // Component statistics: size, row extent, and rows holding more than one run.
  std::vector<int> comp_size(n, 0), comp_min_row(n, 1 << 30), comp_max_row(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const int root = find_root(parent, static_cast<int>(i));
    const size_t r = static_cast<size_t>(root);
    ++comp_size[r];
    comp_min_row[r] = std::min(comp_min_row[r], static_cast<int>(runs[i].row));
    comp_max_row[r] = std::max(comp_max_row[r], static_cast<int>(runs[i].row));
  }

  // Centre-line points. Gates: runs touching the left/right image border lose
  // their margin (biased centre); the end rows of a chain inside the image are
  // partly covered by the tape end; rows where a chain splits into several runs;
  // runs wider than the tape can be (T-branch, merged tapes); rows at or below
  // the horizon cannot hold a ceiling point.
  std::vector<Point> pts(n);
  for (size_t k = 0; k < n; ++k) {
    const int i = order[k];
    const auto& r = runs[static_cast<size_t>(i)];
    Point& p = pts[static_cast<size_t>(i)];
    p.run = i;
    p.row = r.row;
    const double xc = r.sum_w > 0 ? static_cast<double>(r.sum_xw) / static_cast<double>(r.sum_w)
                                  : 0.5 * (r.x_start + r.x_end);
    const Eigen::Vector2d xy = cam.normalise(xc, r.row);
    p.x = xy.x();
    p.y = xy.y();
    p.comp = find_root(parent, i);
    p.weight = opt.weighted_fit ? weight_of_run(r, xc, width) : 1.0;
    const size_t root = static_cast<size_t>(find_root(parent, i));
    bool ok = r.x_start > 0 && r.x_end + 1 < width && r.x_end >= r.x_start;
    if (r.row == comp_min_row[root] && r.row > 0) ok = false;
    if (r.row == comp_max_row[root] && r.row + 1 < height) ok = false;
    const bool same_row_before = k > 0 && runs[static_cast<size_t>(order[k - 1])].row == r.row &&
                                 static_cast<size_t>(find_root(parent, order[k - 1])) == root;
    const bool same_row_after = k + 1 < n && runs[static_cast<size_t>(order[k + 1])].row == r.row &&
                                static_cast<size_t>(find_root(parent, order[k + 1])) == root;
    if (same_row_before || same_row_after) ok = false;
    // Horizontal width of the tape image at normalised row y: W (sin p - y cos p) / (c cos psi).
    const double depth = sp - p.y * cp;
    if (!(depth > 1e-9)) ok = false;
    if (ok && opt.max_width_factor > 0.0) {
      const double expected_px = cam.fx() * cfg.tape_width_m * depth / c;
      const double run_px = r.x_end - r.x_start + 1.0;
      if (run_px > opt.max_width_factor * expected_px + opt.width_slack_px) ok = false;
    }
    p.usable = ok && std::isfinite(p.x) && std::isfinite(p.y) && p.weight > 0.0;
  }

  // Candidate lines: one per large chain, each grown to every usable point
  // within the residual gate (so that a tape broken by a gap counts once).
  const double gate = opt.max_residual_px / cam.fx();
  std::vector<std::pair<int, int>> comps;  // (usable points, root)
  {
    std::vector<int> usable_count(n, 0);
    for (size_t i = 0; i < n; ++i) {
      if (pts[i].usable)
        ++usable_count[static_cast<size_t>(find_root(parent, static_cast<int>(i)))];
    }
    for (size_t i = 0; i < n; ++i) {
      if (usable_count[i] >= 2) comps.emplace_back(usable_count[i], static_cast<int>(i));
    }
    std::sort(comps.begin(), comps.end(), std::greater<>());
    if (comps.size() > 4) comps.resize(4);
  }
  const int usable_total = static_cast<int>(
      std::count_if(pts.begin(), pts.end(), [](const Point& p) { return p.usable; }));
  if (usable_total < opt.min_points || comps.empty()) {
    out.status = Status::too_few_points;
    out.points_used = usable_total;
    return out;
  }

  const auto inlier = [gate](const LineFit& f, const Point& p) {
    return p.usable && std::abs(p.x - (f.a * p.y + f.b)) <= gate;
  };
  std::vector<Candidate> cands;
  for (const auto& [count, root] : comps) {
    LineFit f = fit_x_on_y(pts, [&](const Point& p) { return p.usable && p.comp == root; });
    if (!f.ok) continue;
    // Trim the chain's own outliers (noise stuck to the tape) before growing.
    for (int it = 0; it < opt.refine_iterations && f.ok; ++it) {
      LineFit g = fit_x_on_y(pts, [&](const Point& p) { return inlier(f, p); });
      if (!g.ok) break;
      f = g;
    }
    if (!f.ok) continue;
    Candidate cand;
    cand.line = f;
    cand.support = static_cast<int>(
        std::count_if(pts.begin(), pts.end(), [&](const Point& p) { return inlier(f, p); }));
    // Distance of the principal point (0, 0) from the line x = a y + b.
    cand.dist_to_centre = std::abs(f.b) / std::sqrt(1.0 + f.a * f.a);
    cands.push_back(cand);
  }
  if (cands.empty()) {
    out.status = Status::degenerate;
    return out;
  }
  int best_support = 0;
  for (const Candidate& cd : cands) best_support = std::max(best_support, cd.support);
  const Candidate* best = nullptr;
  for (const Candidate& cd : cands) {
    if (cd.support < (1.0 - opt.tie_fraction) * best_support) continue;
    if (best == nullptr || cd.dist_to_centre < best->dist_to_centre) best = &cd;
  }
  const LineFit line = best->line;

  // Final statistics on the inliers.
  int used = 0;
  int row_min = 1 << 30, row_max = -1;
  double ss = 0.0;
  for (const Point& p : pts) {
    if (!inlier(line, p)) continue;
    ++used;
    row_min = std::min(row_min, p.row);
    row_max = std::max(row_max, p.row);
    const double r = (p.x - (line.a * p.y + line.b)) * cam.fx();
    ss += r * r;
  }
  out.points_used = used;
  out.residual_rms_px = used > 0 ? std::sqrt(ss / used) : 0.0;
  {
    const double norm = std::sqrt(1.0 + line.a * line.a);
    out.line_norm = Eigen::Vector3d(1.0, -line.a, -line.b) / norm;
  }
  if (used < opt.min_points) {
    out.status = Status::too_few_points;
    return out;
  }
  if (row_max - row_min < opt.min_row_span_px) {
    out.status = Status::degenerate;
    return out;
  }
  const Status st = pose_from_centre_line(
      out.line_norm, out.pitch_rad, c, opt.max_abs_yaw_deg * kDegToRad, out.yaw_rad, out.offset_m);
  if (st != Status::ok) {
    out.status = st;
    return out;
  }
  // Vanishing point of +X: normalised (tan psi / cos p, tan p) (seed 000 eq. 24-25,
  // with y down). At the zenith it is at infinity.
  if (cp > 1e-6) {
    const Eigen::Vector2d vp(std::tan(out.yaw_rad) / cp, sp / cp);
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
  if (opt.estimate_pitch) {
    std::vector<Point> left, right;
    left.reserve(static_cast<size_t>(used));
    right.reserve(static_cast<size_t>(used));
    // The estimate is biased far beyond its noise (docs), so 48 rows suffice.
    const int stride = std::max(1, used / 48);
    int seen = 0;
    for (const Point& p : pts) {
      if (!inlier(line, p) || (seen++ % stride) != 0) continue;
      const auto& r = runs[static_cast<size_t>(p.run)];
      Point l = p, rr = p;
      l.weight = rr.weight = 1.0;  // edge positions: quantised to pixels, equal noise
      const Eigen::Vector2d a = cam.normalise(r.x_start - 0.5, r.row);
      const Eigen::Vector2d b = cam.normalise(r.x_end + 0.5, r.row);
      l.x = a.x();
      l.y = a.y();
      rr.x = b.x();
      rr.y = b.y();
      left.push_back(l);
      right.push_back(rr);
    }
    const auto all = [](const Point&) { return true; };
    const LineFit fl = fit_x_on_y(left, all), fr = fit_x_on_y(right, all);
    if (fl.ok && fr.ok) {
      Eigen::Vector3d v =
          Eigen::Vector3d(1.0, -fl.a, -fl.b).cross(Eigen::Vector3d(1.0, -fr.a, -fr.b));
      if (v.y() < 0.0) v = -v;
      if (v.allFinite() && v.y() > 1e-12 * v.norm()) {
        const double pe = std::atan2(v.y(), v.z());
        if (pe > 0.0 && pe < 0.5 * kPi + 0.2) {
          out.pitch_est_valid = true;
          out.pitch_est_rad = pe;
        }
      }
    }
  }
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
    const Eigen::Vector2d vp(std::tan(out.yaw_rad) / cp, std::tan(out.pitch_rad));
    const Eigen::Vector2d vp_px = cam.ideal_pixel(vp);
    if (vp_px.allFinite() && vp_px.cwiseAbs().maxCoeff() < 1e9) {
      out.vp_finite = true;
      out.vp_u_px = vp_px.x();
      out.vp_v_px = vp_px.y();
    }
  }
  return out;
}

}  // namespace ceilnav::host
