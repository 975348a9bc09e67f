#include "host/homing/tracker.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "host/homing/ncc.hpp"
#include "host/homing/orientation.hpp"

namespace ceilnav::host::homing {
namespace {

constexpr int kLevels = 2;  // the coarse level: 1 / 4 resolution

// Frames and the site's patch are matched smoothed (Gaussian, sigma 1 px):
// a template turned by bilinear interpolation is blurred by up to half a
// pixel more at some angles than at others, and unsmoothed the match
// prefers the angles whose blur best fits the frame's sampling phase
// (0.5 deg off on renders); smoothed, that blur is small against the
// common one.
constexpr double kSmoothSigmaPx = 1.0;

// The smoothing of `f` (CV_32FC1); a view into a larger image is smoothed
// with the pixels around it, as the whole image would be.
cv::Mat smooth(const cv::Mat& f) {
  cv::Mat g;
  cv::GaussianBlur(f, g, cv::Size(0, 0), kSmoothSigmaPx);
  return g;
}

cv::Mat to_float(const cv::Mat& grey) {
  cv::Mat f;
  grey.convertTo(f, CV_32F);
  return smooth(f);
}

cv::Mat coarse(const cv::Mat& img) {
  cv::Mat c = img;
  for (int i = 0; i < kLevels; ++i) {
    cv::Mat d;
    cv::pyrDown(c, d);
    c = d;
  }
  return c;
}

double wrap360(double deg) {
  double d = std::fmod(deg, 360.0);
  return d < 0.0 ? d + 360.0 : d;
}

// The vertex of the parabola through (-1, a), (0, b), (1, c), in (-1, 1);
// 0 when not a strict maximum at b.
double vertex(double a, double b, double c) {
  const double den = a - 2.0 * b + c;
  if (!(den < 0.0) || b < a || b < c) return 0.0;
  return std::clamp(0.5 * (a - c) / den, -1.0, 1.0);
}

// The vertex of the quadratic surface fitted to 3 x 3 values v[j][i] at
// offsets (i - 1, j - 1): f = a + b x + c y + d x^2 + e x y + g y^2 (least
// squares, closed form), clamped to [-1, 1]^2; false (and 0, 0) when the
// surface is not a maximum. A ridge along a diagonal (a turned grille's
// slats) biases the two axes' separate parabolas; the joint fit follows it.
bool vertex2(const std::array<std::array<double, 3>, 3>& v, double& x, double& y, double& peak) {
  double s = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      const double f = v[static_cast<size_t>(j)][static_cast<size_t>(i)];
      const double xi = i - 1.0, yj = j - 1.0;
      s += f;
      sx += f * xi;
      sy += f * yj;
      sxx += f * xi * xi;
      syy += f * yj * yj;
      sxy += f * xi * yj;
    }
  }
  // On the 3 x 3 grid: b = sx / 6, c = sy / 6, e = sxy / 4,
  // d = sxx / 2 - s / 3, g = syy / 2 - s / 3 (the x^2 and y^2 columns
  // are orthogonal to the rest once centred), a = 5 s / 9 - (sxx + syy) / 3.
  const double b = sx / 6.0, c = sy / 6.0, e = sxy / 4.0;
  const double d = sxx / 2.0 - s / 3.0, g = syy / 2.0 - s / 3.0;
  const double det = 4.0 * d * g - e * e;
  x = y = 0.0;
  if (!(d < 0.0 && det > 0.0)) return false;
  x = std::clamp((-2.0 * g * b + e * c) / det, -1.0, 1.0);
  y = std::clamp((-2.0 * d * c + e * b) / det, -1.0, 1.0);
  const double a = 5.0 * s / 9.0 - (sxx + syy) / 3.0;
  peak = a + b * x + c * y + d * x * x + e * x * y + g * y * y;
  return true;
}

struct Peak {
  double score = -2.0;
  cv::Point at{0, 0};
};

Peak best_in(const cv::Mat& scores) {
  Peak p;
  cv::minMaxLoc(scores, nullptr, &p.score, nullptr, &p.at);
  return p;
}

// The score surface's peak to a sub-pixel: the quadratic through the best
// cell and its eight neighbours (vertex2), its vertex offsets (dx, dy,
// within half a cell) and the peak's value.
struct SubPixelPeak {
  double dx = 0.0, dy = 0.0, score = -2.0;
  cv::Point at{0, 0};
};
SubPixelPeak sub_pixel(const cv::Mat& scores) {
  const Peak p = best_in(scores);
  SubPixelPeak out;
  out.at = p.at;
  out.score = p.score;
  if (p.at.x < 1 || p.at.y < 1 || p.at.x + 1 >= scores.cols || p.at.y + 1 >= scores.rows) {
    return out;
  }
  std::array<std::array<double, 3>, 3> v{};
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      v[static_cast<size_t>(j)][static_cast<size_t>(i)] =
          scores.at<float>(p.at.y + j - 1, p.at.x + i - 1);
    }
  }
  double peak = p.score;
  if (vertex2(v, out.dx, out.dy, peak)) out.score = std::max(peak, static_cast<double>(p.score));
  out.dx = std::clamp(out.dx, -0.5, 0.5);
  out.dy = std::clamp(out.dy, -0.5, 0.5);
  return out;
}

// The best score outside `radius` of `at` (Chebyshev).
double next_best(const cv::Mat& scores, cv::Point at, int radius) {
  cv::Mat m = scores.clone();
  const cv::Rect r(at.x - radius, at.y - radius, 2 * radius + 1, 2 * radius + 1);
  m(r & cv::Rect(0, 0, m.cols, m.rows)).setTo(-2.0);
  double v = -2.0;
  cv::minMaxLoc(m, nullptr, &v);
  return v;
}

// The score surface's peak near `start` as sub_pixel finds it on the whole
// surface, from a few scores: climb to the best of the 3 x 3 cells about
// the current cell until the centre is best, then the quadratic's vertex
// (none at the surface's edge). The surface of a turn a fraction of a
// degree from the last one peaks at the same cell or the next.
SubPixelPeak local_peak(const BlockNcc& n, const NccTemplate& tmpl, cv::Point start) {
  std::vector<float> memo(static_cast<size_t>(n.cols()) * static_cast<size_t>(n.rows()),
                          std::numeric_limits<float>::quiet_NaN());
  const auto at = [&](int x, int y) {
    float& m =
        memo[static_cast<size_t>(y) * static_cast<size_t>(n.cols()) + static_cast<size_t>(x)];
    if (std::isnan(m)) m = static_cast<float>(n.score(tmpl, x, y));
    return static_cast<double>(m);
  };
  cv::Point c(std::clamp(start.x, 0, n.cols() - 1), std::clamp(start.y, 0, n.rows() - 1));
  for (int moves = 0; moves < n.cols() + n.rows(); ++moves) {
    cv::Point best = c;
    double best_score = at(c.x, c.y);
    for (int j = -1; j <= 1; ++j) {
      for (int i = -1; i <= 1; ++i) {
        const int x = c.x + i, y = c.y + j;
        if (x < 0 || y < 0 || x >= n.cols() || y >= n.rows()) continue;
        const double v = at(x, y);
        if (v > best_score) {
          best_score = v;
          best = cv::Point(x, y);
        }
      }
    }
    if (best == c) break;
    c = best;
  }
  SubPixelPeak out;
  out.at = c;
  out.score = at(c.x, c.y);
  if (c.x < 1 || c.y < 1 || c.x + 1 >= n.cols() || c.y + 1 >= n.rows()) return out;
  std::array<std::array<double, 3>, 3> v{};
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      v[static_cast<size_t>(j)][static_cast<size_t>(i)] = at(c.x + i - 1, c.y + j - 1);
    }
  }
  double peak = out.score;
  if (vertex2(v, out.dx, out.dy, peak)) out.score = std::max(peak, out.score);
  out.dx = std::clamp(out.dx, -0.5, 0.5);
  out.dy = std::clamp(out.dy, -0.5, 0.5);
  return out;
}

}  // namespace

const char* to_string(TrackStatus s) {
  switch (s) {
    case TrackStatus::ok:
      return "ok";
    case TrackStatus::ambiguous:
      return "ambiguous";
    case TrackStatus::not_found:
      return "not_found";
  }
  return "?";
}

cv::Mat turned_template(const Site& site, double gamma_deg, int side, double shift_x_px,
                        double shift_y_px) {
  // out(u, v) = patch(c_in + R (u - c_out - shift_x, v - c_out - shift_y)),
  // R the turn back by gamma (image angles: clockwise positive on the
  // screen), bilinear, the patch's edge replicated beyond it. Exact
  // coordinates (cv::warpAffine rounds them to 1 / 32 px).
  const cv::Mat& patch = site.patch;
  const double c_in = 0.5 * (patch.cols - 1), c_out = 0.5 * (side - 1);
  const double g = gamma_deg * std::numbers::pi / 180.0;
  const double ca = std::cos(g), sa = std::sin(g);
  const int last_x = patch.cols - 1, last_y = patch.rows - 1;
  constexpr double kEdge = 0.01;
  const float* base = patch.ptr<float>(0);
  const int stride = static_cast<int>(patch.step1());
  cv::Mat out(side, side, CV_32FC1);
  std::vector<float> fxs(static_cast<size_t>(side)), fys(static_cast<size_t>(side));
  std::vector<int> offsets(static_cast<size_t>(side));
  const auto fca = static_cast<float>(ca), fsa = static_cast<float>(sa);
  for (int v = 0; v < side; ++v) {
    const double dy = v - c_out - shift_y_px, dx0 = -c_out - shift_x_px;
    const double x_row = c_in + ca * dx0 + sa * dy, y_row = c_in - sa * dx0 + ca * dy;
    const double x_end = x_row + ca * (side - 1), y_end = y_row - sa * (side - 1);
    float* o = out.ptr<float>(v);
    // (A margin of kEdge px keeps the float coordinates inside too.)
    if (std::min(x_row, x_end) >= kEdge && std::max(x_row, x_end) < last_x - kEdge &&
        std::min(y_row, y_end) >= kEdge && std::max(y_row, y_end) < last_y - kEdge) {
      // The row's samples and their 2 x 2 cells all inside the patch: the
      // coordinates in float (1e-5 px at the patch's size), truncation as
      // floor, in two passes (the coordinates', then the samples').
      const auto xr = static_cast<float>(x_row), yr = static_cast<float>(y_row);
      for (int u = 0; u < side; ++u) {
        const float x = xr + fca * static_cast<float>(u), y = yr - fsa * static_cast<float>(u);
        const int xi = static_cast<int>(x), yi = static_cast<int>(y);
        fxs[static_cast<size_t>(u)] = x - static_cast<float>(xi);
        fys[static_cast<size_t>(u)] = y - static_cast<float>(yi);
        offsets[static_cast<size_t>(u)] = yi * stride + xi;
      }
      for (int u = 0; u < side; ++u) {
        const float* p = base + offsets[static_cast<size_t>(u)];
        const float fx = fxs[static_cast<size_t>(u)];
        const float top = p[0] + fx * (p[1] - p[0]);
        const float bottom = p[stride] + fx * (p[stride + 1] - p[stride]);
        o[u] = top + fys[static_cast<size_t>(u)] * (bottom - top);
      }
      continue;
    }
    for (int u = 0; u < side; ++u) {
      const double x = x_row + ca * u, y = y_row - sa * u;
      const double xf = std::floor(x), yf = std::floor(y);
      const auto fx = static_cast<float>(x - xf), fy = static_cast<float>(y - yf);
      // Beyond the patch both corners clamp to its edge (fx, fy moot).
      const int x0 = static_cast<int>(std::clamp(xf, -1.0, static_cast<double>(last_x)));
      const int y0 = static_cast<int>(std::clamp(yf, -1.0, static_cast<double>(last_y)));
      const int xa = std::clamp(x0, 0, last_x), xb = std::clamp(x0 + 1, 0, last_x);
      const float* ra = patch.ptr<float>(std::clamp(y0, 0, last_y));
      const float* rb = patch.ptr<float>(std::clamp(y0 + 1, 0, last_y));
      const float top = ra[xa] + fx * (ra[xb] - ra[xa]);
      const float bottom = rb[xa] + fx * (rb[xb] - rb[xa]);
      o[u] = top + fy * (bottom - top);
    }
  }
  return out;
}

Site record_site(const cv::Mat& frame, const OrientationHistogram& histogram,
                 const CameraConfig& camera, const SiteOptions& options) {
  if (frame.type() != CV_8UC1 || frame.cols != camera.image_width ||
      frame.rows != camera.image_height) {
    throw std::invalid_argument("record_site: the frame must be 8-bit grey of the camera's size");
  }
  if (options.template_px < 16 || options.template_px % 4 != 0 || options.bank_size < 4 ||
      options.bank_size > 360) {
    throw std::invalid_argument(
        "record_site: template_px >= 16 and a multiple of 4, bank_size 4 .. 360");
  }
  Site s;
  s.options = options;
  const int side = static_cast<int>(std::ceil(options.template_px * std::sqrt(2.0))) + 4;
  const double cx = camera.cx(), cy = camera.cy();
  if (cx - 0.5 * side < 0.0 || cy - 0.5 * side < 0.0 || cx + 0.5 * side > frame.cols ||
      cy + 0.5 * side > frame.rows) {
    throw std::invalid_argument("record_site: the site's patch does not fit in the frame");
  }
  const cv::Mat f = to_float(frame);
  cv::getRectSubPix(f, cv::Size(side, side),
                    cv::Point2f(static_cast<float>(cx), static_cast<float>(cy)), s.patch, CV_32F);
  s.major_orientation_deg = major_orientation_deg(histogram);
  if (!std::isfinite(s.major_orientation_deg)) {
    throw std::invalid_argument("record_site: the frame has no orientation (an empty histogram)");
  }
  // Distinctiveness in its own frame.
  const int t = options.template_px;
  const cv::Mat tmpl = turned_template(s, 0.0, t);
  cv::Mat scores;
  cv::matchTemplate(f, tmpl, scores, cv::TM_CCOEFF_NORMED);
  const cv::Point own(static_cast<int>(std::lround(cx - 0.5 * (t - 1))),
                      static_cast<int>(std::lround(cy - 0.5 * (t - 1))));
  s.self_similarity = next_best(scores, own, t / 2);
  for (double a : {90.0, 180.0, 270.0}) {
    cv::Mat r;
    cv::matchTemplate(turned_template(s, a, t), tmpl, r, cv::TM_CCOEFF_NORMED);
    s.rotational_similarity =
        std::max(s.rotational_similarity, static_cast<double>(r.at<float>(0, 0)));
  }
  return s;
}

SiteTracker::SiteTracker(const Site& site, const TrackerOptions& options)
    : site_(site), options_(options) {
  if (site_.patch.empty() || site_.patch.type() != CV_32FC1) {
    throw std::invalid_argument("SiteTracker: the site has no patch");
  }
  const int n = site_.options.bank_size;
  for (int k = 0; k < n; ++k) {
    bank_coarse_.push_back(
        coarse(turned_template(site_, 360.0 * k / n, site_.options.template_px)));
  }
}

TrackResult SiteTracker::track(const cv::Mat& frame, const OrientationHistogram& histogram,
                               std::optional<cv::Point2d> centre,
                               std::optional<double> gamma_prediction_deg) const {
  if (frame.type() != CV_8UC1) throw std::invalid_argument("track: the frame must be 8-bit grey");
  TrackResult out;
  const int t = site_.options.template_px;
  const int tc = t >> kLevels;
  constexpr int kScale = 1 << kLevels;
  const double scale = kScale;
  const cv::Point2d c =
      centre.value_or(cv::Point2d(0.5 * (frame.cols - 1), 0.5 * (frame.rows - 1)));
  int coarse_cols = frame.cols, coarse_rows = frame.rows;  // after the pyrDowns
  for (int i = 0; i < kLevels; ++i) {
    coarse_cols = (coarse_cols + 1) / 2;
    coarse_rows = (coarse_rows + 1) / 2;
  }

  // The coarse search area: template top-left corners whose centre lies
  // within the radius of the prediction.
  const double r = options_.search_radius_px / scale;
  const double half = 0.5 * (tc - 1);
  const int x0 = std::max(0, static_cast<int>(std::floor(c.x / scale - r - half)));
  const int y0 = std::max(0, static_cast<int>(std::floor(c.y / scale - r - half)));
  const int x1 = std::min(coarse_cols, static_cast<int>(std::ceil(c.x / scale + r + half)) + 1);
  const int y1 = std::min(coarse_rows, static_cast<int>(std::ceil(c.y / scale + r + half)) + 1);
  if (x1 - x0 < tc || y1 - y0 < tc) return out;
  const int w = options_.refine_px;
  // Only the part of the frame the search reaches is smoothed and reduced:
  // the area at full resolution and a margin (the refinement window's, and
  // the two pyrDowns' 6 px), its corner on the coarse grid. The smoothing
  // sees the pixels around it and the margin covers the pyrDowns' edge:
  // the values are the whole frame's (the coarse level's to pyrDown's
  // float rounding, 3e-5 grey).
  const int margin = kScale * ((std::max(w, 8) + kScale - 1) / kScale);
  const cv::Rect reach =
      cv::Rect(x0 * kScale - margin, y0 * kScale - margin, (x1 - x0) * kScale + 2 * margin,
               (y1 - y0) * kScale + 2 * margin) &
      cv::Rect(0, 0, frame.cols, frame.rows);
  cv::Mat frame_f;
  frame.convertTo(frame_f, CV_32F);
  // The frame's pixel (x, y) is f(y - reach.y, x - reach.x).
  const cv::Mat f = smooth(frame_f(reach));
  const cv::Mat area =
      coarse(f)(cv::Rect(x0 - reach.x / kScale, y0 - reach.y / kScale, x1 - x0, y1 - y0));

  // Candidates: (angle, coarse template).
  struct Candidate {
    double gamma_deg;
    cv::Mat tmpl;
    Peak peak;
    cv::Mat scores;
  };
  std::vector<Candidate> cands;
  if (gamma_prediction_deg) {
    for (double d : {-10.0, 0.0, 10.0}) {
      const double g = *gamma_prediction_deg + d;
      cands.push_back({g, coarse(turned_template(site_, g, t)), {}, {}});
    }
  } else {
    const double delta =
        orientation_difference_deg(major_orientation_deg(histogram), site_.major_orientation_deg);
    if (!std::isfinite(delta)) return out;
    const int n = site_.options.bank_size;
    for (int k = 0; k < 4; ++k) {
      const double g = wrap360(delta + 90.0 * k);
      const int idx = static_cast<int>(std::lround(g * n / 360.0)) % n;
      cands.push_back({g, bank_coarse_[static_cast<size_t>(idx)], {}, {}});
    }
  }
  BlockNcc area_ncc(area, tc);  // the area's spectrum and block sums shared
  for (Candidate& cd : cands) {
    cd.scores = area_ncc.scores(ncc_template(cd.tmpl));
    cd.peak = best_in(cd.scores);
  }
  // The candidates refined at full resolution: the window about the coarse
  // peak, the angle in three rounds, then the position to a sub-pixel. The
  // quadrant is decided on the refined scores (at a quarter of the
  // resolution the small asymmetric features that tell the turns of a
  // symmetric grille apart are a few pixels).
  struct Refined {
    double score = -2.0, x = 0.0, y = 0.0, gamma = 0.0;
  };
  const auto refine = [&](const Candidate& cd) {
    const cv::Point2d coarse_tl(x0 + cd.peak.at.x, y0 + cd.peak.at.y);
    const int fx0 =
        std::clamp(static_cast<int>(std::lround(coarse_tl.x * scale)) - w, 0, frame.cols - t);
    const int fy0 =
        std::clamp(static_cast<int>(std::lround(coarse_tl.y * scale)) - w, 0, frame.rows - t);
    const int fx1 = std::min(frame.cols, fx0 + t + 2 * w);
    const int fy1 = std::min(frame.rows, fy0 + t + 2 * w);
    const cv::Mat win = f(cv::Rect(fx0 - reach.x, fy0 - reach.y, fx1 - fx0, fy1 - fy0));
    BlockNcc ncc_win(win, t);
    // The score of angle g: the sub-pixel peak's (at whole pixels a turn
    // about the template's centre trades off against the sub-pixel shift
    // of off-centre content, and the angle found is pulled by ~0.4 deg).
    // The first angle's peak over the whole window, the others' climbed to
    // from the last peak (local_peak).
    double g = cd.gamma_deg;
    cv::Point last = sub_pixel(ncc_win.scores(ncc_template(turned_template(site_, g, t)))).at;
    const auto match = [&](double a) {
      const SubPixelPeak p = local_peak(ncc_win, ncc_template(turned_template(site_, a, t)), last);
      last = p.at;
      return p;
    };
    // Hill-climb then parabola, the step shrinking by 4 each round (2, 0.5,
    // 0.125 deg by default): at each step move while a neighbour scores
    // higher (at most 4 moves), then take the parabola's vertex.
    for (double step : {options_.refine_step_deg, 0.25 * options_.refine_step_deg,
                        0.0625 * options_.refine_step_deg}) {
      double mid = match(g).score;
      for (int moves = 0; moves <= 4; ++moves) {
        const double lo = match(g - step).score, hi = match(g + step).score;
        if (moves < 4 && lo > mid && lo >= hi) {
          g -= step;
          mid = lo;
        } else if (moves < 4 && hi > mid) {
          g += step;
          mid = hi;
        } else {
          g += step * vertex(lo, mid, hi);
          break;
        }
      }
    }
    // The position: the quadratic's vertex through the 3 x 3 score cells,
    // then refined on the score of the template itself moved by sub-pixel
    // steps: the quadratic through the 3 x 3 scores at the offset +- h,
    // twice, h = 0.25 then 0.1 px.
    SubPixelPeak p = match(g);
    double sx = p.dx, sy = p.dy;
    const cv::Point whole = p.at;
    const auto ncc = [&](double x, double y) {
      return ncc_win.score(ncc_template(turned_template(site_, g, t, x, y)), whole.x, whole.y);
    };
    double score = ncc(sx, sy);
    for (double h : {0.25, 0.1}) {
      std::array<std::array<double, 3>, 3> v{};
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
          v[static_cast<size_t>(j)][static_cast<size_t>(i)] =
              i == 1 && j == 1 ? score : ncc(sx + h * (i - 1), sy + h * (j - 1));
        }
      }
      double ox = 0.0, oy = 0.0, peak = score;
      if (vertex2(v, ox, oy, peak)) {
        sx += h * ox;
        sy += h * oy;
        score = ncc(sx, sy);
      }
    }
    p.score = score;
    return Refined{p.score, fx0 + whole.x + sx + 0.5 * (t - 1), fy0 + whole.y + sy + 0.5 * (t - 1),
                   g};
  };
  // Only the candidates the coarse level cannot rule out are refined: those
  // within coarse_margin of the best coarse score; none when even the best
  // is far below min_score (no site in view: not_found without the cost).
  double best_coarse = -2.0;
  for (const Candidate& cd : cands) best_coarse = std::max(best_coarse, cd.peak.score);
  if (best_coarse < options_.min_score - options_.coarse_margin) {
    out.score = best_coarse;
    return out;
  }
  std::vector<Refined> refined;
  for (const Candidate& cd : cands) {
    refined.push_back(cd.peak.score >= best_coarse - options_.coarse_margin ? refine(cd)
                                                                            : Refined{});
  }
  std::size_t best = 0;
  for (std::size_t i = 1; i < refined.size(); ++i) {
    if (refined[i].score > refined[best].score) best = i;
  }
  double second = -2.0;
  for (std::size_t i = 0; i < refined.size(); ++i) {
    if (i != best) second = std::max(second, refined[i].score);
  }
  const Candidate& b = cands[best];
  // The fast mode's three candidates are one quadrant: no margin to keep.
  out.quadrant_margin = gamma_prediction_deg ? 1.0 : refined[best].score - second;
  out.place_margin = b.peak.score - next_best(b.scores, b.peak.at, std::max(1, tc / 2));
  out.quadrant = gamma_prediction_deg ? 0 : static_cast<int>(best);
  const Refined& p = refined[best];
  out.x_px = p.x;
  out.y_px = p.y;
  out.gamma_deg = wrap360(p.gamma);
  out.score = p.score;
  if (p.score < options_.min_score) {
    out.status = TrackStatus::not_found;
  } else if (out.quadrant_margin < options_.min_quadrant_margin ||
             out.place_margin < options_.min_place_margin) {
    out.status = TrackStatus::ambiguous;
  } else {
    out.status = TrackStatus::ok;
  }
  return out;
}

}  // namespace ceilnav::host::homing
