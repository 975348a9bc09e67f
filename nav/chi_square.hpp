// The chi-square distribution's CDF and quantile, for the filter's innovation
// gate and the NEES consistency band (docs/navigation.md, "Fusion filter").
#pragma once

namespace ceilnav::nav {

// P(X <= x) for X ~ chi-square with `dof` degrees of freedom (the regularised
// lower incomplete gamma function P(dof/2, x/2)); 0 for x <= 0.
double chi_square_cdf(double x, double dof);

// The x with chi_square_cdf(x, dof) = p, 0 < p < 1, to 1e-12 relative.
double chi_square_quantile(double p, double dof);

}  // namespace ceilnav::nav
