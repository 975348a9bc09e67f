// The guidance's frame-to-frame state: the Hough weight shift the host
// programs for the next frame, and no pan (and no turn) from an accumulator
// without lines. The whole chain on rendered frames is `ceilnav corridor`'s
// (apps/tests/cli_test.sh: pan and lateral-shift goals).
#include "host/corridor/corridor_guide.hpp"

#include <gtest/gtest.h>

namespace ceilnav::host::corridor {
namespace {

Accumulator accumulator(uint8_t weight_shift, uint64_t max_cell) {
  Accumulator a;
  a.shape.theta_step = 4;
  a.shape.rho_bits = 6;
  a.shape.acc_bits = 12;
  a.config.width = 640;
  a.config.weight_shift = weight_shift;
  a.cells.assign(static_cast<size_t>(a.shape.n_theta()) * a.shape.rho_bins(), 0);
  a.cells[17] = max_cell;
  return a;
}

TEST(CorridorGuide, WeightShiftRisesWhileCellsSaturateAndFallsWithRoomToSpare) {
  EXPECT_EQ(CorridorGuide::next_weight_shift(accumulator(5, 4095), 12), 6);
  EXPECT_EQ(CorridorGuide::next_weight_shift(accumulator(15, 4095), 1), 15);
  // Max 1023 = acc_max / 4: at shift 4 it would be at most 2 x 1023 + 1.
  EXPECT_EQ(CorridorGuide::next_weight_shift(accumulator(5, 1023), 0), 4);
  EXPECT_EQ(CorridorGuide::next_weight_shift(accumulator(5, 1024), 0), 5);
  EXPECT_EQ(CorridorGuide::next_weight_shift(accumulator(0, 3), 0), 0);
}

TEST(CorridorGuide, NoLinesNoPanNoTurn) {
  CameraConfig cam;
  GuideParams p;
  p.mount.tilt_rad = 0.6;
  CorridorGuide g(cam, p);
  const GuideFrame f = g.process(accumulator(0, 0));
  EXPECT_EQ(f.status, GuideStatus::not_found);
  EXPECT_TRUE(f.raw_lines.empty());
  EXPECT_EQ(f.turn_rad, 0.0);
  EXPECT_STREQ(to_string(f.status), "not_found");
}

}  // namespace
}  // namespace ceilnav::host::corridor
