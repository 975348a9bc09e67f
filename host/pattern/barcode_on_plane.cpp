// read_barcode_with_pose (barcode.hpp): the bar code read on the pattern
// plane from the disc's pose (docs/pattern.md, plane reader).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "host/pattern/barcode.hpp"
#include "host/pattern/barcode_blocks.hpp"
#include "host/pattern/pattern_axes.hpp"

namespace ceilnav::host::pattern {

namespace {

// A bar run's ink edges on the pattern plane, in units from its block's
// outer end.
struct Mapped {
  const stream::RunRecord* run;
  double e0, e1;  // extent along the block, units from the outer end
  Eigen::Vector2d mid;
  double width;  // normalised, along the row
};

// Every bar run's ink edges onto the pattern plane of the pose (centre t,
// pattern axes in the camera), by block side (0 left, 1 right); runs at the
// image border, off the bars' height or beyond the block are left out.
void map_bar_runs(std::span<const stream::RunRecord> runs, const Eigen::Vector3d& t,
                  const Eigen::Matrix3d& axes, const CameraModel& camera, int image_width,
                  const BarcodeOptions& o, std::vector<Mapped> (&mapped)[2]) {
  const Eigen::Vector3d n = axes.col(2);
  const double u = o.bar_unit_m;
  const double outer = o.radius_m + o.bar_gap_m + 15.0 * u;
  auto to_plane = [&](const Eigen::Vector2d& xy, Eigen::Vector2d& pat) {
    const Eigen::Vector3d ray(xy.x(), xy.y(), 1.0);
    const double den = n.dot(ray);
    if (!(std::abs(den) > 1e-12)) return false;
    const Eigen::Vector3d x = (n.dot(t) / den) * ray - t;
    pat = Eigen::Vector2d(axes.col(0).dot(x), axes.col(1).dot(x));
    return true;
  };
  for (const auto& r : runs) {
    if (r.sum_w < o.min_bar_run_weight || r.sum_w == 0) continue;
    if (r.x_start == 0 || r.x_end + 1 >= image_width) continue;
    const double centre = static_cast<double>(r.sum_xw) / static_cast<double>(r.sum_w);
    const double width = static_cast<double>(r.sum_w) / o.bar_contrast;
    const Eigen::Vector2d l = camera.normalise(centre - 0.5 * width, r.row);
    const Eigen::Vector2d rr = camera.normalise(centre + 0.5 * width, r.row);
    Eigen::Vector2d pl, pr;
    if (!to_plane(l, pl) || !to_plane(rr, pr)) continue;
    if (std::abs(0.5 * (pl.y() + pr.y())) > 0.5 * o.bar_height_m + 2.0 * u) continue;
    const double xm = 0.5 * (pl.x() + pr.x());
    const int side = xm < 0.0 ? 0 : 1;
    auto units = [&](double x) { return side == 0 ? (x + outer) / u : (outer - x) / u; };
    const double a = units(pl.x()), b = units(pr.x());
    if (std::max(a, b) < -1.0 || std::min(a, b) > 16.0) continue;
    mapped[side].push_back({&r, std::min(a, b), std::max(a, b), 0.5 * (l + rr), rr.x() - l.x()});
  }
}

// The block of one side read from its mapped runs: how many runs cover each
// 0.1-unit bin; bars are the bins covered by more than a third of the
// block's typical count; the start bar at 0..3, then gap 1, bar 1 or 2, ...,
// ending at 15, each bound within 0.35 unit; three runs across every bar.
// Returns the block value (-1: not read) and appends the bars' edges.
int read_block_on_plane(const std::vector<Mapped>& mapped, int side, const BarcodeOptions& o,
                        std::vector<BarEdge>& edges) {
  const double u = o.bar_unit_m;
  const double outer = o.radius_m + o.bar_gap_m + 15.0 * u;
  constexpr double kBin = 0.1, kFrom = -1.0, kTol = 0.35;
  constexpr int kBins = 170;
  if (mapped.size() < 3 * kBarsPerBlock) return -1;
  std::vector<int> count(kBins, 0);
  for (const Mapped& m : mapped) {
    const int b0 = std::max(0, static_cast<int>(std::ceil((m.e0 - kFrom) / kBin - 0.5)));
    const int b1 = std::min(kBins - 1, static_cast<int>(std::floor((m.e1 - kFrom) / kBin - 0.5)));
    for (int b = b0; b <= b1; ++b) ++count[static_cast<std::size_t>(b)];
  }
  std::vector<int> sorted(count.begin(), count.end());
  std::sort(sorted.begin(), sorted.end());
  const int high = sorted[static_cast<std::size_t>(kBins * 9 / 10)];
  if (high < 3) return -1;
  // Segments above the threshold: [start, end) in units.
  std::vector<std::pair<double, double>> seg;
  for (int b = 0; b < kBins; ++b) {
    const bool on = 3 * count[static_cast<std::size_t>(b)] > high;
    const bool prev = b > 0 && 3 * count[static_cast<std::size_t>(b - 1)] > high;
    const double edge = kFrom + b * kBin;
    if (on && !prev) seg.emplace_back(edge, edge);
    if (on) seg.back().second = edge + kBin;
  }
  if (seg.size() != kBarsPerBlock) return -1;
  // The start bar at 0..3, then gap 1, bar 1 or 2, ..., ending at 15.
  bool good = std::abs(seg[0].first) <= kTol && std::abs(seg[0].second - 3.0) <= kTol;
  std::array<int, 5> widths{};
  double expect = 3.0;
  for (std::size_t k = 1; k < kBarsPerBlock && good; ++k) {
    const double w = seg[k].second - seg[k].first;
    const int wi = static_cast<int>(std::lround(w));
    good = (wi == 1 || wi == 2) && std::abs(w - wi) <= kTol &&
           std::abs(seg[k].first - seg[k - 1].second - 1.0) <= kTol &&
           std::abs(seg[k].first - (expect + 1.0)) <= kTol;
    widths[k - 1] = wi;
    expect += 1.0 + wi;
  }
  if (!good || std::abs(expect - 15.0) > 0.0) return -1;
  std::array<int, 5> w5{};
  std::copy(widths.begin(), widths.end(), w5.begin());
  // Block values: widths from the outer end inward (golden block_widths).
  int v = -1;
  for (int cand = 0; cand < 10; ++cand) {
    const auto [i, j] = kPairs[static_cast<std::size_t>(cand)];
    bool match = true;
    for (int k = 0; k < 5; ++k)
      match = match && w5[static_cast<std::size_t>(k)] == ((k == i || k == j) ? 2 : 1);
    if (match) v = cand;
  }
  if (v < 0) return -1;
  // Each bar needs three runs across its whole width.
  const auto e = block_edges(v);
  std::array<int, kBarsPerBlock> across{};
  std::vector<BarEdge> side_edges;
  for (const Mapped& m : mapped) {
    for (std::size_t k = 0; k < kBarsPerBlock; ++k) {
      const double b0 = e[2 * k], b1 = e[2 * k + 1];
      const double mid = 0.5 * (m.e0 + m.e1);
      if (mid < b0 || mid > b1 || m.e1 - m.e0 < 0.8 * (b1 - b0)) continue;
      ++across[k];
      const double x0 = side == 0 ? -outer + b0 * u : outer - b1 * u;
      const double x1 = side == 0 ? -outer + b1 * u : outer - b0 * u;
      side_edges.push_back({m.mid.x(), m.mid.y(), x0, x1, m.run->row, m.width});
    }
  }
  if (*std::min_element(across.begin(), across.end()) < 3) return -1;
  edges.insert(edges.end(), side_edges.begin(), side_edges.end());
  return v;
}

}  // namespace

BarcodeRead read_barcode_with_pose(std::span<const stream::RunRecord> runs, const PatternPose& pose,
                                   const CameraModel& camera, int image_width,
                                   const BarcodeOptions& o) {
  BarcodeRead out;
  if (pose.status != PatternStatus::ok && pose.status != PatternStatus::ambiguous) return out;
  const auto axes = pattern_axes_cam(pose.normal_cam, o.up_cam);
  if (!axes || !(o.bar_contrast > 0.0)) return out;
  std::vector<Mapped> mapped[2];
  map_bar_runs(runs, pose.centre_cam, *axes, camera, image_width, o, mapped);
  int value[2] = {-1, -1};
  std::vector<BarEdge> edges;
  for (int side = 0; side < 2; ++side) {
    value[side] = read_block_on_plane(mapped[side], side, o, edges);
  }
  if (value[0] >= 0 && value[1] >= 0) {
    const int low = value[1] / 2;
    if (value[1] % 2 == (value[0] + low) % 2) {
      out.status = PatternStatus::ok;
      out.identity = value[0] * 5 + low;
      out.edges = std::move(edges);
      return out;
    }
    out.status = PatternStatus::unreadable;
    return out;
  }
  if (value[0] >= 0 || value[1] >= 0) {
    out.status = PatternStatus::partial;
    out.disc_direction = value[0] >= 0 ? 1 : -1;
    return out;
  }
  out.status = mapped[0].empty() && mapped[1].empty() ? PatternStatus::no_pattern
                                                      : PatternStatus::unreadable;
  return out;
}

}  // namespace ceilnav::host::pattern
