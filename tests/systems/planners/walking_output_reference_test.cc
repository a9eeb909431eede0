// WalkingOutputReference: the swing-foot reference against its boundary conditions (spec §5.1 [R]) — at the planned
// lift-off the ankle is at its previous foothold at rest on the ground, at mid-SSP it is at the apex height with zero
// vertical speed, at T_SSP it is at the new foothold on the ground descending at the touchdown speed, and after T_SSP
// it keeps descending at that speed; velocities and accelerations equal central finite differences of the position;
// the COM rows pass the input through, the pelvis rows are 0. The swing foot's toe-down pitch (ours) is level at
// lift-off and touchdown, its rate and acceleration equal central finite differences of it, and the toe corner of a
// 0.18 m sole (ankle 0.08 m above it) stays above the ground through the swing: the pitch's geometric purpose.
#include "systems/planners/walking_output_reference.h"
#include "tests/common/source_path.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

namespace rome {
namespace {

// Three periodic steps of the planner's default gait from the left stance, or an empty plan if its NLP fails.
WalkingPlan ThreePeriodicSteps() {
  const AslipPeriodicGaitPlanner planner;
  const PlanCache cache(rome::test::TestPlanCacheDir("rome_walking_output_reference_test_plans"));
  const AslipPeriodicGait gait = planner.Solve(2, &cache);
  WalkingPlan plan;
  if (gait.success()) plan.AppendPeriodicSteps(planner, gait, 3, WalkingDomain::kLeftStance, 0.0, 0.25);
  return plan;
}

TEST(WalkingOutputReference, SwingFootMeetsItsBoundaryConditionsAndIsSmooth) {
  const WalkingPlan plan = ThreePeriodicSteps();
  ASSERT_GE(plan.segments().size(), 3u) << "the gait's NLP failed";
  SwingFootTrajectoryParams params;
  params.ankle_height_m = 0.08;
  const WalkingOutputReference ref("outputs", plan, params);
  // Segment 2 is the second SSP (right stance): the left foot swings.
  const WalkingPlanSegment& ssp = plan.segments().at(2);
  ASSERT_EQ(ssp.domain, WalkingDomain::kRightStance);
  const Eigen::Vector2d start = plan.segments().at(1).left_foothold, end = ssp.left_foothold;
  ASSERT_GT((end - start).norm(), 0.5);  // one stride
  Eigen::Vector3d p, v, a, pp, vp, ap, pm, vm, am;
  const double t0 = ssp.start_time, T = ssp.duration;
  ref.SwingFoot(0, t0 + 1e-12, p, v, a);
  EXPECT_LT((p.head<2>() - start).norm(), 1e-9);
  EXPECT_NEAR(p.z(), 0.08, 1e-9);
  EXPECT_LT(v.norm(), 1e-9);
  // The swing starts with the quintic's lift-off acceleration h''(0) > 0, also at the double just below the planned
  // lift-off (a control tick meant to sit on it; WalkingPlan::kSegmentBoundaryTolerance_s): a tick there that held
  // the foot on its foothold started the swing one tick (1 ms) late and moved the touchdown by 4 ms.
  const double lift_acceleration = a.z();
  EXPECT_GT(lift_acceleration, 1.0);
  ref.SwingFoot(0, std::nextafter(t0, 0.0), pm, vm, am);
  EXPECT_NEAR(am.z(), lift_acceleration, 1e-6 * lift_acceleration);
  ref.SwingFoot(0, t0 + 0.5 * T, p, v, a);
  EXPECT_NEAR(p.z(), 0.08 + params.apex_height_m, 1e-9);
  EXPECT_NEAR(v.z(), 0.0, 1e-9);
  ref.SwingFoot(0, t0 + T - 1e-12, p, v, a);
  EXPECT_LT((p.head<2>() - end).norm(), 1e-9);
  EXPECT_NEAR(p.z(), 0.08, 1e-9);
  EXPECT_NEAR(v.z(), -params.touchdown_velocity_mps, 1e-9);
  EXPECT_LT(v.head<2>().norm(), 1e-9);
  ref.SwingFoot(0, t0 + T + 0.02, p, v, a);  // late touchdown
  EXPECT_NEAR(p.z(), 0.08 - 0.02 * params.touchdown_velocity_mps, 1e-9);
  const double h = 1e-5;
  for (double s : {0.1, 0.3, 0.6, 0.9}) {
    const double t = t0 + s * T;
    ref.SwingFoot(0, t, p, v, a);
    ref.SwingFoot(0, t + h, pp, vp, ap);
    ref.SwingFoot(0, t - h, pm, vm, am);
    EXPECT_LT(((pp - pm) / (2 * h) - v).norm(), 1e-6) << "s = " << s;
    EXPECT_LT(((vp - vm) / (2 * h) - a).norm(), 1e-4) << "s = " << s;
  }
  // The block: COM rows pass through, pelvis rows 0, left-foot rows = SwingFoot.
  auto context = ref.CreateDefaultLeafContext();
  Eigen::VectorXd com(9);
  com << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  context->FixInputPort(0, com);
  context->SetTime(t0 + 0.3 * T);
  const Eigen::VectorXd& d = ref.EvalOutput(*context, "desired");
  const int n = WalkingOutputReference::kNumOutputs;
  EXPECT_EQ(d.head<3>(), com.head<3>());
  EXPECT_EQ(d.segment<3>(n), com.segment<3>(3));
  EXPECT_EQ(d.segment<3>(2 * n), com.tail<3>());
  EXPECT_EQ(d.segment<3>(3).norm(), 0.0);
  ref.SwingFoot(0, t0 + 0.3 * T, p, v, a);
  EXPECT_EQ(d.segment<3>(6), p);
  EXPECT_EQ(d.segment<3>(n + 6), v);
}

TEST(WalkingOutputReference, SwingFootPitchIsLevelAtTheEndsSmoothAndKeepsTheToeAboveTheGround) {
  const WalkingPlan plan = ThreePeriodicSteps();
  ASSERT_GE(plan.segments().size(), 3u) << "the gait's NLP failed";
  SwingFootTrajectoryParams params;
  params.ankle_height_m = 0.08;
  ASSERT_GT(params.pitch_max_rad, 0.0);  // on by default
  const WalkingOutputReference ref("outputs", plan, params);
  const WalkingPlanSegment& ssp = plan.segments().at(2);  // right stance: the left foot swings
  ASSERT_EQ(ssp.domain, WalkingDomain::kRightStance);
  const double t0 = ssp.start_time, T = ssp.duration;
  double th = 0, thd = 0, thdd = 0;
  ref.SwingFootPitch(0, t0 + 1e-12, &th, &thd, &thdd);
  EXPECT_NEAR(th, 0.0, 1e-9);
  EXPECT_NEAR(thd, 0.0, 1e-9);
  ref.SwingFootPitch(0, t0 + 0.5 * T, &th, &thd, &thdd);
  EXPECT_NEAR(th, params.pitch_max_rad, 1e-9);  // at the apex
  ref.SwingFootPitch(0, t0 + T - 1e-12, &th, &thd, &thdd);
  EXPECT_NEAR(th, 0.0, 1e-9);
  ref.SwingFootPitch(1, t0 + 0.5 * T, &th, &thd, &thdd);  // the stance foot stays flat
  EXPECT_EQ(th, 0.0);
  // The toe corner (0.18 m ahead of the ankle, 0.08 m below it in the foot frame) above the ground over the swing.
  const double toe = 0.18, ankle = params.ankle_height_m;
  Eigen::Vector3d p, v, a;
  double lowest_toe = 1.0;
  for (int k = 1; k < 400; ++k) {
    const double t = t0 + k * T / 400;
    ref.SwingFoot(0, t, p, v, a);
    ref.SwingFootPitch(0, t, &th, &thd, &thdd);
    lowest_toe = std::min(lowest_toe, p.z() - toe * std::sin(th) - ankle * std::cos(th));
  }
  EXPECT_GT(lowest_toe, 0.0);
  const double h = 1e-5;
  for (double s : {0.1, 0.3, 0.6, 0.9}) {
    const double t = t0 + s * T;
    double thp = 0, thdp = 0, thddp = 0, thm = 0, thdm = 0, thddm = 0;
    ref.SwingFootPitch(0, t, &th, &thd, &thdd);
    ref.SwingFootPitch(0, t + h, &thp, &thdp, &thddp);
    ref.SwingFootPitch(0, t - h, &thm, &thdm, &thddm);
    EXPECT_NEAR((thp - thm) / (2 * h), thd, 1e-5) << "s = " << s;
    EXPECT_NEAR((thdp - thdm) / (2 * h), thdd, 1e-3) << "s = " << s;
  }
  // The block's left-foot orientation rows carry the rotation vector (0, θ, 0) and its derivatives.
  auto context = ref.CreateDefaultLeafContext();
  context->FixInputPort(0, Eigen::VectorXd::Zero(9));
  context->SetTime(t0 + 0.3 * T);
  const Eigen::VectorXd& d = ref.EvalOutput(*context, "desired");
  ref.SwingFootPitch(0, t0 + 0.3 * T, &th, &thd, &thdd);
  const int n = WalkingOutputReference::kNumOutputs;
  EXPECT_EQ(d.segment<3>(9), Eigen::Vector3d(0, th, 0));
  EXPECT_EQ(d.segment<3>(n + 9), Eigen::Vector3d(0, thd, 0));
  EXPECT_EQ(d.segment<3>(2 * n + 9), Eigen::Vector3d(0, thdd, 0));
  EXPECT_GT(th, 0.1);
}

}  // namespace
}  // namespace rome
