// StandToWalkParams::change_check with WalkingChangeFeasibilityCheck (walking issue 39 §1, §4): a gait change whose
// direct transition asks more torque than the robot has is planned again (a tighter force bound, then the gait graph),
// and the plan it takes fits the torque limits. The walking example's default change, gait A (0.30 m, 0.40 s, 0.10 s,
// 0.25 m) → B (0.40 m, same timing), NLP seed 1, 10 steps of A and 12 of B (as the example plans them).
// Independent check: the joint torques are computed here by the mass-matrix form of the equations of motion,
// M(q) q̈ + C(q, q̇) q̇ + g(q) − τ_spring = B u + J_sᵀ w (CalcMassMatrix, CalcBiasForces: the composite-rigid-body
// algorithm, where the check uses recursive Newton-Euler inverse dynamics), with the stance sole's wrench w, on the
// plan's kinematic replay with the COM correction the diagram tracks (BuildWalkingDiagram's plan):
//  * without the change check, the direct plan's transition single support needs more than an actuator's limit;
//  * with it, the refusal is reported, and every single support up to the run's end fits every actuator's limit;
//  * a change with no plan within the limits at all (the gait graph gives up) returns the refused plan into gait B,
//    whose torque the same independent inverse dynamics finds beyond a limit, so that the check before simulating
//    refuses it naming the joint (exit 1) instead of the planner failing (exit 3).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <Eigen/LU>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "tests/common/sanitizer_scale.h"
#include "tests/common/source_path.h"
#include "tests/diagrams/walking/plan_torque_peak.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

using test::PeakTorque;
using test::TorquePeak;

TEST(WalkingChangeCheck, AChangeBeyondTheTorqueLimitsIsPlannedAgainWithinThem) {
  std::shared_ptr<const MultibodyModel> model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingGait a{0.30, 0.40, 0.10, 0.25}, b{0.40, 0.40, 0.10, 0.25};
  const WalkingDiagramParams params;
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, params);
  const WalkingRunParams run;

  // Without the check: the direct transition's single support asks more than a joint has.
  WalkingPlanReport direct_report;
  const WalkingPlan direct = BuildGaitChangePlan(a, b, 10, 1, &cache, &direct_report, stand, 12);
  ASSERT_EQ(direct_report.chain.size(), 2u);  // A, B: the direct transition
  const WalkingDiagram d0 = BuildWalkingDiagram(model, direct, params);
  const TorquePeak over = PeakTorque(*model, d0.plan, 0.0, WalkingRunEndTime(d0.plan, run), true);
  std::printf("  direct: the %s needs %.3f of its limit at t = %.3f s\n", over.joint.c_str(), over.limit_fraction,
              over.time_s);
  EXPECT_GT(over.limit_fraction, 1.0);

  // With the check: the refusal is reported and the plan taken fits every limit.
  stand.change_check = WalkingChangeFeasibilityCheck(model, params);
  WalkingPlanReport report;
  const WalkingPlan checked = BuildGaitChangePlan(a, b, 10, 1, &cache, &report, stand, 12);
  ASSERT_FALSE(report.refused_changes.empty());
  EXPECT_NEAR(report.refused_changes.front().from.step_length_m, a.step_length_m, 1e-12);
  EXPECT_NEAR(report.refused_changes.front().to.step_length_m, b.step_length_m, 1e-12);
  EXPECT_NE(report.refused_changes.front().problem.find("N m"), std::string::npos);
  std::printf("  refused: %s; %zu gaits walked from A on\n", report.refused_changes.front().problem.c_str(),
              report.chain.size());
  EXPECT_NEAR(report.chain.front().step_length_m, a.step_length_m, 1e-12);
  EXPECT_NEAR(report.chain.back().step_length_m, b.step_length_m, 1e-12);
  EXPECT_TRUE(report.refused_plan_kept.empty()) << report.refused_plan_kept;  // a chain within the limits was found
  const WalkingDiagram d = BuildWalkingDiagram(model, checked, params);
  const TorquePeak peak = PeakTorque(*model, d.plan, 0.0, WalkingRunEndTime(d.plan, run), false);
  std::printf("  checked: the %s needs %.3f of its limit at t = %.3f s\n", peak.joint.c_str(), peak.limit_fraction,
              peak.time_s);
  EXPECT_LE(peak.limit_fraction, 1.0);
}

// The held-out pair (0.37 m, 0.36 s, 0.14 s, 0.27 m) → (0.43 m, 0.46 s, 0.10 s, 0.27 m) of docs/walking.md, as the
// gait-change scenario plans it: the start gait's direct change into A has no NLP plan (locally infeasible), and the
// gait graph's first chain plans its link into A, which the torque check refuses. With one failure allowed the search
// gives up there (the example's 16 all end so: 12 refused by the knee, 4 without a plan; measured), and the plan kept
// is that refused chain, up to A (the report's refused_plan_kept says so). Before, the planner threw (the example's
// exit 3, "the solver gave up").
TEST(WalkingChangeCheck, AChangeWithNoChainWithinTheLimitsKeepsTheRefusedPlanForTheCheckToRefuse) {
  if (test::kSanitizerBuild) GTEST_SKIP() << "planning only (tens of NLPs); the Release suite runs it";
  std::shared_ptr<const MultibodyModel> model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingGait a{0.37, 0.36, 0.14, 0.27}, b{0.43, 0.46, 0.10, 0.27};
  const WalkingDiagramParams params;
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, params);
  stand.change_check = WalkingChangeFeasibilityCheck(model, params);
  stand.gait_graph.max_failed_transitions = 1;
  WalkingPlanReport report;
  const WalkingPlan plan = BuildGaitChangePlan(a, b, 4, 1, &cache, &report, stand, 4);
  ASSERT_FALSE(report.refused_changes.empty());
  const WalkingChangeRefusal& first = report.refused_changes.front();
  std::printf("  refused: from (%.2f m, %.2f s, %.2f s): %s\n", first.from.step_length_m, first.from.ssp_duration_s,
              first.from.dsp_duration_s, first.problem.c_str());
  EXPECT_NEAR(first.to.step_length_m, a.step_length_m, 1e-12);
  EXPECT_NEAR(first.to.ssp_duration_s, a.ssp_duration_s, 1e-12);
  EXPECT_NE(first.problem.find("knee needs"), std::string::npos);
  EXPECT_NE(report.refused_plan_kept.find("through the gait graph"), std::string::npos) << report.refused_plan_kept;
  const WalkingDiagram d = BuildWalkingDiagram(model, plan, params);
  const TorquePeak peak = PeakTorque(*model, d.plan, 0.0, d.plan.end_time(), false);
  std::printf("  kept: the %s needs %.3f of its limit at t = %.3f s\n", peak.joint.c_str(), peak.limit_fraction,
              peak.time_s);
  EXPECT_GT(peak.limit_fraction, 1.0);
  const WalkingFeasibilityReport check = CheckWalkingPlanFeasibility(*model, d.plan, params);
  std::printf("  check before simulating: %s\n", check.torque_problem.c_str());
  EXPECT_NE(check.torque_problem.find("knee needs"), std::string::npos);
}

}  // namespace
}  // namespace rome
