// WalkingPlan::Sample and the WalkingTrajectorySource's outputs run every control tick of the walking loop: once the
// plan and the block's context exist they allocate no heap memory (global operator new and, outside sanitizer builds,
// glibc's malloc family are counted, tests/common/allocation_counter.h). The plan has both kinds of segment (the
// periodic aSLIP + H-LIP steps) and a COM correction, as the walking diagram runs it.
#include <gtest/gtest.h>

#include <cmath>

#include "systems/planners/walking_plan.h"
#include "systems/planners/walking_trajectory_source.h"
#include "tests/common/allocation_counter.h"

namespace rome {
namespace {

TEST(WalkingPlanAllocation, SampleAndTheSourceOutputsAllocateNothing) {
  const AslipPeriodicGaitPlanner planner;
  const AslipPeriodicGait gait = planner.Solve(2);
  ASSERT_TRUE(gait.success());
  WalkingPlan plan;
  plan.AppendPeriodicSteps(planner, gait, 4, WalkingDomain::kLeftStance, 0.0, 0.25);
  // A smooth correction over the plan (values do not matter here, only that the correction is evaluated).
  Eigen::VectorXd breaks = Eigen::VectorXd::LinSpaced(21, 0.0, plan.end_time());
  Eigen::MatrixXd delta(2, breaks.size()), accel(2, breaks.size());
  for (Eigen::Index k = 0; k < breaks.size(); ++k)
    delta.col(k) << 0.01 * std::sin(breaks[k]), 0.005 * std::cos(breaks[k]), accel.col(k) << 0.0, 0.0;
  plan.SetComCorrection(PiecewisePolynomial::CubicHermite(breaks, delta, Eigen::MatrixXd::Zero(2, breaks.size())),
                        PiecewisePolynomial::FirstOrderHold(breaks, accel));
  ASSERT_TRUE(plan.has_com_correction());

  WalkingTrajectorySource source("walking_reference", plan);
  auto context = source.CreateDefaultLeafContext();
  context->SetTime(0.0);
  source.EvalOutput(*context, "com");  // first evaluation sizes the cache entries
  source.EvalOutput(*context, "footholds");
  source.EvalOutput(*context, "normal_force_reference");
  source.EvalTypedOutput<WalkingDomain>(*context, "domain");

  const int com = source.GetOutputPortIndex("com"), footholds = source.GetOutputPortIndex("footholds");
  const int force = source.GetOutputPortIndex("normal_force_reference"), domain = source.GetOutputPortIndex("domain");
  double sum = 0.0;
  const long allocations = test::CountAllocations([&] {
    for (int k = 0; k < 2000; ++k) {  // 1 kHz over the whole plan, both domains and every segment boundary
      const double t = 1e-3 * k;
      const WalkingReference r = plan.Sample(t);
      sum += r.com_position.sum() + r.normal_force.sum();
      context->SetTime(t);
      sum += source.EvalOutput(*context, com)[0] + source.EvalOutput(*context, footholds)[0] +
             source.EvalOutput(*context, force)[0];
      sum += static_cast<double>(source.EvalTypedOutput<WalkingDomain>(*context, domain));
    }
  });
  EXPECT_TRUE(std::isfinite(sum));
  EXPECT_EQ(allocations, 0) << (kCountsMalloc ? "operator new and malloc" : "operator new") << " calls over 2000 ticks";
}

}  // namespace
}  // namespace rome
