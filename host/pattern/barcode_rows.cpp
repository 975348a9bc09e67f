// read_barcode (barcode.hpp): the bar code read along the image rows, each
// row's two blocks decoded from their edges (docs/pattern.md, bar-code reader).
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "host/pattern/barcode.hpp"
#include "host/pattern/barcode_blocks.hpp"

namespace ceilnav::host::pattern {

namespace {

// Least-squares fit of measured edges u (left, right alternating, image order)
// to model positions X (same order) by u = (a X + b) / (c X + 1) + s delta,
// s = +1 on left edges, -1 on right edges (threshold bias). Returns the RMS
// residual in units of the model (divided by the local scale du/dX).
double fit_residual(const std::array<double, 12>& u, const std::array<double, 12>& x) {
  Eigen::Matrix<double, 12, 4> a;
  Eigen::Matrix<double, 12, 1> rhs;
  for (int k = 0; k < 12; ++k) {
    const double s = (k % 2 == 0) ? 1.0 : -1.0;
    a(k, 0) = x[static_cast<std::size_t>(k)];
    a(k, 1) = 1.0;
    a(k, 2) = -x[static_cast<std::size_t>(k)] * u[static_cast<std::size_t>(k)];
    a(k, 3) = s;
    rhs(k) = u[static_cast<std::size_t>(k)];
  }
  const Eigen::Vector4d p = a.colPivHouseholderQr().solve(rhs);
  double sum = 0.0, scale = 0.0;
  for (int k = 0; k < 12; ++k) {
    const double xk = x[static_cast<std::size_t>(k)];
    const double den = p(2) * xk + 1.0;
    if (!(std::abs(den) > 1e-6)) return 1e9;
    const double pred = (p(0) * xk + p(1)) / den + ((k % 2 == 0) ? 1.0 : -1.0) * p(3);
    sum += std::pow(pred - u[static_cast<std::size_t>(k)], 2);
    scale += std::abs((p(0) - p(1) * p(2)) / (den * den));  // du/dX
  }
  scale /= 12.0;
  if (!(scale > 0.0) || !std::isfinite(sum)) return 1e9;
  return std::sqrt(sum / 12.0) / scale;
}

struct BlockRead {
  bool ok = false;
  bool left_type = false;  // wide bar on the left in the image
  int value = -1;
};

BlockRead decode_block(const std::array<double, 12>& u, const BarcodeOptions& o) {
  double best = 1e18, second = 1e18;
  BlockRead r;
  for (int type = 0; type < 2; ++type) {
    for (int v = 0; v < 10; ++v) {
      const auto e = block_edges(v);
      std::array<double, 12> x{};
      if (type == 0) {
        x = e;  // left block: outer end on the left, image order = model order
      } else {
        // Right block: outer end on the right; image order left to right is
        // the model reversed, with left/right edges swapped.
        for (int k = 0; k < 12; ++k)
          x[static_cast<std::size_t>(k)] = -e[static_cast<std::size_t>(11 - k)];
      }
      const double res = fit_residual(u, x);
      if (res < best) {
        second = best;
        best = res;
        r.left_type = type == 0;
        r.value = v;
      } else if (res < second) {
        second = res;
      }
    }
  }
  r.ok = best <= o.max_fit_residual && second >= o.min_fit_ratio * best;
  return r;
}

// One row's bars: edges in normalised x along the row, the normalised edge
// points, and whether the run touches the image border (cut).
struct RowBars {
  std::vector<std::array<double, 2>> bars;
  std::vector<std::array<Eigen::Vector2d, 2>> points;
  std::vector<bool> cut;
};

// The bars of one row's runs (sorted by x_start).
RowBars row_bars(const std::vector<const stream::RunRecord*>& rs, int row,
                 const CameraModel& camera, int image_width, const BarcodeOptions& o) {
  RowBars out;
  for (const auto* r : rs) {
    // Sub-pixel edges from the run's ink: centre sum(x w) / sum(w), width
    // sum(w) / contrast (w = the bar's darkness below the plate); the
    // integer bounds when no contrast is configured.
    double u0 = r->x_start - 0.5, u1 = r->x_end + 0.5;
    if (o.bar_contrast > 0.0 && r->sum_w > 0) {
      const double centre = static_cast<double>(r->sum_xw) / static_cast<double>(r->sum_w);
      const double width = static_cast<double>(r->sum_w) / o.bar_contrast;
      u0 = centre - 0.5 * width;
      u1 = centre + 0.5 * width;
    }
    const Eigen::Vector2d l = camera.normalise(u0, row);
    const Eigen::Vector2d rr = camera.normalise(u1, row);
    out.bars.push_back({l.x(), rr.x()});
    out.points.push_back({l, rr});
    out.cut.push_back(r->x_start == 0 || r->x_end + 1 >= image_width);
  }
  return out;
}

// Groups [first, last] of a row's bars split at gaps larger than 3 x the
// median gap; none for an empty row or a single bar.
std::vector<std::pair<std::size_t, std::size_t>> split_blocks(
    const std::vector<std::array<double, 2>>& bars) {
  std::vector<double> gaps;
  for (std::size_t k = 1; k < bars.size(); ++k) gaps.push_back(bars[k][0] - bars[k - 1][1]);
  std::vector<std::pair<std::size_t, std::size_t>> groups;
  if (gaps.empty()) return groups;
  std::vector<double> sorted = gaps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2),
                   sorted.end());
  const double med = sorted[sorted.size() / 2];
  std::size_t first = 0;
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    if (gaps[k] > 3.0 * med) {
      groups.emplace_back(first, k);
      first = k + 1;
    }
  }
  groups.emplace_back(first, bars.size() - 1);
  return groups;
}

// What the rows read so far: identity votes of the full rows, the bar centres
// per decoded block keyed by (side: 0 left, 1 right; value), rows with one
// block per side, rows with any decoded block.
struct RowTally {
  std::map<int, int> votes;
  std::map<std::pair<int, int>, std::vector<BarEdge>> block_edges_seen;
  int left_seen = 0, right_seen = 0, any_block = 0;
};

// Bar centres (sum(x w) / sum(w): unbiased by the threshold and by the
// ink-width estimate) of a decoded block starting at bar `first` of the row,
// with their pattern-frame x, kept per block for the identity chosen later.
void keep_block(const BlockRead& block, std::size_t first, const RowBars& rb, int row,
                const BarcodeOptions& o, RowTally& tally) {
  const double u = o.bar_unit_m;
  const double outer = o.radius_m + o.bar_gap_m + 15.0 * u;
  const bool left = block.left_type;
  const auto e = block_edges(block.value);
  auto& dst = tally.block_edges_seen[{left ? 0 : 1, block.value}];
  for (std::size_t k = 0; k < 6; ++k) {
    const auto& pts = rb.points[first + k];
    const Eigen::Vector2d mid = 0.5 * (pts[0] + pts[1]);
    const double x0 = left ? -outer + e[2 * k] * u : outer - e[11 - 2 * k] * u;
    const double x1 = left ? -outer + e[2 * k + 1] * u : outer - e[10 - 2 * k] * u;
    dst.push_back({mid.x(), mid.y(), x0, x1, row, pts[1].x() - pts[0].x()});
  }
}

// One row: its bars, blocks of six uncut bars decoded; a left and a right
// block that agree (parity) vote for an identity (a full row), one block is a
// partial row, anything else a bad row (counted in out).
void read_row(int row, std::vector<const stream::RunRecord*>& rs, const CameraModel& camera,
              int image_width, const BarcodeOptions& o, RowTally& tally, BarcodeRead& out) {
  std::sort(rs.begin(), rs.end(),
            [](const auto* a, const auto* b) { return a->x_start < b->x_start; });
  // Edges in normalised x along the row; runs touching the border are cut.
  const RowBars rb = row_bars(rs, row, camera, image_width, o);
  std::vector<BlockRead> blocks;
  std::vector<std::size_t> block_first;
  for (const auto& [first, last] : split_blocks(rb.bars)) {
    if (last - first + 1 != kBarsPerBlock) continue;
    bool any_cut = false;
    for (std::size_t k = first; k <= last; ++k) any_cut = any_cut || rb.cut[k];
    if (any_cut) continue;
    std::array<double, 12> u{};
    for (std::size_t k = 0; k < kBarsPerBlock; ++k) {
      u[2 * k] = rb.bars[first + k][0];
      u[2 * k + 1] = rb.bars[first + k][1];
    }
    const BlockRead b = decode_block(u, o);
    if (b.ok) {
      blocks.push_back(b);
      block_first.push_back(first);
    }
  }
  if (blocks.empty()) return;
  ++tally.any_block;
  if (blocks.size() == 2 && blocks[0].left_type && !blocks[1].left_type) {
    const int left = blocks[0].value, right = blocks[1].value;
    const int low = right / 2;
    if (right % 2 == (left + low) % 2) {
      ++tally.votes[left * 5 + low];
      ++out.full_rows;
      keep_block(blocks[0], block_first[0], rb, row, o, tally);
      keep_block(blocks[1], block_first[1], rb, row, o, tally);
    } else {
      ++out.bad_rows;
    }
  } else if (blocks.size() == 1) {
    ++out.partial_rows;
    (blocks[0].left_type ? tally.left_seen : tally.right_seen)++;
    // Used when its value is the identity's (a row need not cross both blocks).
    keep_block(blocks[0], block_first[0], rb, row, o, tally);
  } else {
    ++out.bad_rows;  // inconsistent block order or count
  }
}

// The identity read: every row's block of the identity's values gives bar
// centres, full rows or not (with the view slanted few rows cross both
// blocks); rows at the ends of a block's bars are partly covered: left out.
void accept_identity(int identity, const RowTally& tally, BarcodeRead& out) {
  out.status = PatternStatus::ok;
  out.identity = identity;
  const int left = identity / 5, low = identity % 5;
  const int right = 2 * low + (left + low) % 2;
  for (const auto& key : {std::pair{0, left}, std::pair{1, right}}) {
    const auto it = tally.block_edges_seen.find(key);
    if (it == tally.block_edges_seen.end()) continue;
    int first_row = 1 << 30, last_row = -1;
    for (const BarEdge& e : it->second) {
      first_row = std::min(first_row, e.row);
      last_row = std::max(last_row, e.row);
    }
    for (const BarEdge& e : it->second) {
      if (e.row > first_row + 2 && e.row < last_row - 2) out.edges.push_back(e);
    }
  }
}

// The identity by the majority of the full rows: at least min_full_rows
// agree and the others (bad rows too) are at most max_bad_row_fraction.
std::optional<int> identity_from_full_rows(const RowTally& tally, const BarcodeRead& out,
                                           const BarcodeOptions& o) {
  if (out.full_rows == 0) return std::nullopt;
  auto best = std::max_element(tally.votes.begin(), tally.votes.end(),
                               [](const auto& a, const auto& b) { return a.second < b.second; });
  const int agree = best->second;
  const int disagree = out.full_rows - agree + out.bad_rows;
  if (agree >= o.min_full_rows && disagree <= o.max_bad_row_fraction * (agree + disagree)) {
    return best->first;
  }
  return std::nullopt;
}

// Per block: the left value and the right value each read on enough rows,
// by the same majority rule (rows with an inconsistent block pair count
// against both), then the parity across the blocks.
std::optional<int> identity_from_blocks(const RowTally& tally, const BarcodeRead& out,
                                        const BarcodeOptions& o) {
  std::map<int, int> side_votes[2];
  int side_rows[2] = {0, 0};
  for (const auto& [key, seen] : tally.block_edges_seen) {
    const int n = static_cast<int>(seen.size() / kBarsPerBlock);
    side_votes[key.first][key.second] = n;
    side_rows[key.first] += n;
  }
  if (side_votes[0].empty() || side_votes[1].empty()) return std::nullopt;
  int value[2] = {-1, -1};
  bool consistent = true;
  for (int side = 0; side < 2; ++side) {
    const auto best =
        std::max_element(side_votes[side].begin(), side_votes[side].end(),
                         [](const auto& a, const auto& b) { return a.second < b.second; });
    const int agree = best->second;
    const int disagree = side_rows[side] - agree + out.bad_rows;
    consistent = consistent && agree >= o.min_full_rows &&
                 disagree <= o.max_bad_row_fraction * (agree + disagree);
    value[side] = best->first;
  }
  const int low = value[1] / 2;
  if (consistent && value[1] % 2 == (value[0] + low) % 2) return value[0] * 5 + low;
  return std::nullopt;
}

}  // namespace

BarcodeRead read_barcode(std::span<const stream::RunRecord> runs, const CameraModel& camera,
                         int image_width, const BarcodeOptions& o) {
  BarcodeRead out;
  if (runs.empty()) return out;
  std::map<int, std::vector<const stream::RunRecord*>> rows;
  for (const auto& r : runs) {
    if (o.bar_contrast > 0.0 && r.sum_w < o.min_bar_run_weight) continue;  // the disc's runs
    rows[r.row].push_back(&r);
  }
  RowTally tally;
  for (auto& [row, rs] : rows) read_row(row, rs, camera, image_width, o, tally, out);
  if (const auto id = identity_from_full_rows(tally, out, o)) {
    accept_identity(*id, tally, out);
    return out;
  }
  if (const auto id = identity_from_blocks(tally, out, o)) {
    accept_identity(*id, tally, out);
    return out;
  }
  if (out.full_rows > 0) {
    out.status = PatternStatus::unreadable;
    return out;
  }
  if (tally.left_seen + tally.right_seen > 0) {
    out.status = PatternStatus::partial;
    out.disc_direction =
        tally.left_seen > tally.right_seen ? 1 : (tally.right_seen > tally.left_seen ? -1 : 0);
    return out;
  }
  out.status = tally.any_block > 0 || out.bad_rows > 0 || !rows.empty() ? PatternStatus::unreadable
                                                                        : PatternStatus::no_pattern;
  return out;
}

}  // namespace ceilnav::host::pattern
