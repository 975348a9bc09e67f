#include "host/corridor/hough_lines.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

namespace ceilnav::host::corridor {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// Bins either side of a row's local peak that row_moments sums.
constexpr int kMomentHalfWidth = 2;

// The votes of row j within `half` bins of its local peak near rho_px: their
// mass, mean rho and the width of the rho interval they come from (a
// segment's votes spread uniformly over an interval of width W; binned,
// their variance is W^2 / 12 + b^2 / 12 for bins of b pixels).
struct RowMoments {
  double mass = 0.0, mean = 0.0, width = 0.0;
};
RowMoments row_moments(const Accumulator& acc, int j, double rho_px, int half) {
  const double b = static_cast<double>(1u << acc.config.rho_shift);
  const int centre = static_cast<int>(std::lround((rho_px + acc.config.width) / b));
  int best = -1;
  uint64_t best_v = 0;
  for (int d : {0, -1, 1}) {
    const int r = centre + d;
    if (r < 0 || r >= acc.bins()) continue;
    if (best < 0 || acc.at(j, r) > best_v) {
      best = r;
      best_v = acc.at(j, r);
    }
  }
  RowMoments m;
  if (best < 0 || best_v == 0) return m;
  double s1 = 0.0, s2 = 0.0;
  for (int r = std::max(0, best - half); r <= std::min(acc.bins() - 1, best + half); ++r) {
    const auto v = static_cast<double>(acc.at(j, r));
    m.mass += v;
    s1 += v * acc.rho_px(r);
    s2 += v * acc.rho_px(r) * acc.rho_px(r);
  }
  m.mean = s1 / m.mass;
  const double var = std::max(0.0, s2 / m.mass - m.mean * m.mean);
  m.width = std::sqrt(std::max(0.0, 12.0 * var - b * b));
  return m;
}

}  // namespace

std::vector<bool> plateau_marks(const Accumulator& acc, uint64_t max, double c) {
  std::vector<bool> marks(static_cast<size_t>(acc.rows()), false);
  const double bound = static_cast<double>(max) * c;
  for (int j = 0; j < acc.rows(); ++j) {
    for (int r = 0; r < acc.bins(); ++r) {
      // eq. 19: k > max x c.
      if (static_cast<double>(acc.at(j, r)) > bound) {
        marks[static_cast<size_t>(j)] = true;
        break;
      }
    }
  }
  return marks;
}

void fill_holes(std::vector<bool>& marks, bool wrap) {
  const int n = static_cast<int>(marks.size());
  const std::vector<bool> in = marks;
  auto mark = [&](int i) { return in[static_cast<size_t>(((i % n) + n) % n)]; };
  if (n == 0 || std::none_of(in.begin(), in.end(), [](bool b) { return b; })) return;
  for (int i = 0; i < n; ++i) {
    if (!mark(i) || mark(i + 1)) continue;  // i: a 1 followed by a 0
    if (!wrap && i + 1 >= n) continue;
    // The 0 run after i: "101", "1001", "10001" have runs of 1..3.
    for (int len = 1; len <= 3; ++len) {
      const int end = i + len + 1;  // the 1 closing the run
      if (!wrap && end >= n) break;
      if (mark(end)) {
        for (int k = i + 1; k < end; ++k) marks[static_cast<size_t>(k % n)] = true;
        break;
      }
    }
  }
}

RowRange plateau_rows(const Accumulator& acc, const std::vector<bool>& marks, int j_max,
                      double theta_range_deg, bool wrap) {
  const int n = static_cast<int>(marks.size());
  const double step = acc.shape.theta_step;
  RowRange run{j_max, j_max};
  const bool all = std::all_of(marks.begin(), marks.end(), [](bool b) { return b; });
  if (all) {
    run = {0, n - 1};
  } else if (marks[static_cast<size_t>(j_max)]) {
    auto at = [&](int i) { return marks[static_cast<size_t>(((i % n) + n) % n)]; };
    int b = j_max, e = j_max;
    while ((wrap || b > 0) && at(b - 1)) --b;
    while ((wrap || e < n - 1) && at(e + 1)) ++e;
    run = {((b % n) + n) % n, e % n};
  }
  // eq. 20: the run when theta_end - theta_begin > theta_range, else theta_max
  // +- theta_range / 2.
  const int run_len = ((run.last - run.first) % n + n) % n;  // rows between the ends
  if (run_len * step > theta_range_deg) return run;
  const int half = static_cast<int>(std::floor(0.5 * theta_range_deg / step + 1e-9));
  if (wrap) {
    if (2 * half + 1 >= n) return {0, n - 1};
    return {((j_max - half) % n + n) % n, (j_max + half) % n};
  }
  return {std::max(0, j_max - half), std::min(n - 1, j_max + half)};
}

void remove_rows(Accumulator& acc, const RowRange& range) {
  const int n = acc.rows();
  for (int k = 0, j = range.first; k < n; ++k, j = (j + 1) % n) {
    for (int r = 0; r < acc.bins(); ++r) {
      acc.cells[static_cast<size_t>(j) * acc.shape.rho_bins() + static_cast<size_t>(r)] = 0;
    }
    if (j == range.last) break;
  }
}

ImageLine refine_peak(const Accumulator& acc, int j, int r) {
  const int n = acc.rows();
  const double step = acc.shape.theta_step;
  const bool circle = acc.full_circle();
  const double rho0 = acc.rho_px(r);
  // Row j + d on the unwrapped theta axis: a row across the end of a full
  // circle holds the same line at theta -+ 180 with -rho.
  struct Row {
    bool valid = false;
    double theta_deg = 0.0;
    RowMoments m;
  };
  auto row = [&](int d) {
    Row out;
    int jj = j + d;
    double sign = 1.0, shift = 0.0;
    if (jj < 0 || jj >= n) {
      if (!circle) return out;
      sign = -1.0;
      shift = jj < 0 ? -180.0 : 180.0;
      jj = (jj + n) % n;
    }
    out.valid = true;
    out.m = row_moments(acc, jj, sign * rho0, kMomentHalfWidth);
    out.m.mean *= sign;
    out.theta_deg = acc.theta_deg(jj) + shift;
    return out;
  };
  const Row rm = row(-1), r0 = row(0), rp = row(1);
  double theta = r0.theta_deg;
  double rho = r0.m.mass > 0.0 ? r0.m.mean : rho0;
  if (rm.valid && rp.valid && rm.m.mass > 0.0 && rp.m.mass > 0.0) {
    // theta: a segment of length L votes, in a row at t, over a rho interval
    // of width W = L |sin(t - theta)| ~ L |t - theta|; on the rows about it,
    // W- = L (theta - t-), W+ = L (t+ - theta), so
    //   theta = t0 + step (W- - W+) / (W- + W+),
    // clamped to half a row (the peak's row is the nearest).
    const double wsum = rm.m.width + rp.m.width;
    if (wsum > 0.0) {
      const double off = std::clamp((rm.m.width - rp.m.width) / wsum, -0.5, 0.5);
      theta = r0.theta_deg + off * step;
    }
    // rho: the votes' mean in every row is the sinusoid x cos t + y sin t of
    // the segment's (weighted) centroid (x, y); least squares through the
    // three rows, evaluated at theta.
    Eigen::Matrix<double, 3, 2> a;
    Eigen::Vector3d y;
    const Row* rows[3] = {&rm, &r0, &rp};
    for (int k = 0; k < 3; ++k) {
      a(k, 0) = std::cos(rows[k]->theta_deg * kDeg);
      a(k, 1) = std::sin(rows[k]->theta_deg * kDeg);
      y(k) = rows[k]->m.mean;
    }
    const Eigen::Vector2d xy = a.colPivHouseholderQr().solve(y);
    rho = xy.x() * std::cos(theta * kDeg) + xy.y() * std::sin(theta * kDeg);
  }
  // Back to theta in [0, 180).
  if (theta < 0.0) {
    theta += 180.0;
    rho = -rho;
  } else if (theta >= 180.0) {
    theta -= 180.0;
    rho = -rho;
  }
  ImageLine out;
  out.theta_rad = theta * kDeg;
  out.rho_px = rho;
  out.strength = static_cast<double>(acc.at(j, r));
  return out;
}

std::vector<HoughLine> extract_lines(const Accumulator& acc, const LineExtractionParams& params) {
  std::vector<HoughLine> lines;
  if (acc.cells.size() < static_cast<size_t>(acc.shape.n_theta()) * acc.shape.rho_bins()) {
    return lines;
  }
  Accumulator work = acc;
  const bool wrap = params.wrap && acc.full_circle();
  uint64_t first_max = 0;
  for (int i = 0; i < params.max_lines; ++i) {
    // Step 4: the global maximum (ties: the lowest index).
    int bj = -1, br = -1;
    uint64_t max = 0;
    for (int j = 0; j < work.rows(); ++j) {
      for (int r = 0; r < work.bins(); ++r) {
        if (work.at(j, r) > max) {
          max = work.at(j, r);
          bj = j;
          br = r;
        }
      }
    }
    if (max == 0) break;
    if (i == 0) first_max = max;
    if (static_cast<double>(max) < params.min_strength_ratio * static_cast<double>(first_max)) {
      break;
    }
    HoughLine h;
    h.row = bj;
    h.bin = br;
    h.votes = max;
    h.line = refine_peak(acc, bj, br);
    lines.push_back(h);
    // Steps 5-7.
    std::vector<bool> marks = plateau_marks(work, max, params.plateau_c);
    fill_holes(marks, wrap);
    remove_rows(work, plateau_rows(work, marks, bj, params.theta_range_deg, wrap));
  }
  // Step 9: by theta, increasing.
  std::sort(lines.begin(), lines.end(), [](const HoughLine& a, const HoughLine& b) {
    return a.line.theta_rad < b.line.theta_rad;
  });
  return lines;
}

bool undistort_line(const ImageLine& raw, const CameraModel& camera, int width, int height,
                    ImageLine& out, int samples) {
  // The chord: u cos + v sin = rho clipped to the frame (Liang-Barsky on the
  // parametric form p0 + s d, p0 the foot of the normal, d along the line).
  const double c = std::cos(raw.theta_rad), s = std::sin(raw.theta_rad);
  const Eigen::Vector2d p0(raw.rho_px * c, raw.rho_px * s), d(-s, c);
  double s0 = -1e9, s1 = 1e9;
  const double lo[2] = {-0.5, -0.5}, hi[2] = {width - 0.5, height - 0.5};
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (p0[k] < lo[k] || p0[k] >= hi[k]) return false;
      continue;
    }
    double a = (lo[k] - p0[k]) / d[k], b = (hi[k] - p0[k]) / d[k];
    if (a > b) std::swap(a, b);
    s0 = std::max(s0, a);
    s1 = std::min(s1, b);
  }
  if (!(s1 > s0)) return false;
  if (!camera.has_distortion()) {
    out = raw;
    return true;
  }
  samples = std::max(samples, 2);
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(static_cast<size_t>(samples));
  Eigen::Vector2d mean(0.0, 0.0);
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d p = p0 + (s0 + (s1 - s0) * i / (samples - 1)) * d;
    pts.push_back(camera.ideal_pixel(camera.normalise(p.x(), p.y())));
    mean += pts.back();
  }
  mean /= samples;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& p : pts) cov += (p - mean) * (p - mean).transpose();
  // The normal: the eigenvector of the smallest eigenvalue.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  const Eigen::Vector2d nrm = es.eigenvectors().col(0);
  out = line_from_homogeneous({nrm.x(), nrm.y(), -nrm.dot(mean)}, raw.strength);
  return true;
}

}  // namespace ceilnav::host::corridor
