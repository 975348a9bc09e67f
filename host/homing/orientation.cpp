#include "host/homing/orientation.hpp"

#include <cmath>
#include <cstddef>
#include <limits>

namespace ceilnav::host::homing {

double major_orientation_deg(std::span<const double> h) {
  const int n = static_cast<int>(h.size());
  int best = -1;
  for (int k = 0; k < n; ++k) {
    if (h[static_cast<std::size_t>(k)] > 0.0 &&
        (best < 0 || h[static_cast<std::size_t>(k)] > h[static_cast<std::size_t>(best)]))
      best = k;
  }
  if (best < 0) return std::numeric_limits<double>::quiet_NaN();
  // The centroid of the peak bin and two on each side (circular): the
  // bins' own mean angle, robust to a peak one or two bins wide.
  double sw = 0.0, swk = 0.0;
  for (int d = -2; d <= 2; ++d) {
    const double w = h[static_cast<std::size_t>((best + d + n) % n)];
    sw += w;
    swk += w * d;
  }
  double deg = (best + swk / sw) * 90.0 / n;
  deg = std::fmod(deg, 90.0);
  if (deg < 0.0) deg += 90.0;
  return deg >= 45.0 ? deg - 90.0 : deg;
}

double orientation_difference_deg(double a_deg, double b_deg) {
  double d = std::fmod(a_deg - b_deg, 90.0);
  if (d < -45.0) d += 90.0;
  if (d >= 45.0) d -= 90.0;
  return d;
}

}  // namespace ceilnav::host::homing
