// WalkingPlan / WalkingTrajectorySource: the composition of a periodic aSLIP gait and the lateral H-LIP P2 orbit
// (spec §4). Checks: the COM reference is continuous (position and velocity) across every domain switch; x advances by
// the step length per step; the lateral motion is the P2 orbit (pre-impact state about each stance foot = ±(p, v) of
// the closed form, feet at ±W/2); vertical Newton's law m (z̈ + g) = F_L + F_R at the collocation nodes; lateral
// ÿ = λ² (y − y_stance) in SSP; and the block reports the same values on the global clock.
#include "systems/planners/walking_plan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "systems/planners/walking_trajectory_source.h"

namespace rome {
namespace {

// A walking line at y = d is the same motion moved sideways by d (the H-LIP is translation invariant): every sample's
// lateral COM and footholds differ by d, everything else is equal.
TEST(WalkingPlan, AWalkingLineOffsetMovesTheLateralMotionAndFootholdsRigidly) {
  const AslipPeriodicGaitPlanner planner;
  const AslipPeriodicGait gait = planner.Solve(2);
  ASSERT_TRUE(gait.success());
  const double W = 0.22, d = -0.137;
  WalkingPlan centred, moved;
  centred.AppendPeriodicSteps(planner, gait, 3, WalkingDomain::kRightStance, 0.4, W);
  moved.AppendPeriodicSteps(planner, gait, 3, WalkingDomain::kRightStance, 0.4, W, false, false, d);
  for (int k = 0; k <= 300; ++k) {
    const double t = centred.end_time() * k / 300.0;
    const WalkingReference a = centred.Sample(t), b = moved.Sample(t);
    EXPECT_NEAR(b.com_position.y() - a.com_position.y(), d, 1e-12) << t;
    EXPECT_NEAR(b.com_position.x(), a.com_position.x(), 1e-12);
    EXPECT_NEAR(b.com_velocity.y(), a.com_velocity.y(), 1e-12);
    EXPECT_NEAR(b.com_acceleration.y(), a.com_acceleration.y(), 1e-9);
    EXPECT_NEAR(b.left_foothold.y() - a.left_foothold.y(), d, 1e-12);
    EXPECT_NEAR(b.right_foothold.y() - a.right_foothold.y(), d, 1e-12);
  }
  EXPECT_THROW(
      moved.AppendPeriodicSteps(planner, gait, 1, WalkingDomain::kLeftStance, 0.0, W, false, false, std::nan("")),
      std::invalid_argument);
}

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
      const WalkingReference r = plan.Sample(s.start_time + s.duration * k / 20.0 + (k == 20 ? -1e-9 : 0.0));
      EXPECT_NEAR(m * (r.com_acceleration(2) + g), r.normal_force.sum(), 1e-6 * m * g)
          << "segment " << i << " node " << k;
    }
  }
  // x advances one step length per step at the gait's mean speed.
  EXPECT_NEAR(plan.Sample(1.0).com_position(0) - plan.Sample(0.0).com_position(0), 2 * l, 1e-9);
  // Lateral sway about the walking line is the P2 orbit's: symmetric, about ±0.03 m.
  double y_max = 0.0;
  for (double t = 0.0; t <= plan.end_time(); t += 0.001)
    y_max = std::max(y_max, std::abs(plan.Sample(t).com_position(1)));
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
  // With a lead, only the force reference reads the plan ahead (the force band's look-ahead).
  WalkingTrajectorySource ahead("walking_reference", plan, 2e-3);
  auto ahead_context = ahead.CreateDefaultLeafContext();
  ahead_context->SetTime(0.73);
  EXPECT_EQ(ahead.EvalOutput(*ahead_context, "normal_force_reference"),
            Eigen::VectorXd(plan.Sample(0.732).normal_force));
  EXPECT_EQ(ahead.EvalOutput(*ahead_context, "com").head<3>(), r.com_position);
  EXPECT_THROW(WalkingTrajectorySource("walking_reference", plan, -1e-3), std::runtime_error);
}

TEST(WalkingPlan, StandingStartTransitionJoinsThePeriodicGait) {
  // The paper's pipeline (spec §0): periodic aSLIP → transition footed aSLIP (standing → gait A, right foot lifts) →
  // footed H-LIP QP on the transition's grid and forces → composition with gait A's steps.
  AslipPeriodicGaitParams gait_params;
  const AslipPeriodicGaitPlanner periodic(gait_params);
  const AslipPeriodicGait gait = periodic.Solve(1);
  ASSERT_TRUE(gait.success());
  AslipTransitionParams tp;
  tp.bounds = gait_params;
  const AslipTransitionPlanner transition_planner(tp);
  AslipTransitionData data;
  data.initial_state = AslipTransitionPlanner::StandingState(gait_params.aslip, 0.9);
  data.final_state = gait.collocation.phases[0].states.col(gait_params.nodes_per_domain - 1);
  data.lifting_leg = 1;
  const AslipTransition transition = transition_planner.Solve(data);
  ASSERT_TRUE(transition.success());
  // Lateral QP on the same nodes (the DSP's last node is the SSP's first).
  const double W = 0.25, m = gait_params.aslip.mass;
  const int N = gait_params.nodes_per_domain;
  FootedHlipTransitionData lat = LateralDataOnTransitionNodes(transition, gait_params.aslip, data, N, W);
  const HybridLinearInvertedPendulum hlip({.z0 = gait.mean_height, .ssp_duration = 0.4, .dsp_duration = 0.1});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(W);
  lat.final_state = Eigen::Vector2d(W / 2 + pre(0), pre(1));
  const FootedHlipTransitionPlan lateral = FootedHlipTransitionPlanner().Solve(lat);
  ASSERT_TRUE(lateral.success()) << lateral.message;

  WalkingPlan plan;
  plan.AppendTransition(transition_planner, transition, data, 0.0, lat, lateral, m, gait_params.step_length);
  plan.AppendPeriodicSteps(periodic, gait, 3, WalkingDomain::kLeftStance, 0.0, W, /*begin_with_double_support=*/true);
  ASSERT_EQ(plan.segments().size(), 2u + 1u + 2u * 2u);
  EXPECT_EQ(plan.segments()[2].domain, WalkingDomain::kDoubleSupport);
  // Standing start at rest between the feet; continuous everywhere after.
  const WalkingReference start = plan.Sample(0.0);
  EXPECT_LT(start.com_velocity.norm(), 1e-9);
  EXPECT_NEAR(start.com_position(1), 0.0, 1e-9);
  EXPECT_NEAR(start.normal_force(0), 0.5 * m * 9.81, 1e-6);
  for (size_t i = 0; i + 1 < plan.segments().size(); ++i) {
    const double t = plan.segments()[i].start_time + plan.segments()[i].duration;
    const WalkingReference a = plan.Sample(t - 1e-9), b = plan.Sample(t + 1e-9);
    EXPECT_LT((a.com_position - b.com_position).norm(), 1e-6) << "boundary " << i;
    EXPECT_LT((a.com_velocity - b.com_velocity).norm(), 1e-6) << "boundary " << i;
    EXPECT_LT((a.normal_force - b.normal_force).norm(), 1e-3 * m) << "boundary " << i;
  }
  // The lateral reference follows the footed H-LIP nodes exactly.
  for (int j = 0; j < 2 * N - 1; j += 5) {
    EXPECT_NEAR(plan.Sample(lat.node_times(j)).com_position(1), lateral.states(0, j), 1e-9) << "node " << j;
  }
  // The right foot lands one step ahead at the end of the transition.
  EXPECT_NEAR(plan.Sample(plan.segments()[1].start_time + 0.1).right_foothold(0), gait_params.step_length, 1e-12);
  // The walking diagram's lateral model (normal_force_pivots, each interval on its own aSLIP height, node_heights set
  // by LateralDataOnTransitionNodes): the sampled reference meets every node, and the integrated model between them.
  ASSERT_EQ(lat.node_heights.size(), 2 * N - 1);
  EXPECT_NEAR(lat.node_heights(0), 0.9, 1e-9);  // standing at 0.9 m
  FootedHlipTransitionParams pivots;
  pivots.normal_force_pivots = true;
  const FootedHlipTransitionPlan lateral_pivots = FootedHlipTransitionPlanner(pivots).Solve(lat);
  ASSERT_TRUE(lateral_pivots.success()) << lateral_pivots.message;
  WalkingPlan plan_pivots;
  plan_pivots.AppendTransition(transition_planner, transition, data, 0.0, lat, lateral_pivots, m,
                               gait_params.step_length);
  double worst = 0.0, worst_mid = 0.0;
  for (int j = 0; j < 2 * N - 1; ++j)
    worst =
        std::max(worst, std::abs(plan_pivots.Sample(lat.node_times(j)).com_position(1) - lateral_pivots.states(0, j)));
  EXPECT_LT(worst, 1e-9);
  // Between the nodes: RK4 (200 sub-steps) of m z_k ÿ = F_L (y − y_L) + F_R (y − y_R) + u_L + u_R from node k to the
  // interval's midpoint, z_k and the forces the interval means, against the sampled reference there.
  for (int k = 0; k + 1 < 2 * N - 1; ++k) {
    const double FL = 0.5 * (lat.left_normal_force(k) + lat.left_normal_force(k + 1));
    const double FR = 0.5 * (lat.right_normal_force(k) + lat.right_normal_force(k + 1));
    const double mz = m * 0.5 * (lat.node_heights(k) + lat.node_heights(k + 1));
    const double u = lateral_pivots.left_torque(k) + lateral_pivots.right_torque(k);
    auto f = [&](const Eigen::Vector2d& q) {
      return Eigen::Vector2d(q(1), (FL * (q(0) - lat.left_foot_y) + FR * (q(0) - lat.right_foot_y) + u) / mz);
    };
    Eigen::Vector2d q = lateral_pivots.states.col(k);
    const double h = 0.5 * (lat.node_times(k + 1) - lat.node_times(k)) / 200;
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector2d k1 = f(q), k2 = f(q + 0.5 * h * k1), k3 = f(q + 0.5 * h * k2), k4 = f(q + h * k3);
      q += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
    const WalkingReference mid = plan_pivots.Sample(0.5 * (lat.node_times(k) + lat.node_times(k + 1)));
    worst_mid = std::max({worst_mid, std::abs(mid.com_position(1) - q(0)), std::abs(mid.com_velocity(1) - q(1))});
  }
  EXPECT_LT(worst_mid, 1e-9);
}

// A control tick meant to fall on a segment boundary belongs to the segment that starts there, whichever side of the
// boundary's floating-point value the tick lands on. The simulator's ticks are k Δt (framework/simulator.cc, offset
// 0); the plan's boundaries are sums of durations. Gait (0.41 s, 0.12 s): the 1 kHz ticks on boundaries differ from
// them by up to a few 1e-16 s, some below and some above.
TEST(WalkingPlan, ATickOnASegmentBoundaryBelongsToTheSegmentThatStartsThere) {
  AslipPeriodicGaitParams params;
  params.ssp_duration = 0.41;
  params.dsp_duration = 0.12;
  const AslipPeriodicGaitPlanner planner(params);
  const AslipPeriodicGait gait = planner.Solve(2);
  ASSERT_TRUE(gait.success());
  WalkingPlan plan;
  plan.AppendPeriodicSteps(planner, gait, 8, WalkingDomain::kLeftStance, 0.0, 0.25);
  int below = 0;
  for (size_t i = 1; i < plan.segments().size(); ++i) {
    const double b = plan.segments()[i].start_time;
    const double tick = static_cast<double>(std::lround(b / 1e-3)) * 1e-3;
    ASSERT_LT(std::abs(tick - b), 1e-12) << "segment " << i;
    if (tick < b) ++below;
    EXPECT_EQ(plan.SegmentIndexAt(tick), i) << "segment " << i << ", tick - start " << tick - b;
    EXPECT_EQ(plan.SegmentIndexAt(std::nextafter(b, 0.0)), i) << "segment " << i;
    EXPECT_EQ(plan.SegmentIndexAt(std::nextafter(b, 1e9)), i) << "segment " << i;
    EXPECT_EQ(plan.Sample(tick).domain, plan.segments()[i].domain) << "segment " << i;
    EXPECT_EQ(plan.SegmentIndexAt(b - 1e-9), i - 1) << "segment " << i;  // a nanosecond before: still the previous one
  }
  EXPECT_EQ(plan.SegmentIndexAt(-1.0), 0u);
  EXPECT_EQ(plan.SegmentIndexAt(plan.end_time() + 1.0), plan.segments().size() - 1);
  EXPECT_GT(below, 0) << "no tick fell below its boundary: the test does not exercise the tie";
  RecordProperty("ticks_below_their_boundary", below);
}

TEST(WalkingPlan, RejectsBadArguments) {
  const AslipPeriodicGaitPlanner planner;
  AslipPeriodicGait unsolved;
  WalkingPlan plan;
  EXPECT_THROW(plan.AppendPeriodicSteps(planner, unsolved, 2, WalkingDomain::kLeftStance, 0.0, 0.25),
               std::invalid_argument);
  EXPECT_THROW(plan.Sample(0.0), std::logic_error);
  EXPECT_THROW(WalkingTrajectorySource("empty", WalkingPlan()), std::exception);
}

}  // namespace
}  // namespace rome
