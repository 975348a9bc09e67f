// The layout of one block of the bar code, shared by the row and the plane
// readers (not part of the front header pattern_pose.hpp): six bars, a start
// bar of 3 units then five bars of 1 or 2 units (two of them 2) with gaps of
// 1, ending 15 units from the block's outer end.
#pragma once

#include <array>
#include <cstddef>
#include <utility>

namespace ceilnav::host::pattern {

inline constexpr int kBarsPerBlock = 6;
// The two wide bars of each block value 0..9.
inline constexpr std::array<std::pair<int, int>, 10> kPairs{
    {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 2}, {1, 3}, {1, 4}, {2, 3}, {2, 4}, {3, 4}}};

// Edge positions in units from the block's outer end (wide bar first), 12 edges.
inline std::array<double, 2 * kBarsPerBlock> block_edges(int value) {
  std::array<double, 2 * kBarsPerBlock> e{};
  e[0] = 0.0;
  e[1] = 3.0;
  double x = 3.0;
  for (int k = 0; k < 5; ++k) {
    const auto [i, j] = kPairs[static_cast<std::size_t>(value)];
    const int w = (k == i || k == j) ? 2 : 1;
    x += 1.0;
    e[static_cast<std::size_t>(2 + 2 * k)] = x;
    x += w;
    e[static_cast<std::size_t>(3 + 2 * k)] = x;
  }
  return e;
}

}  // namespace ceilnav::host::pattern
