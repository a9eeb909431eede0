// WalkingPlan / WalkingTrajectorySource: the composition of a periodic aSLIP gait and the lateral H-LIP P2 orbit
// (spec §4). Checks: the COM reference is continuous (position and velocity) across every domain switch; x advances by
// the step length per step; the lateral motion is the P2 orbit (pre-impact state about each stance foot = ±(p, v) of
// the closed form, feet at ±W/2); vertical Newton's law m (z̈ + g) = F_L + F_R at the collocation nodes; lateral
// ÿ = λ² (y − y_stance) in SSP; and the block reports the same values on the global clock.
#include "systems/planners/walking_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "systems/planners/walking_trajectory_source.h"

namespace rome {
namespace {

TEST(WalkingPlan, ComposesAslipAndHlipIntoAContinuousThreeDimensionalReference) {
  const AslipPeriodicGaitPlanner planner;
  const AslipPeriodicGait gait = planner.Solve(2);
  ASSERT_TRUE(gait.success());
  const double W = 0.25, l = planner.params().step_length, m = planner.params().aslip.mass, g = 9.81;
  WalkingPlan plan;
  plan.AppendPeriodicSteps(planner, gait, 4, WalkingDomain::kLeftStance, 0.0, W);
  ASSERT_EQ(plan.segments().size(), 8u);
  EXPECT_NEAR(plan.end_time(), 4 * 0.5, 1e-12);
  const HybridLinearInvertedPendulum hlip({.z0 = gait.mean_height, .ssp_duration = 0.4, .dsp_duration = 0.1});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(W);
  for (size_t i = 0; i < plan.segments().size(); ++i) {
    const WalkingPlanSegment& s = plan.segments()[i];
    const double t_end = s.start_time + s.duration;
    const WalkingReference before = plan.Sample(t_end - 1e-9);
    if (i + 1 < plan.segments().size()) {
      const WalkingReference after = plan.Sample(t_end + 1e-9);
      EXPECT_LT((after.com_position - before.com_position).norm(), 1e-6) << "segment " << i;
      EXPECT_LT((after.com_velocity - before.com_velocity).norm(), 1e-6) << "segment " << i;
    }
    if (s.domain != WalkingDomain::kDoubleSupport) {
      const bool left = s.domain == WalkingDomain::kLeftStance;
      const double stance_y = left ? W / 2 : -W / 2;
      // Pre-impact lateral state about the stance foot: (p, v) after a left stance, −(p, v) after a right one.
      EXPECT_NEAR(before.com_position(1) - stance_y, left ? pre(0) : -pre(0), 1e-6);
      EXPECT_NEAR(before.com_velocity(1), left ? pre(1) : -pre(1), 1e-6);
      // ÿ = λ² (y − y_stance) in SSP.
      const WalkingReference mid = plan.Sample(s.start_time + 0.13);
      EXPECT_NEAR(mid.com_acceleration(1), hlip.lambda() * hlip.lambda() * (mid.com_position(1) - stance_y), 1e-9);
      // The stance foot carries everything; the other foot is in the air.
      EXPECT_EQ(mid.normal_force(left ? 1 : 0), 0.0);
      // Footholds: stance foot where it stands, the swing foot lands one step ahead on the other side.
      const Eigen::Vector2d stance = left ? mid.left_foothold : mid.right_foothold;
      const Eigen::Vector2d swing = left ? mid.right_foothold : mid.left_foothold;
      EXPECT_NEAR(swing(0) - stance(0), l, 1e-12);
      EXPECT_NEAR(stance(1), stance_y, 1e-12);
      EXPECT_NEAR(swing(1), -stance_y, 1e-12);
    }
    // Vertical Newton at the nodes: m (z̈ + g) = F_L + F_R.
    for (int k = 0; k < 21; ++k) {
      const WalkingReference r = plan.Sample(s.start_time + s.duration * k / 20.0 + (k == 20 ? -1e-12 : 0.0));
      EXPECT_NEAR(m * (r.com_acceleration(2) + g), r.normal_force.sum(), 1e-6 * m * g) << "segment " << i << " node " << k;
    }
  }
  // x advances one step length per step at the gait's mean speed.
  EXPECT_NEAR(plan.Sample(1.0).com_position(0) - plan.Sample(0.0).com_position(0), 2 * l, 1e-9);
  // Lateral sway about the walking line is the P2 orbit's: symmetric, about ±0.03 m.
  double y_max = 0.0;
  for (double t = 0.0; t <= plan.end_time(); t += 0.001) y_max = std::max(y_max, std::abs(plan.Sample(t).com_position(1)));
  EXPECT_GT(y_max, 0.02);
  EXPECT_LT(y_max, 0.05);

  // The block on the global clock.
  WalkingTrajectorySource source("walking_reference", plan);
  auto context = source.CreateDefaultLeafContext();
  context->SetTime(0.73);
  const WalkingReference r = plan.Sample(0.73);
  const Eigen::VectorXd& com = source.EvalOutput(*context, "com");
  EXPECT_EQ(com.head<3>(), r.com_position);
  EXPECT_EQ(com.tail<3>(), r.com_acceleration);
  EXPECT_EQ(source.EvalOutput(*context, "normal_force_reference"), Eigen::VectorXd(r.normal_force));
  EXPECT_EQ(source.EvalOutput(*context, "footholds").head<2>(), r.left_foothold);
}

TEST(WalkingPlan, RejectsBadArguments) {
  const AslipPeriodicGaitPlanner planner;
  AslipPeriodicGait unsolved;
  WalkingPlan plan;
  EXPECT_THROW(plan.AppendPeriodicSteps(planner, unsolved, 2, WalkingDomain::kLeftStance, 0.0, 0.25), std::invalid_argument);
  EXPECT_THROW(plan.Sample(0.0), std::logic_error);
  EXPECT_THROW(WalkingTrajectorySource("empty", WalkingPlan()), std::exception);
}

}  // namespace
}  // namespace rome
