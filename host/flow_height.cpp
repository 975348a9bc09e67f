#include "host/flow_height.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include <Eigen/Dense>

namespace ceilnav::host {
namespace {

// g(y) = w / c of a ceiling point seen at normalised row y (docs/host_maths.md section 6).
double g_of(double y, double sp, double cp) {
  return (cp + y * sp) / (sp - y * cp);
}

// Whether a run lies on the centre line l: its centre within max_residual_px
// plus half its width.
bool on_centre_line(const stream::RunRecord& r, const CameraModel& cam, const Eigen::Vector3d& l,
                    double max_residual_px) {
  if (r.sum_w == 0) return false;
  const double xc = static_cast<double>(r.sum_xw) / static_cast<double>(r.sum_w);
  const Eigen::Vector2d p = cam.normalise(xc, r.row);
  const double dist_px = std::abs(l.x() * p.x() + l.y() * p.y() + l.z()) * cam.fx();
  return dist_px <= max_residual_px + 0.5 * (r.x_end - r.x_start + 1.0);
}

// Mass of pixels a..b of one image row above a background that varies linearly
// between the means of the `bg` pixels just left of a and just right of b (the
// caller keeps a - bg .. b + bg inside the row). Optional outputs: the
// mass-weighted column, the two background means.
struct WindowMass {
  double mass = 0.0, centre = 0.0, left_bg = 0.0, right_bg = 0.0, max_bg = 0.0;
  double background(int x, int a, int b) const {
    return left_bg + (x - a + 0.5) / (b - a + 1.0) * (right_bg - left_bg);
  }
};
WindowMass window_mass(const uint8_t* px, int a, int b, int bg) {
  WindowMass w;
  for (int k = 0; k < bg; ++k) {
    w.left_bg += px[a - bg + k];
    w.right_bg += px[b + 1 + k];
    w.max_bg = std::max(
        {w.max_bg, static_cast<double>(px[a - bg + k]), static_cast<double>(px[b + 1 + k])});
  }
  w.left_bg /= bg;
  w.right_bg /= bg;
  double mx = 0.0;
  for (int x = a; x <= b; ++x) {
    const double v = px[x] - w.background(x, a, b);
    w.mass += v;
    mx += v * x;
  }
  w.centre = w.mass != 0.0 ? mx / w.mass : 0.5 * (a + b);
  return w;
}

}  // namespace

HeightEstimate ceiling_height_from_flow(double v1_norm, double v2_norm, double pitch_rad,
                                        double distance_m, double motion_angle_rad) {
  HeightEstimate out;
  if (!std::isfinite(v1_norm) || !std::isfinite(v2_norm) || !std::isfinite(pitch_rad) ||
      !std::isfinite(distance_m) || !std::isfinite(motion_angle_rad)) {
    return out;
  }
  const double forward_m = distance_m * std::cos(motion_angle_rad);
  // No forward motion (sideways motion leaves the rows unchanged): no parallax.
  if (!(forward_m > 1e-6 * std::abs(distance_m)) || !(forward_m > 0.0)) return out;
  const double sp = std::sin(pitch_rad), cp = std::cos(pitch_rad);
  // A ceiling point c above the camera and w ahead projects to
  //   y = (w sin p - c cos p) / (w cos p + c sin p)  =>  w / c = g(y).
  const double den1 = sp - v1_norm * cp, den2 = sp - v2_norm * cp;
  if (!(den1 > 1e-9) || !(den2 > 1e-9)) return out;  // on or below the horizon
  const double g1 = (cp + v1_norm * sp) / den1;
  const double g2 = (cp + v2_norm * sp) / den2;
  const double dg = g1 - g2;
  if (!(dg > 1e-12 * (1.0 + std::abs(g1)))) return out;  // no parallax (or moved backwards)
  const double c = forward_m / dg;
  if (!std::isfinite(c) || !(c > 0.0)) return out;
  out.status = Status::ok;
  out.ceiling_above_camera_m = c;
  out.range_m = c * g1;
  return out;
}

namespace {

std::optional<Eigen::Vector2d> tape_end(const cv::Mat* grey,
                                        std::span<const stream::RunRecord> runs,
                                        const CameraModel& cam, const CameraConfig& cfg,
                                        const TapePose& pose, const TapeEndOptions& opt) {
  if (pose.status != Status::ok || runs.empty()) return std::nullopt;
  if (grey != nullptr && (grey->type() != CV_8UC1 || grey->rows != cfg.image_height)) {
    return std::nullopt;
  }
  const Eigen::Vector3d& l = pose.line_norm;
  const double sp = std::sin(pose.pitch_rad), cp = std::cos(pose.pitch_rad);
  const double c = cfg.ceiling_above_camera_m();

  // Per row: tape mass and mass-weighted centre of the runs on the centre line.
  struct RowSum {
    double mass = 0.0, xw = 0.0;
    int x_min = 1 << 30, x_max = -1;
  };
  std::map<int, RowSum> rows;
  for (const auto& r : runs) {
    if (!on_centre_line(r, cam, l, opt.max_residual_px)) continue;
    RowSum& s = rows[r.row];
    s.mass += static_cast<double>(r.sum_w);
    s.xw += static_cast<double>(r.sum_xw);
    s.x_min = std::min(s.x_min, static_cast<int>(r.x_start));
    s.x_max = std::max(s.x_max, static_cast<int>(r.x_end));
  }
  if (rows.empty()) return std::nullopt;

  // First chain from the top and its last row.
  std::vector<int> chain;
  for (const auto& [row, s] : rows) {
    if (!chain.empty() && row != chain.back() + 1) break;
    chain.push_back(row);
  }
  const int last = chain.back();
  if (last + 1 >= cfg.image_height) return std::nullopt;  // runs off the bottom: no end
  // Expected tape width just below the end: W (sin p - y cos p) / c (cos psi ~ 1).
  {
    const double y_next = (last + 1.0 - cam.cy()) / cam.fy();
    const double width_px = cam.fx() * cfg.tape_width_m * (sp - y_next * cp) / c;
    if (width_px < opt.min_visible_width_px) return std::nullopt;  // fading at the horizon
  }
  // End rows: the tape end crosses rows over about its width times the tilt of
  // the cut; allow half the tape width plus 3 rows.
  const double y_last = (last - cam.cy()) / cam.fy();
  const double width_last_px = cam.fx() * cfg.tape_width_m * std::max(0.0, sp - y_last * cp) / c;
  const int span = 3 + static_cast<int>(std::ceil(0.5 * width_last_px));
  const int n_chain = static_cast<int>(chain.size());
  if (n_chain < opt.min_rows + span + opt.reference_rows / 2) return std::nullopt;
  const int ref_end = n_chain - span;  // chain[ref_end - 1] is the last full row
  const int ref_begin = std::max(0, ref_end - opt.reference_rows);
  if (ref_end - ref_begin < 2) return std::nullopt;
  // Linear fits over the reference rows: mass(row) and centre(row), pixels.
  double n = 0, sr = 0, srr = 0, sm = 0, srm = 0, sx = 0, srx = 0;
  for (int k = ref_begin; k < ref_end; ++k) {
    const int row = chain[static_cast<size_t>(k)];
    const RowSum& s = rows.at(row);
    const double xc = s.xw / s.mass;
    n += 1;
    sr += row;
    srr += static_cast<double>(row) * row;
    sm += s.mass;
    srm += row * s.mass;
    sx += xc;
    srx += row * xc;
  }
  const double det = n * srr - sr * sr;
  if (!(det > 0.0)) return std::nullopt;
  const double mass_slope = (n * srm - sr * sm) / det, mass_icpt = (sm - mass_slope * sr) / n;
  const double x_slope = (n * srx - sr * sx) / det, x_icpt = (sx - x_slope * sr) / n;
  double v_end = chain[static_cast<size_t>(ref_end - 1)] + 0.5;
  if (grey == nullptr) {
    for (int k = ref_end; k < n_chain; ++k) {
      const int row = chain[static_cast<size_t>(k)];
      const double full = mass_icpt + mass_slope * row;
      if (!(full > 0.0)) return std::nullopt;
      v_end += rows.at(row).mass / full;
    }
  } else {
    // The same sum with the grey mass of a window around the centre line: no
    // threshold drops the faint rows of the blurred end, which continues
    // `tail_rows` rows past the last run.
    double half = 0.0;
    for (int k = ref_begin; k < ref_end; ++k) {
      const RowSum& s = rows.at(chain[static_cast<size_t>(k)]);
      half = std::max(half, 0.5 * (s.x_max - s.x_min + 1));
    }
    half += opt.grey_margin_px;
    const int first = chain[static_cast<size_t>(ref_begin)];
    const int stop = std::min(last + opt.tail_rows, cfg.image_height - 1);
    std::vector<double> mass;
    for (int row = first; row <= stop; ++row) {
      const double xc = x_icpt + x_slope * row;
      const int a = static_cast<int>(std::floor(xc - half));
      const int b = static_cast<int>(std::ceil(xc + half));
      if (a - opt.grey_background_px < 0 || b + opt.grey_background_px >= grey->cols) {
        return std::nullopt;
      }
      mass.push_back(window_mass(grey->ptr<uint8_t>(row), a, b, opt.grey_background_px).mass);
    }
    double gn = 0, gr = 0, grr = 0, gm = 0, grm = 0;
    for (int k = ref_begin; k < ref_end; ++k) {
      const int row = chain[static_cast<size_t>(k)];
      const double m = mass[static_cast<size_t>(row - first)];
      gn += 1;
      gr += row;
      grr += static_cast<double>(row) * row;
      gm += m;
      grm += row * m;
    }
    const double gdet = gn * grr - gr * gr;
    if (!(gdet > 0.0)) return std::nullopt;
    const double gslope = (gn * grm - gr * gm) / gdet, gicpt = (gm - gslope * gr) / gn;
    for (int row = chain[static_cast<size_t>(ref_end)]; row <= stop; ++row) {
      const double full = gicpt + gslope * row;
      if (!(full > 0.0)) return std::nullopt;
      v_end += mass[static_cast<size_t>(row - first)] / full;
    }
  }
  const double u_end = x_icpt + x_slope * v_end;
  const Eigen::Vector2d p = cam.normalise(u_end, v_end);
  if (!p.allFinite()) return std::nullopt;
  return p;
}

}  // namespace

std::optional<Eigen::Vector2d> find_tape_end(std::span<const stream::RunRecord> runs,
                                             const CameraModel& cam, const CameraConfig& cfg,
                                             const TapePose& pose, const TapeEndOptions& opt) {
  return tape_end(nullptr, runs, cam, cfg, pose, opt);
}

std::optional<Eigen::Vector2d> find_tape_end(const cv::Mat& grey,
                                             std::span<const stream::RunRecord> runs,
                                             const CameraModel& cam, const CameraConfig& cfg,
                                             const TapePose& pose, const TapeEndOptions& opt) {
  return tape_end(&grey, runs, cam, cfg, pose, opt);
}

WidthHeight ceiling_height_from_tape_width(const cv::Mat& grey,
                                           std::span<const stream::RunRecord> runs,
                                           const CameraModel& cam, const CameraConfig& cfg,
                                           const TapePose& pose, const WidthHeightOptions& opt) {
  WidthHeight out;
  if (pose.status != Status::ok || grey.type() != CV_8UC1 || runs.empty()) return out;
  const Eigen::Vector3d& l = pose.line_norm;
  const double nl = std::hypot(l.x(), l.y());
  if (!(nl > 0.0)) return out;
  const Eigen::Vector2d n(l.x() / nl, l.y() / nl);  // unit normal of the centre line
  if (!(std::abs(n.x()) > 0.2)) return out;         // tape nearly along the rows
  const double sp = std::sin(pose.pitch_rad), cp = std::cos(pose.pitch_rad);
  const double cos_psi = std::cos(pose.yaw_rad);

  // One run per row: rows with two runs on the centre line (a crossing) are skipped.
  std::map<int, const stream::RunRecord*> row_run;
  std::map<int, int> count;
  for (const auto& r : runs) {
    if (!on_centre_line(r, cam, l, opt.max_residual_px)) continue;
    row_run[r.row] = &r;
    ++count[r.row];
  }
  std::vector<double> values;
  const int width = grey.cols;
  for (const auto& [row, rp] : row_run) {
    if (count[row] != 1 || row < 0 || row >= grey.rows) continue;
    const stream::RunRecord& r = *rp;
    const int a = r.x_start - opt.margin_px, b = r.x_end + opt.margin_px;  // mass window
    const int a0 = a - opt.background_px, b1 = b + opt.background_px;
    if (a0 < 0 || b1 >= width) continue;
    const uint8_t* px = grey.ptr<uint8_t>(row);
    // Background: the pixels just beyond the window on both sides; a row with
    // another bright thing there (a branch, a neighbour) is skipped below.
    const WindowMass wm = window_mass(px, a, b, opt.background_px);
    const double mass = wm.mass, centre = wm.centre, bl = wm.left_bg, br = wm.right_bg,
                 bmax = wm.max_bg;
    if (!(mass > 0.0)) continue;
    // Plateau: pixels well inside the tape's edges, from a first width guess
    // (the run) refined once with the mass / plateau width.
    double w_px = r.x_end - r.x_start + 1.0;
    double plateau = 0.0;
    bool good = true;
    for (int iter = 0; iter < 2 && good; ++iter) {
      const double half = 0.5 * w_px - opt.plateau_inset_px;
      const int lo = static_cast<int>(std::ceil(centre - half));
      const int hi = static_cast<int>(std::floor(centre + half));
      if (hi < lo || lo < a || hi > b) {
        good = false;
        break;
      }
      double sum = 0.0;
      for (int x = lo; x <= hi; ++x) sum += px[x] - wm.background(x, a, b);
      plateau = sum / (hi - lo + 1);
      if (!(plateau > 0.0)) {
        good = false;
        break;
      }
      w_px = mass / plateau;
    }
    if (!good || w_px < opt.min_width_px) continue;
    // The background must be dark against the plateau on both sides.
    if (bmax - std::min(bl, br) > 0.25 * plateau || std::abs(bl - br) > 0.1 * plateau) continue;
    // Pixel width along the row -> perpendicular width -> width at constant y.
    const Eigen::Vector2d p0 = cam.normalise(centre - 0.5, row);
    const Eigen::Vector2d p1 = cam.normalise(centre + 0.5, row);
    const Eigen::Vector2d pc = cam.normalise(centre, row);
    if (!p0.allFinite() || !p1.allFinite() || !pc.allFinite()) continue;
    const double perp = std::abs(n.dot(p1 - p0)) * w_px;
    const double dx = perp / std::abs(n.x());
    const double depth_term = sp - pc.y() * cp;
    if (!(depth_term > 0.0) || !(dx > 0.0)) continue;
    values.push_back(cfg.tape_width_m * depth_term / (dx * cos_psi));
  }
  if (static_cast<int>(values.size()) < opt.min_rows) return out;
  std::vector<double> sorted = values;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<double> dev;
  for (double v : values) dev.push_back(std::abs(v - median));
  std::nth_element(dev.begin(), dev.begin() + static_cast<long>(dev.size() / 2), dev.end());
  const double mad = std::max(dev[dev.size() / 2], 1e-6 * median);
  double sum = 0.0, sum2 = 0.0;
  int n_in = 0;
  for (double v : values) {
    if (std::abs(v - median) > 3.0 * 1.4826 * mad) continue;
    sum += v;
    sum2 += v * v;
    ++n_in;
  }
  if (n_in < opt.min_rows) return out;
  const double mean = sum / n_in;
  const double var = std::max(0.0, (sum2 - n_in * mean * mean) / (n_in - 1));
  out.status = Status::ok;
  out.ceiling_above_camera_m = mean;
  out.std_error_m = std::sqrt(var / n_in);
  out.rows = n_in;
  return out;
}

bool FlowTrack::add(const PlanarPose& pose, const Eigen::Vector2d& feature_norm) {
  const double sp = std::sin(pitch_), cp = std::cos(pitch_);
  const double den = sp - feature_norm.y() * cp;
  if (!(den > 1e-9) || !feature_norm.allFinite()) return false;
  Obs o{pose, Eigen::Vector2d(g_of(feature_norm.y(), sp, cp), -feature_norm.x() / den),
        den * den * den * den};
  const auto world = [&](const Obs& ob, double c) {
    const double cy = std::cos(ob.pose.yaw_rad), sy = std::sin(ob.pose.yaw_rad);
    return Eigen::Vector2d(ob.pose.x_m + c * (cy * ob.q.x() - sy * ob.q.y()),
                           ob.pose.y_m + c * (sy * ob.q.x() + cy * ob.q.y()));
  };
  bool continues = false;
  if (!obs_.empty()) {
    // With the configured height: a fit of a drifting feature cannot widen the gate.
    const Eigen::Vector2d here = world(o, c0_);
    const Eigen::Vector2d there = world(obs_.back(), c0_);
    const double range = c0_ * o.q.norm();
    continues = (here - there).norm() <= opt_.gate_m + opt_.gate_fraction * range;
  }
  if (!continues) obs_.clear();
  obs_.push_back(o);
  return continues;
}

FlowFit FlowTrack::fit() const {
  FlowFit out;
  out.frames = static_cast<int>(obs_.size());
  if (out.frames < std::max(3, opt_.min_frames)) return out;
  out.travel_m = std::hypot(obs_.back().pose.x_m - obs_.front().pose.x_m,
                            obs_.back().pose.y_m - obs_.front().pose.y_m);
  if (!(out.travel_m >= opt_.min_travel_m)) return out;
  // Unknowns theta = (c, Fx, Fy): rows c (R q)_x - Fx = -Px and c (R q)_y - Fy = -Py.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const Obs& o : obs_) {
    const double cy = std::cos(o.pose.yaw_rad), sy = std::sin(o.pose.yaw_rad);
    const Eigen::Vector2d rq(cy * o.q.x() - sy * o.q.y(), sy * o.q.x() + cy * o.q.y());
    const Eigen::Vector3d ax(rq.x(), -1.0, 0.0), ay(rq.y(), 0.0, -1.0);
    ata += o.weight * (ax * ax.transpose() + ay * ay.transpose());
    atb += o.weight * (ax * -o.pose.x_m + ay * -o.pose.y_m);
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
  if (ldlt.info() != Eigen::Success) return out;
  const Eigen::Vector3d theta = ldlt.solve(atb);
  if (!theta.allFinite() || !(theta.x() > 0.0)) return out;
  double chi2 = 0.0;
  for (const Obs& o : obs_) {
    const double cy = std::cos(o.pose.yaw_rad), sy = std::sin(o.pose.yaw_rad);
    const double rx = o.pose.x_m + theta.x() * (cy * o.q.x() - sy * o.q.y()) - theta.y();
    const double ry = o.pose.y_m + theta.x() * (sy * o.q.x() + cy * o.q.y()) - theta.z();
    chi2 += o.weight * (rx * rx + ry * ry);
  }
  const Eigen::Matrix3d cov = ata.inverse() * (chi2 / std::max(1, 2 * out.frames - 3));
  out.status = Status::ok;
  out.ceiling_above_camera_m = theta.x();
  out.range_m = theta.x() * obs_.back().q.x();
  out.std_error_m = std::sqrt(std::max(0.0, cov(0, 0)));
  return out;
}

}  // namespace ceilnav::host
