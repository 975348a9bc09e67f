#include "host/junction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>

#include <Eigen/Core>

namespace ceilnav::host {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Ceiling plane in the tape's frame (docs/host_maths.md section 9): s along
// the tape from the camera's foot point, l from the fitted centre line (left +).
struct TapeFrame {
  double sp, cp, sy, cy, c, offset;

  // Normalised ray (x, y) -> (s, l); false at or below the horizon.
  bool to_ceiling(double x, double y, double& s, double& l) const {
    const double d = sp - y * cp;
    if (!(d > 1e-9)) return false;
    const double t = c / d;
    s = t * (x * sy + y * sp * cy + cp * cy);
    l = t * (-x * cy + y * sp * sy + cp * sy) + offset;
    return true;
  }
  // (s, l) -> normalised ray; false behind the camera.
  bool to_ray(double s, double l, Eigen::Vector2d& xy) const {
    const double yl = l - offset;
    const double xc = sy * s - cy * yl;
    const double yc = sp * cy * s + sp * sy * yl - cp * c;
    const double zc = cp * cy * s + cp * sy * yl + sp * c;
    if (!(zc > 1e-9)) return false;
    xy = Eigen::Vector2d(xc / zc, yc / zc);
    return true;
  }
};

// A stretch of one run's pixels on one side of the band, with its ceiling moments.
struct Piece {
  int row = 0, u0 = 0, u1 = 0, run = 0;
  int side = 0;                                             // +1 left, -1 right
  double a = 0, as = 0, al = 0, ass = 0, all = 0, asl = 0;  // area moments
  double attach = 1e9;  // inner end (min |l|) minus the band half-width, metres
  double attach_limit = 0.0;
  double foot_s = 0.0;  // metres per pixel along s (area-weighted below)
};

struct Interval {
  double a, b, foot_s;
  double weight;  // the run's sum_w over the tape's predicted width, grey
  double width;   // the run's extent across the tape (band pixels), metres
  double foot_l;  // metres per pixel across the tape
};

struct Branch {
  int side = 0;  // +1 left, -1 right, 2 both
  double s0 = 0.0, angle = 0.0;
  double foot_s = 0.0;  // mean metres per pixel along s over the strip
  JunctionEvidence ev;
};

int find(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

// A component of branch pixels as a strip (moments): accepted when it is one
// straight strip of the tape width, about perpendicular to the tape, joined to
// the band and long enough.
bool strip_of(const std::vector<const Piece*>& ps, double tape_w, const JunctionOptions& opt,
              Branch& out) {
  double a = 0, as = 0, al = 0, ass = 0, all = 0, asl = 0, foot = 0;
  bool attached = false;
  for (const Piece* p : ps) {
    a += p->a;
    as += p->as;
    al += p->al;
    ass += p->ass;
    all += p->all;
    asl += p->asl;
    foot += p->foot_s * p->a;
    attached = attached || p->attach <= p->attach_limit;
  }
  if (!(a > 0.0) || !attached) return false;
  const double ms = as / a, ml = al / a;
  const double vss = ass / a - ms * ms, vll = all / a - ml * ml, vsl = asl / a - ms * ml;
  const double tr = vss + vll, dif = std::hypot(vss - vll, 2.0 * vsl);
  const double l1 = 0.5 * (tr + dif), l2 = std::max(0.0, 0.5 * (tr - dif));
  const double phi = 0.5 * std::atan2(2.0 * vsl, vss - vll);  // major axis from +s
  double ds = std::cos(phi), dl = std::sin(phi);
  const int side = ps.front()->side;
  if (dl * side < 0.0) {  // point away from the tape
    ds = -ds;
    dl = -dl;
  }
  JunctionEvidence& ev = out.ev;
  ev.branch_runs = static_cast<int>(ps.size());
  ev.branch_area_m2 = a;
  ev.branch_length_m = std::sqrt(12.0 * l1);
  ev.branch_thickness_m = std::sqrt(12.0 * l2);
  ev.thickness_allowance_m = opt.width_tolerance * tape_w + opt.width_slack_px * foot / a;
  ev.branch_fill = a / std::max(1e-12, ev.branch_thickness_m * ev.branch_length_m);
  out.side = side;
  out.foot_s = foot / a;
  out.angle = std::atan2(std::abs(dl), ds);
  if (ev.branch_length_m < opt.min_branch_length_m) return false;
  if (std::abs(ev.branch_thickness_m - tape_w) > ev.thickness_allowance_m) return false;
  if (std::abs(ev.branch_fill - 1.0) > opt.fill_tolerance) return false;
  if (std::abs(out.angle - 0.5 * kPi) > opt.max_angle_error_deg * kPi / 180.0) return false;
  // The strip's axis crosses the tape's centre line (l = 0) at s0.
  out.s0 = ms - ml * ds / dl;
  return std::isfinite(out.s0);
}

}  // namespace

std::string_view to_string(JunctionKind k) {
  switch (k) {
    case JunctionKind::none:
      return "none";
    case JunctionKind::t_branch:
      return "t_branch";
    case JunctionKind::l_turn:
      return "l_turn";
    case JunctionKind::tape_end:
      return "tape_end";
  }
  return "?";
}

std::string_view to_string(JunctionSide s) {
  switch (s) {
    case JunctionSide::none:
      return "none";
    case JunctionSide::left:
      return "left";
    case JunctionSide::right:
      return "right";
    case JunctionSide::both:
      return "both";
  }
  return "?";
}

std::vector<Junction> detect_junctions(const FrameOutcome& frame, const CameraModel& cam,
                                       const CameraConfig& cfg, const JunctionOptions& opt) {
  return detect_junctions(frame.runs, frame.settings, cam, cfg, frame.pose, opt);
}

std::vector<Junction> detect_junctions(std::span<const stream::RunRecord> runs,
                                       const ThresholdSettings& settings, const CameraModel& cam,
                                       const CameraConfig& cfg, const TapePose& pose,
                                       const JunctionOptions& opt) {
  std::vector<Junction> found;
  if (pose.status != Status::ok || std::strcmp(pose.method, "runs_centre_line") != 0) return found;
  const double c = cfg.ceiling_above_camera_m(), tape_w = cfg.tape_width_m;
  if (!(c > 0.0) || !(tape_w > 0.0) || runs.empty()) return found;
  const TapeFrame tf{std::sin(pose.pitch_rad),
                     std::cos(pose.pitch_rad),
                     std::sin(pose.yaw_rad),
                     std::cos(pose.yaw_rad),
                     c,
                     pose.offset_m};

  const double margin_px = 2.0;
  // The ceiling point (s, l) is seen: inside the image by margin_px.
  const auto in_image = [&](double s, double l) {
    Eigen::Vector2d r;
    if (!tf.to_ray(s, l, r)) return false;
    const Eigen::Vector2d p = cam.distort_to_pixel(r);
    return p.x() >= margin_px && p.y() >= margin_px && p.x() <= cfg.image_width - 1 - margin_px &&
           p.y() <= cfg.image_height - 1 - margin_px;
  };
  // The view of the band: the s range over which the centre line is inside
  // the image and the tape at least min_tape_width_px wide.
  const auto in_view = [&](double s) {
    Eigen::Vector2d r1, r2;
    if (!in_image(s, 0.0) || !tf.to_ray(s, -0.5 * tape_w, r1) || !tf.to_ray(s, 0.5 * tape_w, r2)) {
      return false;
    }
    return (cam.distort_to_pixel(r2) - cam.distort_to_pixel(r1)).norm() >= opt.min_tape_width_px;
  };
  // A strip would be seen leaving the line at s on side `side` (+1 left, -1
  // right): the ceiling min_branch_length_m beyond the band edge there is in view.
  const auto side_in_view = [&](double s, int side) {
    const double l =
        side * (0.5 * tape_w + (1.0 + opt.band_margin_widths) * tape_w + opt.min_branch_length_m);
    return in_image(s - tape_w, l) && in_image(s + tape_w, l);
  };
  // Visibility along the line is one interval: stepped every 0.1 m from 10 c
  // behind the foot point, its ends bisected to 1 mm.
  const double step = 0.1, s_far = 40.0 * c;
  double view_lo = 0.0, view_hi = 0.0;
  bool seen = false;
  const auto bisect = [&](double in, double out) {
    for (int it = 0; it < 7; ++it) {
      const double mid = 0.5 * (in + out);
      (in_view(mid) ? in : out) = mid;
    }
    return in;
  };
  for (double s = -10.0 * c; s <= s_far; s += step) {
    const bool vis = in_view(s);
    if (vis && !seen) {
      seen = true;
      view_lo = bisect(s, s - step);
    }
    if (seen && !vis) {
      view_hi = bisect(s - step, s);
      break;
    }
    if (seen) view_hi = s;
  }
  if (!seen) return found;

  // Every run pixel onto the ceiling. The distortion is undistorted at every
  // kSample-th pixel of a run and its last (with four points about the run's
  // centre, for the local Jacobian); the pixels between are interpolated
  // linearly in normalised coordinates (the undistortion is smooth: under
  // 0.01 px off over 8 px for the demo lens).
  constexpr int kSample = 8;
  std::vector<double> u, v;
  for (const stream::RunRecord& r : runs) {
    const double uc = 0.5 * (r.x_start + r.x_end);
    for (int x = r.x_start; x < r.x_end; x += kSample) {
      u.push_back(x);
      v.push_back(r.row);
    }
    u.push_back(r.x_end);
    v.push_back(r.row);
    u.insert(u.end(), {uc - 0.5, uc + 0.5, uc, uc});
    v.insert(v.end(), {r.row + 0.0, r.row + 0.0, r.row - 0.5, r.row + 0.5});
  }
  std::vector<double> xs(u.size()), ys(u.size());
  cam.normalise(u, v, xs, ys);

  std::vector<Piece> pieces;
  std::vector<Interval> band;
  size_t k = 0;
  for (size_t ri = 0; ri < runs.size(); ++ri) {
    const stream::RunRecord& r = runs[ri];
    const size_t n = static_cast<size_t>(r.x_end - r.x_start + 1);
    const size_t samples = (n - 1 + kSample - 1) / kSample + 1;
    const size_t base = k;
    k += samples + 4;
    // Normalised coordinates of pixel q of the run.
    const auto ray = [&](size_t q, double& x, double& y) {
      if (samples == 1) {
        x = xs[base];
        y = ys[base];
        return;
      }
      const size_t seg = std::min(q / kSample, samples - 2);
      const double x0 = static_cast<double>(seg * kSample);
      const double x1 = std::min(x0 + kSample, static_cast<double>(n - 1));
      const double t = (static_cast<double>(q) - x0) / (x1 - x0);
      x = xs[base + seg] + t * (xs[base + seg + 1] - xs[base + seg]);
      y = ys[base + seg] + t * (ys[base + seg + 1] - ys[base + seg]);
    };
    double s_l, l_l, s_r, l_r, s_u, l_u, s_d, l_d;
    const size_t j = base + samples;
    if (!tf.to_ceiling(xs[j], ys[j], s_l, l_l) || !tf.to_ceiling(xs[j + 1], ys[j + 1], s_r, l_r) ||
        !tf.to_ceiling(xs[j + 2], ys[j + 2], s_u, l_u) ||
        !tf.to_ceiling(xs[j + 3], ys[j + 3], s_d, l_d)) {
      continue;
    }
    // J = d(s, l)/d(u, v): pixel area |det J|, metres per pixel along l and s.
    const double j00 = s_r - s_l, j01 = s_d - s_u, j10 = l_r - l_l, j11 = l_d - l_u;
    const double det = std::abs(j00 * j11 - j01 * j10);
    const double foot_l = det / std::max(1e-12, std::hypot(j00, j01));
    const double foot_s = det / std::max(1e-12, std::hypot(j10, j11));
    const double half_band =
        0.5 * tape_w + std::max(opt.band_margin_widths * tape_w, opt.band_margin_px * foot_l);
    const double attach_limit = std::max(opt.max_attach_widths * tape_w, 2.0 * foot_l);
    double band_lo = 1e18, band_hi = -1e18, band_l_lo = 1e18, band_l_hi = -1e18;
    Piece cur;
    const auto flush = [&]() {
      if (cur.side != 0) pieces.push_back(cur);
      cur = Piece{};
    };
    for (size_t q = 0; q < n; ++q) {
      double s, l, rx, ry;
      const int x = r.x_start + static_cast<int>(q);
      ray(q, rx, ry);
      if (!tf.to_ceiling(rx, ry, s, l) || s > view_hi + 0.5 || s < view_lo - 0.5) {
        flush();
        continue;
      }
      const int side = l > half_band ? 1 : (l < -half_band ? -1 : 0);
      if (side == 0) {
        flush();
        band_lo = std::min(band_lo, s);
        band_hi = std::max(band_hi, s);
        band_l_lo = std::min(band_l_lo, l);
        band_l_hi = std::max(band_l_hi, l);
        continue;
      }
      if (side != cur.side) {
        flush();
        cur.side = side;
        cur.row = r.row;
        cur.u0 = x;
        cur.run = static_cast<int>(ri);
        cur.foot_s = foot_s;
        cur.attach_limit = attach_limit;
      }
      cur.u1 = x;
      cur.a += det;
      cur.as += det * s;
      cur.al += det * l;
      cur.ass += det * s * s;
      cur.all += det * l * l;
      cur.asl += det * s * l;
      cur.attach = std::min(cur.attach, std::abs(l) - half_band);
    }
    flush();
    if (band_hi >= band_lo) {
      // The run's weight over the tape's predicted length along its row,
      // W / |dl/du|: the tape's grey above background_level where it is
      // wider than the blur (less where the threshold clips a dim tape).
      const double predicted_px = std::max(1.0, tape_w / std::max(1e-12, std::abs(j10)));
      band.push_back({band_lo - 0.5 * foot_s, band_hi + 0.5 * foot_s, foot_s,
                      static_cast<double>(r.sum_w) / predicted_px, band_l_hi - band_l_lo + foot_l,
                      foot_l});
    }
  }

  // Branch pixels into connected components per side (8-connectivity between rows).
  std::sort(pieces.begin(), pieces.end(), [](const Piece& p, const Piece& q) {
    return p.row != q.row ? p.row < q.row : p.u0 < q.u0;
  });
  std::vector<int> parent(pieces.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (size_t i = 0, prev = 0; i < pieces.size();) {
    size_t end = i;
    while (end < pieces.size() && pieces[end].row == pieces[i].row) ++end;
    size_t pb = prev;
    while (pb < i && pieces[pb].row + 1 < pieces[i].row) ++pb;
    for (size_t a = i; a < end; ++a) {
      for (size_t b = pb; b < i; ++b) {
        if (pieces[b].side == pieces[a].side && pieces[b].u0 <= pieces[a].u1 + 1 &&
            pieces[a].u0 <= pieces[b].u1 + 1) {
          const int ra = find(parent, static_cast<int>(a)), rb = find(parent, static_cast<int>(b));
          parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
        }
      }
    }
    prev = i;
    i = end;
  }
  std::vector<std::vector<const Piece*>> comps(pieces.size());
  for (size_t i = 0; i < pieces.size(); ++i) {
    comps[static_cast<size_t>(find(parent, static_cast<int>(i)))].push_back(&pieces[i]);
  }
  std::vector<Branch> branches;
  for (const auto& comp : comps) {
    Branch b;
    if (!comp.empty() && strip_of(comp, tape_w, opt, b)) branches.push_back(b);
  }

  // The line's coverage along s: band stretches merged across small breaks;
  // stretches shorter than a tape width (specks) are dropped.
  std::sort(band.begin(), band.end(),
            [](const Interval& p, const Interval& q) { return p.a < q.a; });
  std::vector<Interval> line;
  for (const Interval& iv : band) {
    const double gap = std::max(opt.gap_split_widths * tape_w, 3.0 * iv.foot_s);
    if (!line.empty() && iv.a - line.back().b <= gap) {
      line.back().b = std::max(line.back().b, iv.b);
      line.back().foot_s = std::max(line.back().foot_s, iv.foot_s);
      line.back().foot_l = std::max(line.back().foot_l, iv.foot_l);
    } else {
      line.push_back(iv);
    }
  }
  std::erase_if(line, [&](const Interval& iv) { return iv.b - iv.a < tape_w; });
  // Median of a field of the band's runs within end_window_m of stretch i's end.
  std::vector<double> ws;
  const auto end_median = [&](size_t i, double Interval::*field) {
    ws.clear();
    for (const Interval& iv : band) {
      if (iv.b <= line[i].b + 1e-9 && iv.b >= line[i].b - opt.end_window_m &&
          iv.a >= line[i].a - 1e-9) {
        ws.push_back(iv.*field);
      }
    }
    if (ws.empty()) return 0.0;
    std::nth_element(ws.begin(), ws.begin() + static_cast<std::ptrdiff_t>(ws.size() / 2), ws.end());
    return ws[ws.size() / 2];
  };
  // How far beyond stretch i's end the band is seen empty.
  const auto empty_beyond = [&](size_t i) {
    const double next = i + 1 < line.size() ? line[i + 1].a : view_hi;
    return std::min(next, view_hi) - line[i].b;
  };
  // The runs' width across the tape in that window, over W.
  const auto end_width_ratio = [&](size_t i) { return end_median(i, &Interval::width) / tape_w; };
  // Bright tape is cut near the foot of its blurred edges: W to W + 2 px across.
  const auto end_width_ok = [&](size_t i) {
    const double r = end_width_ratio(i);
    return r >= 1.0 - opt.end_width_tolerance &&
           r <= 1.0 + opt.end_width_tolerance + 2.0 * line[i].foot_l / tape_w;
  };
  const double thr_w = settings.threshold - settings.background_level;
  const auto end_contrast = [&](size_t i) {
    return (end_median(i, &Interval::weight) - thr_w) / std::max(0.5, settings.noise_sigma_grey);
  };
  const auto enough_empty = [&](size_t i) {
    return empty_beyond(i) >= std::max(opt.min_empty_beyond_m, 3.0 * line[i].foot_s);
  };

  // Crossings: a branch on each side at the same place.
  std::vector<Branch> joined;
  std::vector<bool> used(branches.size(), false);
  for (size_t i = 0; i < branches.size(); ++i) {
    if (used[i]) continue;
    Branch b = branches[i];
    for (size_t j = i + 1; j < branches.size(); ++j) {
      if (used[j] || branches[j].side == b.side) continue;
      if (std::abs(branches[j].s0 - b.s0) <= tape_w + b.ev.thickness_allowance_m) {
        used[j] = true;
        const Branch& o = branches[j];
        b.s0 = 0.5 * (b.s0 + o.s0);
        b.angle = 0.5 * (b.angle + o.angle);
        b.side = 2;
        b.ev.branch_runs += o.ev.branch_runs;
        b.ev.branch_area_m2 += o.ev.branch_area_m2;
        b.ev.branch_length_m = std::max(b.ev.branch_length_m, o.ev.branch_length_m);
        break;
      }
    }
    joined.push_back(b);
  }

  // Branch pixels (of any shape) within 2 W (and 2 footprints) of s, on
  // side `side` (0: both): something leaves the line there.
  const double unclaimed_area = opt.max_end_branch_area_widths2 * tape_w * tape_w;
  const auto area_near = [&](double s, double foot, int side) {
    double area = 0.0;
    const double reach = 2.0 * tape_w + 2.0 * foot;
    for (const Piece& p : pieces) {
      if ((side == 0 || p.side == side) && std::abs(p.as / p.a - s) <= reach) area += p.a;
    }
    return area;
  };
  std::vector<bool> end_used(line.size(), false);
  for (const Branch& b : joined) {
    // The stretch of line the branch leaves from.
    size_t li = line.size();
    for (size_t i = 0; i < line.size(); ++i) {
      if (line[i].a - tape_w <= b.s0 && b.s0 <= line[i].b + tape_w) li = i;
    }
    if (li == line.size()) continue;
    // One side only when the other is empty there (else a crossing or a
    // T seen from its stem whose other half is not confirmed: not decided).
    if (b.side != 2 &&
        (!side_in_view(b.s0, -b.side) || area_near(b.s0, b.foot_s, -b.side) > unclaimed_area)) {
      continue;
    }
    Junction jn;
    jn.side =
        b.side == 2 ? JunctionSide::both : (b.side > 0 ? JunctionSide::left : JunctionSide::right);
    jn.distance_m = b.s0;
    // s0 is the strip's centroid along s (its inclination term is small):
    // each of its two edges is quantised to a pixel's span, uniformly, and
    // the centroid is their mean: variance 2 (foot_s^2 / 12) / 4.
    jn.distance_sigma_m = b.foot_s / std::sqrt(24.0);
    jn.branch_angle_rad = b.angle;
    jn.evidence = b.ev;
    jn.evidence.line_end_m = line[li].b;
    jn.evidence.empty_beyond_m = empty_beyond(li);
    jn.evidence.view_end_m = view_hi;
    if (line[li].b >= b.s0 + tape_w + opt.min_continuation_m) {
      jn.kind = JunctionKind::t_branch;
    } else if (enough_empty(li) && end_contrast(li) >= opt.min_end_contrast_sigma &&
               line[li].b - line[li].a >= opt.min_branch_length_m) {
      jn.kind = JunctionKind::l_turn;
      jn.evidence.end_contrast_sigma = end_contrast(li);
      jn.evidence.end_width_ratio = end_width_ratio(li);
      end_used[li] = true;
    } else {
      continue;  // the line beyond the branch is not in view yet: not decided
    }
    found.push_back(jn);
  }
  for (size_t i = 0; i < line.size(); ++i) {
    if (end_used[i] || !enough_empty(i) || end_contrast(i) < opt.min_end_contrast_sigma ||
        area_near(line[i].b, line[i].foot_s, 0) > unclaimed_area || !side_in_view(line[i].b, 1) ||
        !side_in_view(line[i].b, -1) || !end_width_ok(i)) {
      continue;
    }
    // The runs reach past the tape's edges by as much as the threshold cuts
    // into the blurred edge below its half level, across the tape (the
    // width's excess over W, half each side) as along it at the end: the
    // same blur and threshold, in pixels; along s a pixel spans foot_s.
    const double reach_px = std::max(0.0, 0.5 * (end_median(i, &Interval::width) - tape_w)) /
                            std::max(1e-12, end_median(i, &Interval::foot_l));
    Junction jn;
    jn.kind = JunctionKind::tape_end;
    jn.evidence.end_reach_m = reach_px * end_median(i, &Interval::foot_s);
    jn.distance_m = line[i].b - jn.evidence.end_reach_m;
    // The end row is quantised to a pixel's span along s (uniform: foot_s^2 /
    // 12); the reach comes from widths quantised to a pixel across at both
    // edges, median over the window's runs: about 0.2 px, taken as 1/12 px^2.
    jn.distance_sigma_m = end_median(i, &Interval::foot_s) * std::sqrt(2.0 / 12.0);
    jn.evidence.line_end_m = line[i].b;
    jn.evidence.empty_beyond_m = empty_beyond(i);
    jn.evidence.view_end_m = view_hi;
    jn.evidence.end_contrast_sigma = end_contrast(i);
    jn.evidence.end_width_ratio = end_width_ratio(i);
    found.push_back(jn);
  }
  std::sort(found.begin(), found.end(), [](const Junction& p, const Junction& q) {
    return std::abs(p.distance_m) < std::abs(q.distance_m);
  });
  return found;
}

}  // namespace ceilnav::host
