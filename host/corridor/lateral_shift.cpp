#include "host/corridor/lateral_shift.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ceilnav::host::corridor {
namespace {

// One-to-one matches of the candidate pairs to a proposed shift: pairs
// within the tolerance, greedily by residual, each current and model line
// used once. Returns the pairs' indices into `pairs`.
std::vector<std::size_t> agree(const std::vector<LineShift>& pairs, double proposal,
                               double tolerance, double& residual_sum) {
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    if (std::abs(pairs[k].shift_m - proposal) <= tolerance) order.push_back(k);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::abs(pairs[a].shift_m - proposal) < std::abs(pairs[b].shift_m - proposal);
  });
  std::vector<std::size_t> out;
  std::vector<int> used_line, used_model;
  residual_sum = 0.0;
  for (std::size_t k : order) {
    const LineShift& p = pairs[k];
    if (std::find(used_line.begin(), used_line.end(), p.line) != used_line.end()) continue;
    if (std::find(used_model.begin(), used_model.end(), p.model_line) != used_model.end()) continue;
    used_line.push_back(p.line);
    used_model.push_back(p.model_line);
    residual_sum += std::abs(p.shift_m - proposal);
    out.push_back(k);
  }
  return out;
}

double weighted_mean(const std::vector<LineShift>& pairs, const std::vector<std::size_t>& picks,
                     double& sigma) {
  double sw = 0.0, swx = 0.0;
  for (std::size_t k : picks) {
    const double w = 1.0 / (pairs[k].sigma_m * pairs[k].sigma_m);
    sw += w;
    swx += w * pairs[k].shift_m;
  }
  sigma = 1.0 / std::sqrt(sw);
  return swx / sw;
}

}  // namespace

std::optional<LineShift> line_shift(const ImageLine& line, double pan_rad,
                                    const CorridorModel& model, int model_line,
                                    const ShiftOptions& options) {
  const ModelLine& m = model.lines.at(static_cast<std::size_t>(model_line));
  const std::optional<double> q = inclination(line, model.camera, pan_rad);
  if (!q) return std::nullopt;
  LineShift s;
  s.model_line = model_line;
  s.shift_m = m.height_m * (m.inclination - *q);  // S1
  const Eigen::Vector2d g = inclination_gradient(line, model.camera, pan_rad);
  s.d_shift_d_theta = -m.height_m * g.x();
  s.d_shift_d_rho = -m.height_m * g.y();
  s.sigma_m = std::hypot(s.d_shift_d_theta * options.sigma_theta_rad,
                         s.d_shift_d_rho * options.sigma_rho_px);
  // Never a zero sigma (a weight of infinity): 0.1 mm floor.
  s.sigma_m = std::max(s.sigma_m, 1e-4);
  s.strength = line.strength;
  return s;
}

LateralShift lateral_shift(const std::vector<ImageLine>& lines, double pan_rad,
                           const CorridorModel& model, const ShiftOptions& options) {
  std::vector<LineShift> pairs;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    for (std::size_t j = 0; j < model.lines.size(); ++j) {
      std::optional<LineShift> s =
          line_shift(lines[i], pan_rad, model, static_cast<int>(j), options);
      if (!s) continue;
      s->line = static_cast<int>(i);
      pairs.push_back(*s);
    }
  }
  LateralShift out;
  if (pairs.empty()) return out;

  // Consensus: each pair's shift is a proposal, scored by its matches and
  // the prior (ShiftOptions).
  const double centre = options.prior_m.value_or(0.0);
  const auto score = [&](double s, std::size_t matches) {
    double v = static_cast<double>(matches);
    if (options.prior_m) {
      const double z = (s - *options.prior_m) / options.prior_sigma_m;
      v -= 0.5 * z * z;
    }
    return v;
  };
  std::vector<std::size_t> best;
  double best_score = -std::numeric_limits<double>::infinity();
  double best_residual = std::numeric_limits<double>::infinity();
  double best_distance = std::numeric_limits<double>::infinity();
  for (const LineShift& p : pairs) {
    if (options.prior_m && std::abs(p.shift_m - *options.prior_m) > options.prior_gate_m) continue;
    double residual = 0.0;
    const std::vector<std::size_t> picks =
        agree(pairs, p.shift_m, options.match_tolerance_m, residual);
    double sigma = 0.0;
    const double s = weighted_mean(pairs, picks, sigma);
    const double v = score(s, picks.size());
    const double distance = std::abs(s - centre);
    const bool better =
        v > best_score + 1e-9 || (v >= best_score - 1e-9 &&
                                  (residual < best_residual - 1e-9 ||
                                   (residual <= best_residual + 1e-9 && distance < best_distance)));
    if (better) {
      best = picks;
      best_score = v;
      best_residual = residual;
      best_distance = distance;
    }
  }
  if (best.empty()) return out;
  // Refine: the matches around the weighted mean of the winners.
  double sigma = 0.0;
  double mean = weighted_mean(pairs, best, sigma);
  double residual = 0.0;
  const std::vector<std::size_t> refined = agree(pairs, mean, options.match_tolerance_m, residual);
  if (refined.size() >= best.size()) best = refined;
  mean = weighted_mean(pairs, best, sigma);

  out.valid = true;
  out.shift_m = mean;
  out.sigma_m = sigma;
  const LineShift* strongest = nullptr;
  for (std::size_t k : best) {
    out.matches.push_back(pairs[k]);
    if (strongest == nullptr || pairs[k].strength > strongest->strength) strongest = &pairs[k];
  }
  std::sort(out.matches.begin(), out.matches.end(),
            [](const LineShift& a, const LineShift& b) { return a.model_line < b.model_line; });
  out.strongest_shift_m = strongest->shift_m;
  out.strongest_sigma_m = strongest->sigma_m;
  return out;
}

}  // namespace ceilnav::host::corridor
