#include "host/corridor/turn_law.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ceilnav::host::corridor {

TurnLaw design_turn_law() {
  return design_turn_law(TurnLawDesign{});
}

TurnLaw design_turn_law(const TurnLawDesign& d) {
  if (!(d.convergence_length_m > 0.0) || !(d.damping > 0.0) || !(d.wheelbase_m > 0.0) ||
      !(d.credible_heading_rad > 0.0) || !(d.max_curvature_per_m > 0.0) || !std::isfinite(d.s_m)) {
    throw std::invalid_argument(
        "design_turn_law: lengths, damping, heading and curvature must be > 0");
  }
  TurnLaw law;
  law.wheelbase_m = d.wheelbase_m;
  law.c1 = 2.0 * d.damping * d.wheelbase_m / d.convergence_length_m;
  law.c2_rad_per_m = d.wheelbase_m / (d.convergence_length_m * d.convergence_length_m);
  law.heading_turn_max_rad = law.c1 * d.credible_heading_rad;
  law.shift_turn_max_rad = law.heading_turn_max_rad;
  law.max_turn_rad = std::atan(d.max_curvature_per_m * d.wheelbase_m);
  law.s_m = d.s_m;
  return law;
}

double heading_term(double delta_phi_rad, const TurnLaw& law) {
  // Eq. 27 with |c1 Delta-phi| in the condition.
  const double scaled = law.c1 * delta_phi_rad;
  if (std::abs(scaled) <= law.heading_turn_max_rad) return -scaled;
  return -std::copysign(law.heading_turn_max_rad, delta_phi_rad);
}

double shift_term(double delta_y_m, const TurnLaw& law) {
  const double g = -law.c2_rad_per_m * (delta_y_m + law.s_m);  // eq. 28
  return std::clamp(g, -law.shift_turn_max_rad, law.shift_turn_max_rad);
}

double wheel_turn(double delta_phi_rad, double delta_y_m, const TurnLaw& law) {
  const double turn = heading_term(delta_phi_rad, law) + shift_term(delta_y_m, law);  // eq. 26
  return std::clamp(turn, -law.max_turn_rad, law.max_turn_rad);
}

double yaw_rate(double turn_rad, double speed_mps, const TurnLaw& law) {
  return speed_mps * std::tan(turn_rad) / law.wheelbase_m;
}

}  // namespace ceilnav::host::corridor
