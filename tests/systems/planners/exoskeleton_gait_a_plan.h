#pragma once
// Test helper: three periodic steps of gait A (l = 0.3 m, T_SSP = 0.4 s, T_DSP = 0.1 s, W = 0.25 m; NLP seed 1, COM
// height range 0.84-0.90 m as the walking diagram's defaults) starting with a double support, and the swing-foot
// parameters of the exoskeleton (its sole 0.08 m below the ankle). NLP solutions are cached under the system's
// temporary directory, `cache_name`.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "systems/planners/aslip_periodic_gait_planner.h"
#include "systems/planners/walking_output_reference.h"
#include "systems/planners/walking_plan.h"
#include "tests/common/source_path.h"

namespace rome::test {

inline WalkingPlan ExoskeletonGaitAPlan(const std::string& cache_name) {
  AslipPeriodicGaitParams gp;
  gp.height_min = 0.84;
  gp.height_max = 0.90;
  const AslipPeriodicGaitPlanner planner(gp);
  const PlanCache cache(TestPlanCacheDir(cache_name));
  const AslipPeriodicGait gait = planner.Solve(1, &cache);
  EXPECT_TRUE(gait.success());
  WalkingPlan plan;
  plan.AppendPeriodicSteps(planner, gait, 3, WalkingDomain::kLeftStance, 0.0, 0.25, /*begin_with_double_support=*/true);
  return plan;
}

inline SwingFootTrajectoryParams ExoskeletonSwing() {
  SwingFootTrajectoryParams swing;
  swing.ankle_height_m = 0.08;
  return swing;
}

}  // namespace rome::test
