#include "nav/ceiling_height.hpp"

#include <cmath>
#include <stdexcept>

#include "nav/chi_square.hpp"

namespace ceilnav::nav {

CeilingHeightFilter::CeilingHeightFilter(const CeilingHeightOptions& options)
    : opt_(options), x_(Eigen::VectorXd::Zero(2)), p_(Eigen::MatrixXd::Zero(2, 2)) {
  if (!(opt_.map_sigma_fraction > 0.0) || !(opt_.width_bias_fraction >= 0.0) ||
      !(opt_.flow_bias_fraction >= 0.0) || !(opt_.gate_probability > 0.0) ||
      !(opt_.gate_probability < 1.0)) {
    throw std::invalid_argument(
        "CeilingHeightFilter: sigmas must be >= 0 (the map's > 0), the gate in (0, 1)");
  }
  p_(0, 0) = opt_.width_bias_fraction * opt_.width_bias_fraction;
  p_(1, 1) = opt_.flow_bias_fraction * opt_.flow_bias_fraction;
  gate_ = chi_square_quantile(opt_.gate_probability, 1.0);
}

int CeilingHeightFilter::index_of(int zone, double map_height_m) {
  if (const auto it = zone_index_.find(zone); it != zone_index_.end()) return it->second;
  if (!(map_height_m > 0.0) || !std::isfinite(map_height_m)) {
    throw std::invalid_argument("CeilingHeightFilter: the map's height must be > 0");
  }
  const int n = static_cast<int>(x_.size());
  x_.conservativeResize(n + 1);
  x_(n) = map_height_m;
  p_.conservativeResize(n + 1, n + 1);
  p_.row(n).setZero();
  p_.col(n).setZero();
  const double s = opt_.map_sigma_fraction * map_height_m;
  p_(n, n) = s * s;
  zone_index_[zone] = n;
  return n;
}

CeilingHeightFilter::Estimate CeilingHeightFilter::estimate(int zone, double map_height_m) {
  const int i = index_of(zone, map_height_m);
  Estimate e;
  e.height_m = x_(i);
  e.sigma_m = std::sqrt(p_(i, i));
  e.updates = updates_[zone];
  return e;
}

bool CeilingHeightFilter::update(int zone, double map_height_m, Source source, double z_m,
                                 double sigma_m) {
  if (!std::isfinite(z_m) || !(sigma_m > 0.0) || !std::isfinite(sigma_m)) {
    throw std::invalid_argument(
        "CeilingHeightFilter: a measurement needs a finite value and sigma > 0");
  }
  const int i = index_of(zone, map_height_m);
  const int b = source == Source::width ? 0 : 1;
  // z = h (1 + beta): H = d z / d x at the estimate.
  const double h = x_(i), beta = x_(b);
  Eigen::RowVectorXd hrow = Eigen::RowVectorXd::Zero(x_.size());
  hrow(i) = 1.0 + beta;
  hrow(b) = h;
  const double innovation = z_m - h * (1.0 + beta);
  const double s = (hrow * p_ * hrow.transpose())(0, 0) + sigma_m * sigma_m;
  int& accepted = source == Source::width ? counters_.width_accepted : counters_.flow_accepted;
  int& rejected = source == Source::width ? counters_.width_rejected : counters_.flow_rejected;
  if (innovation * innovation / s > gate_) {
    ++rejected;
    return false;
  }
  const Eigen::VectorXd k = p_ * hrow.transpose() / s;
  x_ += k * innovation;
  // Joseph form: stays symmetric and positive semi-definite.
  const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(x_.size(), x_.size()) - k * hrow;
  p_ = a * p_ * a.transpose() + k * (sigma_m * sigma_m) * k.transpose();
  ++accepted;
  ++updates_[zone];
  return true;
}

}  // namespace ceilnav::nav
