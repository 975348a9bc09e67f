// Contracts of estimate_tape_pose's steps that the whole-function tests do not
// pin down one by one: how runs link into chains, and that a set of inliers
// is fitted once however often it recurs.
#include "host/tape_pose_steps.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "common/run_record.hpp"

namespace ceilnav::host::tape_steps {
namespace {

stream::RunRecord run(int row, int x_start, int x_end) {
  stream::RunRecord r;
  r.row = static_cast<uint16_t>(row);
  r.x_start = static_cast<uint16_t>(x_start);
  r.x_end = static_cast<uint16_t>(x_end);
  r.sum_w = 100;
  r.sum_xw = 100 * static_cast<uint64_t>(x_start + x_end) / 2;
  return r;
}

TEST(TapeChains, RunsOfAdjacentRowsJoinWhenTheirSpansTouchDiagonalsIncluded) {
  // Out of (row, x) order on purpose: sort_runs must not rely on it.
  const std::vector<stream::RunRecord> runs{
      run(5, 10, 12),   // 0
      run(4, 13, 15),   // 1: touches 0 at a corner (8-connectivity)
      run(4, 17, 18),   // 2: one pixel right of 1, touches nothing
      run(6, 5, 8),     // 3: ends a pixel before 0 starts
      run(8, 10, 12),   // 4: row 7 is empty
      run(6, 13, 13),   // 5: touches 0 at a corner
      run(10, 30, 31),  // 6: the two arms of a U ...
      run(10, 35, 36),  // 7
      run(11, 31, 35),  // 8: ... joined by the row below
  };
  Scratch sc;
  sort_runs(runs, sc);
  link_chains(runs.size(), sc);
  chain_extents(runs.size(), sc);
  // The root of a chain is its lowest run index.
  const std::vector<int> expected_root{0, 0, 2, 3, 4, 0, 6, 6, 6};
  ASSERT_EQ(sc.root.size(), runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(sc.root[i], expected_root[i]) << i;
  // Extents are per chain, indexed by the root.
  EXPECT_EQ(sc.comp_min_row[0], 4);
  EXPECT_EQ(sc.comp_max_row[0], 6);
  EXPECT_EQ(sc.comp_min_col[0], 10);
  EXPECT_EQ(sc.comp_max_col[0], 15);
  EXPECT_EQ(sc.comp_min_row[6], 10);
  EXPECT_EQ(sc.comp_max_row[6], 11);
  EXPECT_EQ(sc.comp_min_col[6], 30);
  EXPECT_EQ(sc.comp_max_col[6], 36);
}

TEST(TapeCentreLine, ARecurringSetIsFittedOnceAndGivesTheSameLine) {
  Points pts;
  pts.resize(6);
  for (std::size_t k = 0; k < 6; ++k) {
    pts.y[k] = 0.1 * static_cast<double>(k);
    pts.x[k] = 0.5 * pts.y[k] + 0.2 + (k == 5 ? 0.05 : 0.0);  // the last one off the line
    pts.weight[k] = 1.0;
  }
  std::vector<MaskFit> memo;
  InlierFits fits(pts, 0.01, memo);
  const Mask all(6, 1);
  const LineFit f = fits.fit(all);
  ASSERT_TRUE(f.ok);
  EXPECT_EQ(memo.size(), 1u);
  const LineFit again = fits.fit(all);
  EXPECT_EQ(memo.size(), 1u);
  EXPECT_EQ(again.a, f.a);
  EXPECT_EQ(again.b, f.b);
  // The inliers of the line through the first five leave the sixth out.
  Mask first_five(6, 1);
  first_five[5] = 0;
  const LineFit g = fits.fit(first_five);
  ASSERT_TRUE(g.ok);
  EXPECT_EQ(memo.size(), 2u);
  EXPECT_NEAR(g.a, 0.5, 1e-12);
  EXPECT_NEAR(g.b, 0.2, 1e-12);
  Mask in;
  fits.inliers(g, in);
  EXPECT_EQ(in, first_five);
}

}  // namespace
}  // namespace ceilnav::host::tape_steps
