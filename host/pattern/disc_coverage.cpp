#include "host/pattern/disc_coverage.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace ceilnav::host::pattern {
namespace {

double normal_cdf(double t) {
  return 0.5 * std::erfc(-t / std::numbers::sqrt2);
}
double normal_pdf(double t) {
  return std::exp(-0.5 * t * t) / std::sqrt(2.0 * std::numbers::pi);
}
// Antiderivatives of the normal cdf: Psi' = Phi, Psi2' = Psi.
double psi1(double t) {
  return t * normal_cdf(t) + normal_pdf(t);
}
double psi2(double t) {
  return 0.5 * ((t * t + 1.0) * normal_cdf(t) + t * normal_pdf(t));
}

// One run as the fit sees it: its pixels (run + margins), the measured
// coverage sum and first moment about the middle, and per pixel the
// normalised coordinates; the pixel -> normalised Jacobian at each end.
struct RunData {
  int x0 = 0, x1 = 0, y = 0;
  double mid = 0.0, area = 0.0, moment = 0.0, moment_scale = 1.0;
  std::vector<double> nx, ny;
  Eigen::Matrix2d jl, jr;
  // Pixels in0..in1 lie so deep inside the start ellipse (kInteriorMarginPx
  // beyond the blur's reach) that they weigh w_in throughout the fit; their
  // count and sum of (x - mid).
  int in0 = 0, in1 = -1;
  double in_offsets = 0.0;
};
constexpr double kInteriorMarginPx = 3.0;

Eigen::Matrix2d pixel_jacobian(const CameraModel& camera, double u, double v) {
  const double h = 0.5;
  const Eigen::Vector2d du = camera.normalise(u + h, v) - camera.normalise(u - h, v);
  const Eigen::Vector2d dv = camera.normalise(u, v + h) - camera.normalise(u, v - h);
  Eigen::Matrix2d j;
  j.col(0) = du / (2.0 * h);
  j.col(1) = dv / (2.0 * h);
  return j;
}

// Parameters: centre (2) and the shape S = 4 Sigma (3): (x - c)^T S^-1 (x - c) = 1.
using Params = Eigen::Matrix<double, 5, 1>;

Params to_params(const Ellipse& e) {
  Params p;
  p << e.cx, e.cy, 4.0 * e.cov(0, 0), 4.0 * e.cov(0, 1), 4.0 * e.cov(1, 1);
  return p;
}

// Pixel-unit signed distance (> 0 outside) of normalised point q (relative
// to the centre) from the ellipse x^T mi x = 1, through the pixel -> normalised
// Jacobian j: the radial implicit function rho - 1 (exact for a circle) over
// its pixel gradient; the gradient's direction in n.
double edge_distance(const Eigen::Vector2d& q, const Eigen::Matrix2d& mi, const Eigen::Matrix2d& j,
                     Eigen::Vector2d& n) {
  const Eigen::Vector2d mq = mi * q;
  const double rho2 = q.dot(mq);
  if (!(rho2 > 1e-24)) {
    n = Eigen::Vector2d(1.0, 0.0);
    return -1e9;
  }
  const double rho = std::sqrt(rho2);
  const Eigen::Vector2d g = j.transpose() * mq;  // rho times the gradient of rho
  const double gn = std::sqrt(g.squaredNorm());
  n = g / gn;
  return (rho - 1.0) * rho / gn;
}

// The area of the pixel at normalised offset q from the centre inside the
// ellipse x^T mi x = 1 (j: pixel -> normalised). A straight edge through the
// pixel, except where the outline's radius of curvature is under
// kSubdivideRadiusPx (the ends of a thin ellipse's major axis, 1.7 px at 5 m
// and 75 deg): there the pixel is split into 4 x 4 boxes, each with its own
// straight edge (the distance's and the edge's curvature errors fall 16x).
constexpr double kSubdivideRadiusPx = 10.0;
double box_coverage(const Eigen::Vector2d& q, const Eigen::Matrix2d& mi, const Eigen::Matrix2d& j) {
  Eigen::Vector2d n;
  const double d = edge_distance(q, mi, j, n);
  if (std::abs(d) > 1.2) return d < 0.0 ? 1.0 : 0.0;
  // Curvature of the level set through q, in pixels: g = grad Q, H = hess Q.
  const Eigen::Vector2d g = j.transpose() * (2.0 * mi * q);
  const Eigen::Matrix2d h = j.transpose() * (2.0 * mi) * j;
  const Eigen::Vector2d gp(-g.y(), g.x());
  const double gn = g.norm();
  const double curvature = std::abs(gp.dot(h * gp)) / (gn * gn * gn);
  if (!(curvature * kSubdivideRadiusPx > 1.0)) return edge_pixel_coverage(d, n.x(), n.y(), 0.0);
  constexpr int kSub = 4;
  double sum = 0.0;
  for (int a = 0; a < kSub; ++a) {
    for (int b = 0; b < kSub; ++b) {
      const Eigen::Vector2d off((a + 0.5) / kSub - 0.5, (b + 0.5) / kSub - 0.5);
      Eigen::Vector2d ns;
      const double ds = edge_distance(q + j * off, mi, j, ns);
      sum += edge_pixel_coverage(ds * kSub, ns.x(), ns.y(), 0.0);
    }
  }
  return sum / (kSub * kSub);
}

// Beyond this distance (px) a pixel and every pixel its blur reaches are
// fully in or out.
double blur_reach(const DiscCoverageModel& m, int kernel_half) {
  const double psf = m.kernel_sigma_px > 0.0 ? 0.0 : m.psf_sigma_px;
  return 0.75 + 7.0 * psf + std::numbers::sqrt2 * kernel_half;
}

Eigen::Matrix2d shape_inverse(const Params& p) {
  Eigen::Matrix2d s;
  s << p(2), p(3), p(3), p(4);
  return s.inverse();
}

// Residuals of every run for parameters p; false when S is not positive definite.
bool residuals(const Params& p, const std::vector<RunData>& runs, const DiscCoverageModel& m,
               const std::vector<double>& kernel, double w_in, double w_out, Eigen::VectorXd& r) {
  if (!(p(2) > 0.0) || !(p(2) * p(4) - p(3) * p(3) > 0.0)) return false;
  const Eigen::Matrix2d mi = shape_inverse(p);
  const int kh = static_cast<int>(kernel.size()) - 1;
  const double psf = m.kernel_sigma_px > 0.0 ? 0.0 : m.psf_sigma_px;
  const double reach = blur_reach(m, kh);
  std::vector<double> cells, dist;
  std::vector<Eigen::Vector2d> normal;
  r.resize(2 * static_cast<Eigen::Index>(runs.size()));
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const RunData& rd = runs[k];
    const int n = rd.x1 - rd.x0 + 1;
    const int n_in = rd.in1 >= rd.in0 ? rd.in1 - rd.in0 + 1 : 0;
    double area = w_in * n_in, moment = w_in * rd.in_offsets;
    auto q_of =
        [&](int i) -> Eigen::Vector2d {  // normalised offset of pixel i (extrapolated off the run)
      const int c = std::clamp(i, 0, n - 1);
      const auto cu = static_cast<std::size_t>(c);
      const Eigen::Matrix2d& j = 2 * c < n ? rd.jl : rd.jr;
      return Eigen::Vector2d(rd.nx[cu] - p(0), rd.ny[cu] - p(1)) + j.col(0) * (i - c);
    };
    // Pixels i0..i1 of the run, which the edge may reach.
    auto segment = [&](int i0, int i1) {
      if (i1 < i0) return;
      // Pass 1: each pixel's distance; pixels within the blur's reach of the
      // edge need their coverage.
      int near0 = i1 + 1, near1 = i0 - 1;
      dist.resize(static_cast<std::size_t>(i1 - i0 + 1));
      normal.resize(dist.size());
      for (int i = i0; i <= i1; ++i) {
        const auto iu = static_cast<std::size_t>(i - i0);
        dist[iu] = edge_distance(q_of(i), mi, 2 * i < n ? rd.jl : rd.jr, normal[iu]);
        if (std::abs(dist[iu]) <= reach) {
          near0 = std::min(near0, i);
          near1 = i;
        }
      }
      const int cols = near1 - near0 + 1 + 2 * kh, rows = 2 * kh + 1;
      if (kh > 0 && near1 >= near0) {
        // Exact box coverage of every cell the pixel kernel reaches, once.
        cells.assign(static_cast<std::size_t>(cols * rows), 0.0);
        for (int c = 0; c < cols; ++c) {
          const int i = near0 - kh + c;
          const Eigen::Matrix2d& j = 2 * std::clamp(i, 0, n - 1) < n ? rd.jl : rd.jr;
          const Eigen::Vector2d q = q_of(i);
          for (int dv = -kh; dv <= kh; ++dv) {
            cells[static_cast<std::size_t>((dv + kh) * cols + c)] =
                box_coverage(q + j.col(1) * dv, mi, j);
          }
        }
      }
      for (int i = i0; i <= i1; ++i) {
        const double d = dist[static_cast<std::size_t>(i - i0)];
        const Eigen::Vector2d& nrm = normal[static_cast<std::size_t>(i - i0)];
        double w = w_in;
        if (d > reach) {
          w = w_out;
        } else if (d > -reach) {
          double c = 0.0;
          if (kh == 0) {
            c = edge_pixel_coverage(d, nrm.x(), nrm.y(), psf);
          } else {
            // The pixel kernel mixes the neighbours' exact box coverages.
            for (int dv = 0; dv < rows; ++dv) {
              const double kv = kernel[static_cast<std::size_t>(std::abs(dv - kh))];
              const double* row = &cells[static_cast<std::size_t>(dv * cols + (i - near0))];
              for (int du = 0; du < rows; ++du) {
                c += kv * kernel[static_cast<std::size_t>(std::abs(du - kh))] *
                     row[static_cast<std::size_t>(du)];
              }
            }
          }
          w = expected_weight(c, m);
        }
        area += w;
        moment += (static_cast<double>(rd.x0 + i) - rd.mid) * w;
      }
    };
    if (n_in > 0) {
      segment(0, rd.in0 - 1);
      segment(rd.in1 + 1, n - 1);
    } else {
      segment(0, n - 1);
    }
    r(2 * static_cast<Eigen::Index>(k)) = area - rd.area;
    r(2 * static_cast<Eigen::Index>(k) + 1) = (moment - rd.moment) / rd.moment_scale;
  }
  return true;
}

// Marks each run's deep interior for parameters p (see RunData); false when
// the given interiors are no longer deep enough (check = true).
bool mark_interiors(const Params& p, std::vector<RunData>& runs, double reach, bool check) {
  const Eigen::Matrix2d mi = shape_inverse(p);
  for (RunData& rd : runs) {
    const int n = rd.x1 - rd.x0 + 1;
    auto depth = [&](int i) {
      const auto iu = static_cast<std::size_t>(i);
      Eigen::Vector2d nrm;
      return edge_distance(Eigen::Vector2d(rd.nx[iu] - p(0), rd.ny[iu] - p(1)), mi,
                           2 * i < n ? rd.jl : rd.jr, nrm);
    };
    if (check) {
      // The distance along a chord of a convex region is largest at its ends.
      if (rd.in1 >= rd.in0 && (depth(rd.in0) > -reach || depth(rd.in1) > -reach)) return false;
      continue;
    }
    rd.in0 = 0;
    rd.in1 = -1;
    rd.in_offsets = 0.0;
    for (int i = 0; i < n; ++i) {
      if (depth(i) < -(reach + kInteriorMarginPx)) {
        if (rd.in1 < rd.in0) rd.in0 = i;
        rd.in1 = i;
      }
    }
    for (int i = rd.in0; i <= rd.in1; ++i) rd.in_offsets += rd.x0 + i - rd.mid;
  }
  return true;
}

}  // namespace

double expected_weight(double c, const DiscCoverageModel& m) {
  const double kappa = m.k > 0 ? m.contrast / static_cast<double>(m.k) : 0.0;
  const double s = m.contrast > 0.0 ? m.noise_grey / m.contrast : 0.0;
  if (!(s > 1e-9)) {
    if (c < 0.0) return -kappa * c;
    if (c < m.dead_lo) return 0.0;
    if (c < m.dead_hi) return c;
    return 1.0;
  }
  // x = c + e, e ~ N(0, s^2): kappa E[-x; x < 0] + E[x; lo <= x < hi] + P(x >= hi).
  const double z0 = -c / s, zl = (m.dead_lo - c) / s, zh = (m.dead_hi - c) / s;
  const double dark = kappa * (s * normal_pdf(z0) - c * normal_cdf(z0));
  const double mid = c * (normal_cdf(zh) - normal_cdf(zl)) - s * (normal_pdf(zh) - normal_pdf(zl));
  return dark + mid + (1.0 - normal_cdf(zh));
}

double edge_pixel_coverage(double d, double nx, double ny, double sigma) {
  const double a = std::max(std::abs(nx), std::abs(ny)), b = std::min(std::abs(nx), std::abs(ny));
  const double half = 0.5 * (a + b);
  if (!(sigma > 0.0)) {
    // P(u a + v b < -d), u and v uniform on [-1/2, 1/2]: a trapezoid's cdf.
    const double t = -d;
    auto lower = [&](double x) {  // x <= 0
      if (x <= -half) return 0.0;
      if (x <= -0.5 * (a - b)) return (x + half) * (x + half) / (2.0 * a * b);
      return (x + 0.5 * a) / a;
    };
    return t <= 0.0 ? lower(t) : 1.0 - lower(-t);
  }
  if (d <= -half - 8.0 * sigma) return 1.0;
  if (d >= half + 8.0 * sigma) return 0.0;
  const double k1 = 0.5 * a - d, k2 = -0.5 * a - d;
  if (b < 1e-4) {  // edge along a pixel axis: the box is a segment across it
    return sigma / a * (psi1(k1 / sigma) - psi1(k2 / sigma));
  }
  const double hb = 0.5 * b;
  const double sum = psi2((k1 + hb) / sigma) - psi2((k1 - hb) / sigma) - psi2((k2 + hb) / sigma) +
                     psi2((k2 - hb) / sigma);
  return std::clamp(sigma * sigma / (a * b) * sum, 0.0, 1.0);
}

std::vector<double> pixel_kernel(double sigma) {
  if (!(sigma > 0.0)) return {1.0};
  const int half = static_cast<int>(std::ceil(5.0 * sigma));
  std::vector<double> k(static_cast<std::size_t>(half) + 1);
  double sum = 0.0;
  for (int i = -half; i <= half; ++i) sum += std::exp(-0.5 * i * i / (sigma * sigma));
  for (int i = 0; i <= half; ++i)
    k[static_cast<std::size_t>(i)] = std::exp(-0.5 * i * i / (sigma * sigma)) / sum;
  // Taps under kMinKernelWeight dropped, the rest renormalised to sum 1.
  while (k.size() > 1 && k.back() < kMinKernelWeight) k.pop_back();
  double kept = k[0];
  for (std::size_t i = 1; i < k.size(); ++i) kept += 2.0 * k[i];
  for (double& w : k) w /= kept;
  return k;
}

std::optional<CoverageFit> fit_disc_coverage(std::span<const stream::RunRecord> disc_runs,
                                             const Ellipse& start, const DiscCoverageModel& model,
                                             const CameraModel& camera, int width, int height) {
  if (model.k == 0 || !(model.contrast > 0.0)) return std::nullopt;
  std::vector<RunData> runs;
  runs.reserve(disc_runs.size());
  const double k = static_cast<double>(model.k);
  // Runs the device cannot emit (reversed, beyond the image, overlapping to
  // more pixels than the image has) are refused, not fitted.
  int64_t pixels = 0;
  for (const stream::RunRecord& r : disc_runs) {
    if (r.x_end < r.x_start || r.x_end >= width || r.row >= height) return std::nullopt;
    pixels += r.x_end - r.x_start + 1;
  }
  if (width < 3 || height < 3 || pixels > int64_t{width} * height) return std::nullopt;
  for (const stream::RunRecord& r : disc_runs) {
    if (r.row == 0 || r.row + 1 >= height || r.x_start == 0 || r.x_end + 1 >= width) continue;
    RunData rd;
    rd.x0 = r.x_start - 1;
    rd.x1 = r.x_end + 1;
    rd.y = r.row;
    rd.mid = 0.5 * (rd.x0 + rd.x1);
    rd.area = static_cast<double>(r.sum_w) / k;
    rd.moment = (static_cast<double>(r.sum_xw) - rd.mid * static_cast<double>(r.sum_w)) / k;
    rd.moment_scale = std::max(1.0, rd.area);
    const int n = rd.x1 - rd.x0 + 1;
    std::vector<double> us(static_cast<std::size_t>(n)), vs(us.size(), static_cast<double>(rd.y));
    for (int i = 0; i < n; ++i) us[static_cast<std::size_t>(i)] = rd.x0 + i;
    rd.nx.resize(us.size());
    rd.ny.resize(us.size());
    camera.normalise(us, vs, rd.nx, rd.ny);
    rd.jl = pixel_jacobian(camera, rd.x0 + 1.0, rd.y);
    rd.jr = pixel_jacobian(camera, rd.x1 - 1.0, rd.y);
    runs.push_back(std::move(rd));
  }
  if (runs.size() < 6) return std::nullopt;
  const double w_in = expected_weight(1.0, model), w_out = expected_weight(0.0, model);
  const std::vector<double> kernel = pixel_kernel(model.kernel_sigma_px);

  Params p = to_params(start);
  const double reach = blur_reach(model, static_cast<int>(kernel.size()) - 1);
  if (!(p(2) > 0.0) || !(p(2) * p(4) - p(3) * p(3) > 0.0)) return std::nullopt;
  mark_interiors(p, runs, reach, false);
  Eigen::VectorXd r;
  if (!residuals(p, runs, model, kernel, w_in, w_out, r)) return std::nullopt;
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  const double scale = std::sqrt(p(2) + p(4));
  // Forward differences from the residuals r_at at `at`: steps of about
  // 1e-3 px (centre) and 1e-4 of the size.
  auto jacobian = [&](const Params& at, const Eigen::VectorXd& r_at, Eigen::MatrixXd& jac) {
    jac.resize(r_at.size(), 5);
    for (int j = 0; j < 5; ++j) {
      const double h = j < 2 ? 2e-6 * scale : 2e-4 * scale * scale;
      Params pp = at;
      pp(j) += h;
      Eigen::VectorXd rp;
      if (!residuals(pp, runs, model, kernel, w_in, w_out, rp)) return false;
      jac.col(j) = (rp - r_at) / h;
    }
    return true;
  };
  int it = 0;
  for (; it < 30; ++it) {
    Eigen::MatrixXd jac;
    if (!jacobian(p, r, jac)) return std::nullopt;
    const Eigen::Matrix<double, 5, 5> jtj = jac.transpose() * jac;
    const Params jtr = jac.transpose() * r;
    bool improved = false;
    Params step = Params::Zero();
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::Matrix<double, 5, 5> a = jtj;
      for (int j = 0; j < 5; ++j) a(j, j) *= 1.0 + lambda;
      step = a.ldlt().solve(-jtr);
      Eigen::VectorXd rn;
      if (step.allFinite() && residuals(p + step, runs, model, kernel, w_in, w_out, rn) &&
          rn.squaredNorm() <= cost) {
        p += step;
        r = rn;
        cost = rn.squaredNorm();
        lambda = std::max(1e-6, lambda / 4.0);
        improved = true;
      } else {
        lambda *= 8.0;
      }
    }
    if (!improved) break;
    // Converged: the centre moved < 1e-5 and the size < 1e-6 of the size.
    if (std::abs(step(0)) + std::abs(step(1)) < 1e-5 * scale &&
        step.tail<3>().cwiseAbs().sum() < 1e-6 * scale * scale) {
      ++it;
      break;
    }
  }
  // The fit moved the outline by more than the interiors' margin: not trusted.
  if (!mark_interiors(p, runs, reach, true)) return std::nullopt;
  CoverageFit fit;
  Eigen::Matrix2d cov;
  cov << p(2), p(3), p(3), p(4);
  const auto e = ellipse_from_covariance(Eigen::Vector2d(p(0), p(1)), 0.25 * cov);
  if (!e) return std::nullopt;
  fit.ellipse = *e;
  // Parameter covariance: the residuals' variance times (J^T J)^-1 at the
  // solution (the runs' residuals taken as independent).
  {
    Eigen::MatrixXd jac;
    if (!jacobian(p, r, jac)) return std::nullopt;
    const double dof = std::max(1.0, static_cast<double>(r.size()) - 5.0);
    const Eigen::Matrix<double, 5, 5> jtj = jac.transpose() * jac;
    fit.ellipse.param_cov = (cost / dof) * jtj.inverse();
    if (!fit.ellipse.param_cov.allFinite()) fit.ellipse.param_cov.setZero();
  }
  fit.runs = static_cast<int>(runs.size());
  fit.iterations = it;
  fit.rms_px = std::sqrt(cost / static_cast<double>(r.size()));
  return fit;
}

}  // namespace ceilnav::host::pattern
