#pragma once
// Shared by the closed-loop stepping-stones tests: runs the example's diagram and checks the paper's claims for
// periodic footholds (no fall, periodic orbit: post-impact L_y of the last steps within 1 %, Sec. VI-B; L+ near
// the planner's L_des, Eq. (17)-(18); touchdowns within 2 cm of the stone centres; speed in 0.4-1.6 m/s).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"

namespace rome::test {

struct WalkResult {
  SimulatorStatus status;
  std::vector<StepRecord> steps;
  double mean_speed_mps = 0;
  double qp_failures = 0;
};

inline WalkResult Walk(const Terrain& terrain, int steps, SteppingStonesDiagramParams params = {}) {
  params.supervisor.max_steps = steps;
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  sim.Initialize();
  const LeafContext& plant_ctx = d.diagram->GetSubsystemContext(*d.plant, sim.get_context());
  const double x0 = d.plant->EvalOutput(plant_ctx, "com")[0];
  WalkResult r;
  r.status = sim.AdvanceTo(3.0 * steps);
  r.steps = d.supervisor->steps(d.diagram->GetSubsystemContext(*d.supervisor, sim.get_context()));
  r.mean_speed_mps = (d.plant->EvalOutput(plant_ctx, "com")[0] - x0) / sim.get_context().time();
  r.qp_failures = d.controller->EvalOutput(d.diagram->GetSubsystemContext(*d.controller, sim.get_context()), "qp_failures")[0];
  return r;
}

/// Speed of the converged gait: Σ l / Σ T over the last `n` steps [m/s].
inline double LastStepsSpeed(const WalkResult& r, int n) {
  double length = 0, duration = 0;
  for (int k = static_cast<int>(r.steps.size()) - n; k < static_cast<int>(r.steps.size()); ++k) {
    length += r.steps[k].step_length_m;
    duration += r.steps[k].duration_s;
  }
  return length / duration;
}

inline void ExpectPeriodicWalk(const WalkResult& r, int steps, const std::string& what) {
  ASSERT_EQ(r.status.reason, SimulatorStatus::Reason::kReachedTermination) << what << ": " << r.status.ToString();
  EXPECT_NE(r.status.message.find("completed"), std::string::npos) << what << ": " << r.status.message;
  ASSERT_EQ(static_cast<int>(r.steps.size()), steps) << what;
  for (size_t k = 0; k < r.steps.size(); ++k) {
    EXPECT_EQ(r.steps[k].stone, r.steps[k].planned_stone) << what << ", step " << k;
    EXPECT_LT(r.steps[k].foothold_error_m, 0.02) << what << ", step " << k;
  }
  // Periodic orbit: the post-impact momentum of the last steps repeats to within 1 % ...
  const int n = static_cast<int>(r.steps.size());
  for (int k = n - 3; k < n; ++k) {
    const double change = std::abs(r.steps[k].post_impact_momentum - r.steps[k - 1].post_impact_momentum) / r.steps[k - 1].post_impact_momentum;
    EXPECT_LT(change, 0.01) << what << ", step " << k << ": L+ " << r.steps[k - 1].post_impact_momentum << " -> " << r.steps[k].post_impact_momentum;
  }
  // ... and sits on the planner's target: Eq. (17)-(18) drive L+ to L_des.
  const StepRecord& last = r.steps.back();
  EXPECT_NEAR(last.post_impact_momentum, last.L_des, 0.03 * last.L_des) << what;
  EXPECT_GT(r.mean_speed_mps, 0.4) << what;
  EXPECT_LT(r.mean_speed_mps, 1.6) << what;
  EXPECT_EQ(r.qp_failures, 0) << what;
}

}  // namespace rome::test
