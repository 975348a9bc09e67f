#include "golden/hough_ref.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <opencv2/imgproc.hpp>

#include "fixedpoint/hough_trig.hpp"

namespace ceilnav::golden {

namespace {

constexpr uint32_t kCoordLimit = 2048;

template <class RhoIndex>
std::vector<uint64_t> accumulate(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                                 const std::vector<EdgePoint>& edges, RhoIndex rho_index) {
  const uint32_t bins = shape.rho_bins();
  std::vector<uint64_t> acc(static_cast<size_t>(shape.n_theta()) * bins, 0u);
  if (!cfg.enable) {
    return acc;
  }
  const stream::ThetaRange range = stream::theta_range(shape, cfg);
  for (int j = range.first; j < range.first + range.count; ++j) {
    const int k_deg = j * shape.theta_step;
    for (const EdgePoint& e : edges) {
      if (e.x >= kCoordLimit || e.y >= kCoordLimit) {
        continue;
      }
      // eq. 18: w = (row - r) / s with r = row - 1 - y counted from the bottom.
      const uint64_t w = cfg.unit_weight ? 1u : ((uint64_t{e.y} + 1u) >> cfg.weight_shift);
      int64_t idx = 0;
      if (rho_index(e, k_deg, idx) && idx >= 0 && idx < int64_t{bins}) {
        acc[static_cast<size_t>(j - range.first) * bins + static_cast<size_t>(idx)] += w;
      }
    }
  }
  return acc;
}

}  // namespace

std::vector<uint64_t> hough_ref(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                                const std::vector<EdgePoint>& edges) {
  const auto& table = fp::hough::trig_table();
  const int frac = fp::hough::kTrigFrac;
  return accumulate(shape, cfg, edges, [&](const EdgePoint& e, int k, int64_t& idx) {
    const auto kk = static_cast<size_t>(k);
    // rho * 2^frac in exact integers, biased by the configured width.
    int64_t sum = int64_t{e.x} * table.cos[kk] + int64_t{e.y} * table.sin[kk] +
                  int64_t{cfg.width} * (int64_t{1} << frac);
    // round (half up) of the division by 2^(frac + rho_shift)
    const int64_t den = int64_t{1} << (frac + cfg.rho_shift);
    sum += den / 2;
    idx = sum >= 0 ? sum / den : -((-sum + den - 1) / den);
    return true;
  });
}

std::vector<uint32_t> hough_cells_ref(const stream::HoughShape& shape,
                                      const stream::HoughConfig& cfg,
                                      const std::vector<stream::EdgeRecord>& edges) {
  std::vector<EdgePoint> pts;
  pts.reserve(edges.size());
  for (const stream::EdgeRecord& e : edges) pts.push_back({e.x, e.y});
  std::vector<uint32_t> cells;
  for (const uint64_t c : hough_ref(shape, cfg, pts)) {
    cells.push_back(static_cast<uint32_t>(std::min<uint64_t>(c, shape.acc_max())));
  }
  return cells;
}

std::vector<uint64_t> hough_ref_double(const stream::HoughShape& shape,
                                       const stream::HoughConfig& cfg,
                                       const std::vector<EdgePoint>& edges) {
  return accumulate(shape, cfg, edges, [&](const EdgePoint& e, int k, int64_t& idx) {
    const double t = k * std::numbers::pi / 180.0;
    const double rho = e.x * std::cos(t) + e.y * std::sin(t) + cfg.width;
    idx = static_cast<int64_t>(std::floor(std::ldexp(rho, -cfg.rho_shift) + 0.5));
    return true;
  });
}

std::vector<EdgePoint> line_points(double rho, double theta_deg, int w, int h) {
  const double t = theta_deg * std::numbers::pi / 180.0;
  const double c = std::cos(t);
  const double s = std::sin(t);
  std::vector<EdgePoint> p;
  const bool by_column = std::abs(s) > std::abs(c);
  for (int u = 0; u < (by_column ? w : h); ++u) {
    const auto v = static_cast<int>(std::lround(by_column ? (rho - u * c) / s : (rho - u * s) / c));
    if (v >= 0 && v < (by_column ? h : w)) {
      const auto a = static_cast<uint16_t>(u);
      const auto b = static_cast<uint16_t>(v);
      p.push_back(by_column ? EdgePoint{a, b} : EdgePoint{b, a});
    }
  }
  return p;
}

HoughPeak hough_peak(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                     const std::vector<uint64_t>& acc) {
  const stream::ThetaRange range = stream::theta_range(shape, cfg);
  size_t best = 0;
  for (size_t i = 1; i < acc.size(); ++i) {
    if (acc[i] > acc[best]) {
      best = i;
    }
  }
  const size_t bins = shape.rho_bins();
  const auto j = static_cast<int>(best / bins);
  const auto r = static_cast<double>(best % bins);
  HoughPeak p;
  p.votes = acc[best];
  p.theta = (range.first + j) * shape.theta_step * std::numbers::pi / 180.0;
  p.rho = std::ldexp(r, cfg.rho_shift) - cfg.width;
  return p;
}

HoughPeak opencv_strongest_line(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                                const std::vector<EdgePoint>& edges, int width, int height) {
  cv::Mat img = cv::Mat::zeros(height, width, CV_8UC1);
  for (const EdgePoint& e : edges) {
    img.at<uchar>(e.y, e.x) = 255;
  }
  std::vector<cv::Vec3f> lines;  // rho, theta, votes
  cv::HoughLines(img, lines, std::ldexp(1.0, cfg.rho_shift),
                 shape.theta_step * std::numbers::pi / 180.0, 1);
  HoughPeak p;
  if (!lines.empty()) {
    p.rho = lines[0][0];
    p.theta = lines[0][1];
    p.votes = static_cast<uint64_t>(std::lround(lines[0][2]));
  }
  return p;
}

}  // namespace ceilnav::golden
