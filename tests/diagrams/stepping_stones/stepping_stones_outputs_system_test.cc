// SteppingStonesOutputsSystem: outputs equal the pure-math trajectories with the LIP estimate of p̈^x, the
// phase runs 0 → 1 between the step start and ε l, the cache follows new step parameters, bad input is named.
#include "diagrams/stepping_stones/stepping_stones_outputs_system.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rome {
namespace {

StepOutputParameters Step() {
  StepOutputParameters s;
  s.phi_0 = 0.1;
  s.phi_f = -0.03;
  s.p_com_x0 = -0.2;
  s.p_sw0_x = -0.4;
  s.p_sw0_z = 0.0;
  s.step_length = 0.5;
  s.step_height = 0.2;
  s.impact_fraction = 0.6;
  s.step_start_time = 2.0;
  s.step_duration = 0.4;
  return s;
}

TEST(SteppingStonesOutputsSystem, MatchesThePureMathTrajectories) {
  SteppingStonesOutputsSystem system("outputs");
  auto context = system.CreateDefaultLeafContext();
  const StepOutputParameters step = Step();
  EXPECT_EQ(SteppingStonesOutputsSystem::PackStepParameters(SteppingStonesOutputsSystem::UnpackStepParameters(
                SteppingStonesOutputsSystem::PackStepParameters(step))),
            SteppingStonesOutputsSystem::PackStepParameters(step));
  system.FixTypedInputPort(*context, system.GetInputPortIndex("step_parameters"), step);
  system.FixInputPort(*context, system.GetInputPortIndex("com_height_desired"), Eigen::Vector3d(0.9, 0.1, -0.5));
  const SteppingStonesOutputTrajectories reference({}, {}, step);
  const double z0 = 0.8;
  for (double x : {-0.2, -0.05, 0.1, 0.3}) {
    const double z = z0 + 0.2 / 0.5 * x;
    system.FixInputPort(*context, system.GetInputPortIndex("com_state"), Eigen::Vector4d(x, z, 0.9, 0.36));
    const DesiredOutputs expected = reference.Evaluate(0.0, x, 0.9, 9.81 / z0 * x, Eigen::Vector3d(0.9, 0.1, -0.5));
    EXPECT_NEAR((system.EvalOutput(*context, "y_desired") - expected.y).norm(), 0.0, 1e-14);
    EXPECT_NEAR((system.EvalOutput(*context, "ydot_desired") - expected.ydot).norm(), 0.0, 1e-14);
    EXPECT_NEAR((system.EvalOutput(*context, "yddot_desired") - expected.yddot).norm(), 0.0, 1e-12);
    EXPECT_NEAR(system.EvalOutput(*context, "phase")[0], (x + 0.2) / (0.3 + 0.2), 1e-15);
  }
  // At ε l the swing foot is at the foothold (minus the strike depth); the torso at φ_f.
  EXPECT_NEAR(system.EvalOutput(*context, "y_desired")[2], 0.5, 1e-15);
  EXPECT_NEAR(system.EvalOutput(*context, "y_desired")[3], 0.2 - 0.01, 1e-15);
  EXPECT_NEAR(system.EvalOutput(*context, "y_desired")[0], -0.03, 1e-15);
  // New step parameters rebuild the trajectories.
  StepOutputParameters next = step;
  next.step_length = 0.3;
  next.step_height = 0.0;
  system.FixTypedInputPort(*context, system.GetInputPortIndex("step_parameters"), next);
  system.FixInputPort(*context, system.GetInputPortIndex("com_state"), Eigen::Vector4d(0.18, 0.8, 0.9, 0.0));
  EXPECT_NEAR(system.EvalOutput(*context, "y_desired")[2], 0.3, 1e-15);
  // Bad step parameters are named.
  next.step_length = 0.0;
  system.FixTypedInputPort(*context, system.GetInputPortIndex("step_parameters"), next);
  try {
    system.EvalOutput(*context, "y_desired");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("outputs"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("step_parameters"), std::string::npos) << e.what();
  }
}

TEST(SteppingStonesOutputsSystem, TimeBasedPhase) {
  SteppingStonesOutputsSystemParams params;
  params.phase.type = PhaseType::kTimeBased;
  SteppingStonesOutputsSystem system("outputs", params);
  auto context = system.CreateDefaultLeafContext();
  system.FixTypedInputPort(*context, system.GetInputPortIndex("step_parameters"), Step());
  system.FixInputPort(*context, system.GetInputPortIndex("com_height_desired"), Eigen::Vector3d(0.9, 0.0, 0.0));
  system.FixInputPort(*context, system.GetInputPortIndex("com_state"), Eigen::Vector4d(0.0, 0.8, 0.9, 0.0));
  context->SetTime(2.1);
  EXPECT_NEAR(system.EvalOutput(*context, "phase")[0], 0.25, 1e-14);
  EXPECT_NEAR(system.EvalOutput(*context, "phase")[1], 2.5, 1e-14);
}

}  // namespace
}  // namespace rome
