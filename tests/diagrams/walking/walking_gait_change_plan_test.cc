// BuildGaitChangePlan beyond one direct transition (walking issue 39), checked on the ROM plan:
// - a change of step width W: the footed H-LIP transition ends on gait B's period-2 orbit, compared with the H-LIP's
//   closed form (spec §2.2: σ2 = λ tanh(λ T_SSP / 2), p = −W / (2 + T_DSP σ2), v = σ2 p at the end of a left stance),
//   and the plan then follows that orbit: the test's own H-LIP flow (DSP ẏ constant, SSP cosh/sinh about the new
//   stance foot) from the transition's end lands on the mirrored pre-impact state one step later;
// - a change the direct transition NLP cannot plan goes through intermediate gaits of the gait graph: each change
//   stays within the graph's reach, and the plan walks the chain's gaits in order (their T_SSP and step lengths).
// NLP seed 1 (tuned on seeds >= 1000).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "tests/common/source_path.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

constexpr double kGravity = 9.81;

StandToWalkParams Stand(const MultibodyModel& model) {
  StandToWalkParams stand;
  stand.sole = SoleOf(model, "left_foot");
  return stand;
}

// Index of the last single support that carries footed H-LIP nodes (the A → B transition's SSP).
size_t LastTransitionSsp(const WalkingPlan& plan) {
  size_t last = plan.segments().size();
  for (size_t i = 0; i < plan.segments().size(); ++i)
    if (plan.segments()[i].domain != WalkingDomain::kDoubleSupport && plan.segments()[i].lateral_nodes.cols() > 0)
      last = i;
  return last;
}

// [y, ẏ] of the plan at t, about the stance foot at stance_y, mirrored in a right stance (+y toward the swing side's
// opposite, as the P2 formula's left stance).
Eigen::Vector2d LateralAbout(const WalkingPlan& plan, double t, double stance_y, bool left_stance) {
  const WalkingReference r = plan.Sample(t);
  const double mirror = left_stance ? 1.0 : -1.0;
  return {mirror * (r.com_position.y() - stance_y), mirror * r.com_velocity.y()};
}

TEST(WalkingGaitChangePlan, AChangeOfStepWidthEndsOnGaitBsPeriodTwoOrbit) {
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  for (const double w_b : {0.22, 0.30}) {  // narrower and wider than A's 0.26 m
    SCOPED_TRACE(w_b);
    const WalkingGait a{.step_length_m = 0.30, .ssp_duration_s = 0.40, .dsp_duration_s = 0.10, .step_width_m = 0.26};
    WalkingGait b = a;
    b.step_width_m = w_b;
    WalkingPlanReport report;
    const WalkingPlan plan = BuildGaitChangePlan(a, b, 6, 1, &cache, &report, Stand(*model), 4);
    ASSERT_EQ(report.chain.size(), 2u);  // the direct transition
    const size_t i = LastTransitionSsp(plan);
    ASSERT_LT(i + 3, plan.segments().size());
    const WalkingPlanSegment& ssp = plan.segments()[i];
    const bool left = ssp.domain == WalkingDomain::kLeftStance;
    const double stance_y = (left ? ssp.left_foothold : ssp.right_foothold).y();
    const double landing_y = (left ? ssp.right_foothold : ssp.left_foothold).y();
    EXPECT_NEAR(std::abs(landing_y - stance_y), w_b, 1e-12);
    EXPECT_EQ(landing_y < stance_y, left);  // the swing foot lands on its own side
    // z0 of B's H-LIP: the time average of the plan's height over B's next step (spec §2.2), by the midpoint rule.
    const WalkingPlanSegment& dsp = plan.segments()[i + 1];
    const WalkingPlanSegment& next_ssp = plan.segments()[i + 2];
    const double t0 = dsp.start_time, T = dsp.duration + next_ssp.duration;
    double z_sum = 0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) z_sum += plan.Sample(t0 + (k + 0.5) * T / n).com_position.z();
    const double z0 = z_sum / n, lambda = std::sqrt(kGravity / z0);
    EXPECT_NEAR(dsp.duration, b.dsp_duration_s, 1e-9);
    EXPECT_NEAR(next_ssp.duration, b.ssp_duration_s, 1e-9);
    const double sigma2 = lambda * std::tanh(lambda * b.ssp_duration_s / 2);
    const double p = -w_b / (2 + b.dsp_duration_s * sigma2), v = sigma2 * p;
    // The transition's end: B's P2 pre-impact state about the stance foot.
    const double t_end = ssp.start_time + ssp.duration;
    const Eigen::Vector2d pre = LateralAbout(plan, t_end - 1e-9, stance_y, left);
    std::printf("  W %.2f -> %.2f m: pre-impact (%.5f m, %.5f m/s), closed form (%.5f m, %.5f m/s), z0 %.4f m\n",
                a.step_width_m, w_b, pre(0), pre(1), p, v, z0);
    EXPECT_NEAR(pre(0), p, 1e-3);
    EXPECT_NEAR(pre(1), v, 5e-3);
    // One step of the test's own H-LIP from there: DSP (ẏ constant), then SSP about the landed foot.
    double y = stance_y + (left ? pre(0) : -pre(0)), yd = left ? pre(1) : -pre(1);
    y += yd * dsp.duration;
    const double ch = std::cosh(lambda * next_ssp.duration), sh = std::sinh(lambda * next_ssp.duration);
    const double rel = y - landing_y;
    const double y_next = landing_y + rel * ch + yd / lambda * sh, yd_next = rel * lambda * sh + yd * ch;
    const Eigen::Vector2d flowed =
        Eigen::Vector2d((left ? -1.0 : 1.0) * (y_next - landing_y), (left ? -1.0 : 1.0) * yd_next);
    // P2: the next pre-impact state about the new stance foot is the mirrored one.
    EXPECT_NEAR(flowed(0), p, 2e-3);
    EXPECT_NEAR(flowed(1), v, 1e-2);
    // And the plan's own next pre-impact state agrees with that flow.
    const Eigen::Vector2d planned_next =
        LateralAbout(plan, next_ssp.start_time + next_ssp.duration - 1e-9, landing_y, !left);
    EXPECT_NEAR(planned_next(0), flowed(0), 2e-3);
    EXPECT_NEAR(planned_next(1), flowed(1), 1e-2);
    // Every later segment keeps the feet W_B apart.
    for (size_t k = i; k < plan.segments().size(); ++k)
      EXPECT_NEAR(std::abs(plan.segments()[k].left_foothold.y() - plan.segments()[k].right_foothold.y()), w_b, 1e-12)
          << "segment " << k;
  }
}

// The two pairs of issue 39 whose direct transition NLP is locally infeasible (NLP seed 1).
TEST(WalkingGaitChangePlan, AChangeWithNoDirectPlanChainsThroughIntermediateGaits) {
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const StandToWalkParams stand = Stand(*model);
  const WalkingGait pairs[2][2] = {{{0.25, 0.38, 0.09, 0.27}, {0.42, 0.42, 0.11, 0.27}},
                                   {{0.22, 0.48, 0.14, 0.21}, {0.38, 0.40, 0.10, 0.21}}};
  for (const auto& pair : pairs) {
    const WalkingGait &a = pair[0], &b = pair[1];
    WalkingPlanReport report;
    StandToWalkParams direct_only = stand;
    direct_only.chain_gait_changes = false;
    EXPECT_THROW(BuildGaitChangePlan(a, b, 6, 1, &cache, nullptr, direct_only, 4), std::runtime_error);
    const WalkingPlan plan = BuildGaitChangePlan(a, b, 6, 1, &cache, &report, stand, 4);
    ASSERT_GT(report.chain.size(), 2u);
    std::printf("  chain of %zu gaits, %d transitions tried, %d failed, %.2f s:", report.chain.size(),
                report.chain_transitions_tried, report.chain_transitions_failed, report.chain_planning_s);
    for (const WalkingGait& g : report.chain)
      std::printf(" (%g, %g, %g, %g)", g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m);
    std::printf("\n");
    EXPECT_GT(report.chain_planning_s, 0.0);
    EXPECT_DOUBLE_EQ(report.chain.front().step_length_m, a.step_length_m);
    EXPECT_DOUBLE_EQ(report.chain.back().step_length_m, b.step_length_m);
    const GaitGraphParams graph;
    for (size_t k = 0; k + 1 < report.chain.size(); ++k) {
      const WalkingGait &g = report.chain[k], &h = report.chain[k + 1];
      EXPECT_LE(std::abs(h.step_length_m - g.step_length_m), graph.reach[0] + 1e-9);
      EXPECT_LE(std::abs(h.ssp_duration_s - g.ssp_duration_s), graph.reach[1] + 1e-9);
      EXPECT_LE(std::abs(h.dsp_duration_s - g.dsp_duration_s), graph.reach[2] + 1e-9);
      EXPECT_LE(std::abs(h.step_width_m - g.step_width_m), graph.reach[3] + 1e-9);
    }
    // The plan walks the chain: after the last transition into each chain gait, its periodic single supports last
    // that gait's T_SSP and advance its step length; B walks last.
    std::vector<size_t> transitions;
    for (size_t i = 0; i < plan.segments().size(); ++i)
      if (plan.segments()[i].domain != WalkingDomain::kDoubleSupport && plan.segments()[i].lateral_nodes.cols() > 0)
        transitions.push_back(i);
    ASSERT_GE(transitions.size(), report.chain.size() - 1);
    const size_t first = transitions.size() - (report.chain.size() - 1);
    for (size_t k = 1; k < report.chain.size(); ++k) {
      const size_t i = transitions[first + k - 1];
      const WalkingPlanSegment& ssp = plan.segments().at(i + 2);  // the gait's first periodic single support
      EXPECT_NEAR(ssp.duration, report.chain[k].ssp_duration_s, 1e-9) << "chain gait " << k;
      const double stride = std::abs(ssp.left_foothold.x() - ssp.right_foothold.x());
      EXPECT_NEAR(stride, report.chain[k].step_length_m, 1e-9) << "chain gait " << k;
      EXPECT_NEAR(std::abs(ssp.left_foothold.y() - ssp.right_foothold.y()), report.chain[k].step_width_m, 1e-12)
          << "chain gait " << k;
    }
  }
}

// A chain whose direct last transition planned the lifting foot unloaded and loaded again in its double support (the
// plant then lifts it early and it lands again): with StandToWalkParams::reload_floor_fraction such a transition has no
// plan. Checked on the plan's own force reference, sampled every 1 ms: in no transition's double support does the
// lifting foot's force fall below 2 % m g and rise above it again.
TEST(WalkingGaitChangePlan, NoTransitionUnloadsTheLiftingFootAndLoadsItAgain) {
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const StandToWalkParams stand = Stand(*model);
  WalkingPlanReport report;
  const WalkingPlan plan =
      BuildGaitChangePlan({0.22, 0.48, 0.14, 0.21}, {0.38, 0.40, 0.10, 0.28}, 6, 1, &cache, &report, stand, 4);
  const double floor = stand.reload_floor_fraction * model->total_mass() * kGravity;
  int transitions = 0;
  for (size_t i = 0; i + 1 < plan.segments().size(); ++i) {
    const WalkingPlanSegment &dsp = plan.segments()[i], &ssp = plan.segments()[i + 1];
    if (dsp.domain != WalkingDomain::kDoubleSupport || ssp.lateral_nodes.cols() == 0) continue;
    ++transitions;
    const int lifting = ssp.domain == WalkingDomain::kLeftStance ? 1 : 0;
    bool unloaded = false, reloaded = false;
    for (double t = dsp.start_time; t < dsp.start_time + dsp.duration - 1e-9; t += 1e-3) {
      const double f = plan.Sample(t).normal_force[lifting];
      reloaded = reloaded || (unloaded && f > floor);
      unloaded = unloaded || f < floor;
    }
    EXPECT_FALSE(reloaded) << "transition ending at " << ssp.start_time + ssp.duration << " s";
  }
  EXPECT_EQ(transitions, 1 + 1 + static_cast<int>(report.chain.size()) - 1);  // standing, start gait -> A, the chain
}

}  // namespace
}  // namespace rome
