#include "nav/chi_square.hpp"

#include <cmath>

namespace ceilnav::nav {
namespace {

// Regularised lower incomplete gamma P(a, x), x > 0: the power series
// x^a e^-x / Gamma(a+1) * sum_n x^n / ((a+1)...(a+n)) below x = a + 1, else
// 1 - Q with Q from its continued fraction (modified Lentz evaluation).
double gamma_p(double a, double x) {
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 1000 && std::abs(term) > 1e-17 * std::abs(sum); ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return sum * std::exp(log_prefix);
  }
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 1000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double chi_square_cdf(double x, double dof) {
  if (!(x > 0.0)) return 0.0;
  return gamma_p(0.5 * dof, 0.5 * x);
}

double chi_square_quantile(double p, double dof) {
  double lo = 0.0, hi = dof + 10.0;
  while (chi_square_cdf(hi, dof) < p) hi *= 2.0;
  while (hi - lo > 1e-12 * hi) {
    const double mid = 0.5 * (lo + hi);
    (chi_square_cdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace ceilnav::nav
