// Closed-loop stepping-stones walking (Algorithm 1 of the stepping-stones paper) on AMBER: the example's diagram
// run event by event, 12 steps on flat ground with l = 0.4 m: no fall, convergence to a periodic orbit (post-impact
// L_y of the last steps within 1 %), L+ within 3 % of the planner's L_des, touchdowns within 2 cm of the stone
// centres. The 30-step sweep over the paper's periodic footholds is stepping_stones_walking_sweep_test (slow).
#include "diagrams/stepping_stones/stepping_stones_diagram.h"

#include <gtest/gtest.h>

#include "tests/diagrams/stepping_stones/stepping_stones_walk.h"

namespace rome {
namespace {

TEST(SteppingStonesDiagram, FlatGroundConvergesToAPeriodicOrbit) {
  const int steps = 12;
  test::ExpectPeriodicWalk(test::Walk(PeriodicSteppingStones(0.4, 0.0, steps + 2), steps), steps, "flat l = 0.4 m");
}

TEST(SteppingStonesDiagram, TerrainHelpersRejectBadInput) {
  EXPECT_THROW(PeriodicSteppingStones(0.05, 0.0, 10), std::invalid_argument);  // stones would overlap
  EXPECT_THROW(PeriodicSteppingStones(0.4, 0.0, 1), std::invalid_argument);
  RandomSteppingStonesParams p;
  p.min_gap_m = 0.8;  // above max_gap_m
  EXPECT_THROW(RandomSteppingStones(p), std::invalid_argument);
  // The random stones respect the paper's ranges.
  const Terrain t = RandomSteppingStones(RandomSteppingStonesParams{});
  for (size_t k = 1; k < t.stones().size(); ++k) {
    const double gap = t.stones()[k].x_center_m - t.stones()[k - 1].x_center_m;
    const double rise = t.stones()[k].top_height_m - t.stones()[k - 1].top_height_m;
    EXPECT_GE(gap, 0.2);
    EXPECT_LE(gap, 0.7);
    EXPECT_LE(std::abs(rise), 0.25);
  }
}

}  // namespace
}  // namespace rome
