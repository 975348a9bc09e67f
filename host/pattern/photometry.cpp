#include "host/pattern/photometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ceilnav::host::pattern {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kBins = 256;

using Histogram = std::array<uint32_t, kBins>;

double count(const Histogram& h, int lo, int hi) {
  double n = 0.0;
  for (int g = std::max(lo, 0); g <= std::min(hi, kBins - 1); ++g)
    n += h[static_cast<std::size_t>(g)];
  return n;
}

// The q-quantile of the pixels with grey in [lo, hi], a bin g spreading its
// pixels evenly over [g - 1/2, g + 1/2] (the camera's rounding).
double quantile(const Histogram& h, int lo, int hi, double q) {
  const double total = count(h, lo, hi);
  if (!(total > 0.0)) return kNaN;
  const double target = q * total;
  double below = 0.0;
  for (int g = std::max(lo, 0); g <= std::min(hi, kBins - 1); ++g) {
    const double n = h[static_cast<std::size_t>(g)];
    if (below + n >= target && n > 0.0) return g - 0.5 + (target - below) / n;
    below += n;
  }
  return hi + 0.5;
}

// The mode of the pixels with grey in [lo, hi] after smoothing the histogram
// with a Gaussian of sigma (the noise's: a level's peak keeps its place), to
// a fraction of a bin by a parabola through the peak and its neighbours.
double mode(const Histogram& h, int lo, int hi, double sigma) {
  lo = std::max(lo, 0);
  hi = std::min(hi, kBins - 1);
  if (hi < lo) return kNaN;
  const int half = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> s(static_cast<std::size_t>(hi - lo + 1), 0.0);
  for (int g = lo; g <= hi; ++g) {
    double acc = 0.0;
    for (int t = -half; t <= half; ++t) {
      const int k = g + t;
      if (k < lo || k > hi) continue;
      acc += std::exp(-0.5 * t * t / (sigma * sigma)) * h[static_cast<std::size_t>(k)];
    }
    s[static_cast<std::size_t>(g - lo)] = acc;
  }
  const auto it = std::max_element(s.begin(), s.end());
  if (!(*it > 0.0)) return kNaN;
  const auto i = static_cast<std::size_t>(it - s.begin());
  double frac = 0.0;
  if (i > 0 && i + 1 < s.size()) {
    const double a = s[i - 1], b = s[i], c = s[i + 1];
    const double den = a - 2.0 * b + c;
    if (den < 0.0) frac = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
  }
  return lo + static_cast<double>(i) + frac;
}

// Pixels darker than x (bins spread evenly over their +-1/2, as quantile).
double below(const Histogram& h, double x) {
  double n = 0.0;
  for (int g = 0; g < kBins; ++g) {
    const double lo = g - 0.5;
    if (lo >= x) break;
    n += h[static_cast<std::size_t>(g)] * std::min(1.0, x - lo);
  }
  return n;
}

// The level of the darkest class from its lower half only: for cores normal
// about the level b, F(b - z sigma) = Phi(-z) / Phi(0) F(b) with F the count
// below (the partly inked pixels, lighter than the cores, leave F below b
// nearly untouched; the pixels the camera clips to 0 lie below b - sigma and
// count as they should while b - z sigma >= 1/2). F(x - z sigma) / F(x)
// rises with x through the cores' lower half: b is where it reaches the
// ratio, scanned from 1/2 + z sigma up. NaN when it is reached at the start (the
// level lies under 1/2 + sigma: clipped), not below `limit`, or with fewer
// than min_cores pixels below it (2 F(b): the cores).
double dark_level(const Histogram& h, double sigma, double limit, double min_cores, double z) {
  const double ratio = 0.5 * std::erfc(z / std::sqrt(2.0)) / 0.5;  // Phi(-z) / Phi(0)
  constexpr double kStep = 0.05;
  bool first = true;
  for (double x = 0.5 + z * sigma; x < limit; x += kStep) {
    const double f = below(h, x);
    if (!(f > 0.0)) continue;
    if (below(h, x - z * sigma) >= ratio * f) {
      if (first || 2.0 * f < min_cores) return kNaN;
      return x;
    }
    first = false;
  }
  return kNaN;
}

// The class thresholds of golden::pattern::class_thresholds for the levels.
struct Split {
  int bar_below, shadow_from, pattern_from;
  friend bool operator==(const Split&, const Split&) = default;
};
Split split(double black, double scale, const PatternAlbedos& a) {
  const double lb = black + scale * a.bar, lw = black + scale * a.wall;
  const double ls = black + scale * a.shadow, ld = black + scale * a.disc;
  Split s{};
  s.bar_below = std::max(1, static_cast<int>(std::lround(lb + (lw - lb) / 3.0)));
  s.shadow_from = static_cast<int>(std::lround(0.5 * (lw + ls)));
  s.pattern_from = std::min(255, static_cast<int>(std::lround(0.5 * (lw + ld))));
  return s;
}

}  // namespace

std::string to_string(PhotometryStatus s) {
  switch (s) {
    case PhotometryStatus::ok:
      return "ok";
    case PhotometryStatus::no_disc:
      return "no_disc";
    case PhotometryStatus::clipped:
      return "clipped";
    case PhotometryStatus::out_of_range:
      return "out_of_range";
    case PhotometryStatus::low_contrast:
      return "low_contrast";
    case PhotometryStatus::imprecise:
      return "imprecise";
    case PhotometryStatus::inconsistent:
      return "inconsistent";
    case PhotometryStatus::not_converged:
      return "not_converged";
  }
  return "unknown";
}

double level_from_band_counts(double n_low, double n_high, int lo, int mid, int hi, double sigma) {
  if (!(n_low > 0.0) || !(n_high > 0.0) || !(lo < mid && mid < hi) || !(sigma > 0.0)) return kNaN;
  auto phi = [&](double x, double mu) {
    return 0.5 * std::erfc(-(x - mu) / (sigma * std::sqrt(2.0)));
  };
  auto ratio = [&](double mu) {
    const double p_lo = phi(mid - 0.5, mu) - phi(lo - 0.5, mu);
    const double p_hi = phi(hi - 0.5, mu) - phi(mid - 0.5, mu);
    return p_hi / p_lo;
  };
  const double target = n_high / n_low;
  double a = lo - 4.0 * sigma, b = hi + 4.0 * sigma;
  if (!(ratio(a) < target && ratio(b) > target)) return kNaN;
  for (int i = 0; i < 60; ++i) {
    const double m = 0.5 * (a + b);
    (ratio(m) < target ? a : b) = m;
  }
  return 0.5 * (a + b);
}

PhotometricCalibration calibrate_photometry(const Histogram& h, const PatternAlbedos& a,
                                            const PhotometryOptions& o, double local_wall_grey) {
  PhotometricCalibration c;
  c.black = o.nominal_black;
  c.scale = o.nominal_scale;
  const double sigma = std::max(1.0, o.noise_grey);
  constexpr int kMaxIterations = 12;
  for (c.iterations = 1; c.iterations <= kMaxIterations; ++c.iterations) {
    const Split t = split(c.black, c.scale, a);
    if (!(t.bar_below < t.shadow_from && t.shadow_from < t.pattern_from)) {
      c.status = PhotometryStatus::low_contrast;
      return c;
    }
    // Disc: every pixel at or above the disc threshold. Its median is the
    // disc's level while fewer than half of them are clipped at 255 (the
    // edge pixels above the midpoint are a few per cent of the class).
    const double n_disc = count(h, t.pattern_from, 255);
    if (n_disc < o.min_disc_pixels) {
      c.status = PhotometryStatus::no_disc;
      return c;
    }
    c.disc_clipped = h[255] > 0.35 * n_disc;
    c.disc_grey = c.disc_clipped ? kNaN : quantile(h, t.pattern_from, 255, 0.5);
    // Searched up to the wall's noise, not only in the bar class: a level
    // the start's split puts at the class's edge is found all the same.
    const double wall_now = c.black + c.scale * a.wall;
    const double limit = std::max<double>(t.bar_below, wall_now - 2.5 * sigma);
    c.bar_grey = dark_level(h, sigma, limit, o.min_bar_pixels, 1.0);
    // Deeper in the tail (z = 2, where the level allows): the partly inked
    // pixels weigh less there. Where the two disagree by more than sigma / 2
    // the dark pixels are not a level with its noise (bars under two pixels
    // wide: no cores) and the bars give no level.
    const double deep = dark_level(h, sigma, limit, o.min_bar_pixels, 2.0);
    if (std::isfinite(deep)) {
      c.bar_grey = std::abs(deep - c.bar_grey) <= 0.25 * sigma ? deep : kNaN;
    }
    c.bar_clipped = !std::isfinite(c.bar_grey);
    c.wall_grey =
        local_wall_grey >= 0.0 ? local_wall_grey : mode(h, t.bar_below, t.shadow_from - 1, sigma);

    double black = 0.0, scale = 0.0;
    const bool local_wall = local_wall_grey >= 0.0;
    if (!c.disc_clipped && (c.bar_clipped || local_wall)) {
      // The disc and the wall around it: the two levels its edge lies
      // between, measured where it is.
      scale = (c.disc_grey - c.wall_grey) / (a.disc - a.wall);
      black = c.disc_grey - scale * a.disc;
    } else if (!c.disc_clipped) {  // the disc and the bars (no wall measured there)
      black = c.bar_grey;
      scale = (c.disc_grey - black) / (a.disc - a.bar);
    } else if (!c.bar_clipped) {  // disc clipped: the bars and the wall
      scale = (c.wall_grey - c.bar_grey) / (a.wall - a.bar);
      black = c.bar_grey - scale * a.bar;
    } else {  // both clipped: the wall alone cannot give two unknowns
      c.status = PhotometryStatus::clipped;
      return c;
    }
    if (!(scale > 0.0) || !std::isfinite(black)) {
      c.status = PhotometryStatus::low_contrast;
      return c;
    }
    c.black = black;
    c.scale = scale;
    // The same class split again gives the same estimate: a fixed point.
    if (split(c.black, c.scale, a) == t) break;
  }
  if (c.iterations > kMaxIterations) {
    c.status = PhotometryStatus::not_converged;
    return c;
  }
  const double gain = c.gain(o), offset = c.offset(o);
  // The wall's albedo covers more of any view of the pattern than the bars'
  // ink (the plates, the gaps and the rim alone are most of the ink's area,
  // and the wall panel surrounds them): a split that gives the bar class
  // more pixels than the wall class took a darker wall for the bars (and,
  // at a steep view, the side wall for the wall).
  const Split fin = split(c.black, c.scale, a);
  const bool consistent =
      count(h, fin.bar_below, fin.shadow_from - 1) >= count(h, 0, fin.bar_below - 1);
  if (!consistent) {
    c.status = PhotometryStatus::inconsistent;
  } else if (!(gain >= o.min_gain && gain <= o.max_gain) ||
             !(std::abs(offset) <= o.max_offset_grey)) {
    c.status = PhotometryStatus::out_of_range;
  } else if (c.scale * (a.wall - a.bar) < o.min_bar_contrast_sigmas * sigma) {
    c.status = PhotometryStatus::low_contrast;
  } else if (c.disc_clipped && o.disc_radius_px > 0.0 &&
             o.edge_px_per_contrast * o.level_error_grey / (c.scale * (a.wall - a.bar)) >
                 o.max_radius_error * o.disc_radius_px) {
    c.status = PhotometryStatus::imprecise;
  } else {
    c.status = PhotometryStatus::ok;
  }
  return c;
}

}  // namespace ceilnav::host::pattern
