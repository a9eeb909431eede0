// MomentumRegulationPlannerSystem in closed loop with the LIP walker (SteppingLinearInvertedPendulum): after
// the first impact every step starts on the orbit of energy E* with post-impact momentum L_des (the ROM orbit
// repeats), on flat ground and on stairs, from a perturbed start.
#include "systems/planners/momentum_regulation_planner_system.h"

#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/rom/stepping_linear_inverted_pendulum.h"

namespace rome {
namespace {

struct Case {
  double l, h;
};

TEST(MomentumRegulationPlannerSystem, ClosedLoopLipWalkerRepeatsItsOrbit) {
  for (const Case& step : {Case{0.4, 0.0}, Case{0.5, 0.2}, Case{0.4, -0.1}}) {
    const double z0 = 0.8, eps = 0.6, E_star = 0.4;
    SteppingLinearInvertedPendulumParams lip_params;
    lip_params.lip.z0 = z0;
    lip_params.impact_fraction = eps;
    lip_params.initial_x = -0.25;  // perturbed start: neither the post-impact position nor the energy of the orbit
    lip_params.initial_L = 0.9;
    MomentumRegulationPlannerParams planner_params;
    planner_params.target_orbital_energy = E_star;
    planner_params.impact_fraction = eps;

    DiagramBuilder builder;
    auto* lip = builder.AddSystem(std::make_unique<SteppingLinearInvertedPendulum>("lip", lip_params));
    auto* planner = builder.AddSystem(std::make_unique<MomentumRegulationPlannerSystem>("planner", planner_params));
    builder.AddSystem(std::make_unique<ConstantVectorSource>("step", Eigen::Vector2d(step.l, step.h)));
    builder.AddSystem(std::make_unique<ConstantVectorSource>(
        "pre_impact_height",
        Eigen::VectorXd::Constant(1, LinearInvertedPendulum::ComHeightOnSlope(eps * step.l, z0, step.l, step.h))));
    builder.AddSystem(std::make_unique<Demultiplexer>("split", std::vector<int>{1, 1}));
    builder.Connect("step", "y", "lip", "step");
    builder.Connect("step", "y", "planner", "step");
    builder.Connect("pre_impact_height", "y", "planner", "pre_impact_com_height");
    builder.Connect("lip", "com_state", "planner", "com_state");
    builder.Connect("lip", "state", "split", "u");
    builder.Connect("split", "y1", "planner", "angular_momentum");
    builder.Connect("planner", "u_des", "lip", "impact_vertical_velocity");
    auto diagram = builder.Build();
    SimulatorConfig config;
    config.relative_tolerance = 1e-12;
    config.absolute_tolerance = 1e-13;
    Simulator sim(*diagram, config);

    const LeafContext& lip_context = diagram->GetSubsystemContext(*lip, sim.get_context());
    const LeafContext& planner_context = diagram->GetSubsystemContext(*planner, sim.get_context());
    const double L_des = planner->planner().DesiredPostImpactMomentum(
        step.l, step.h, LinearInvertedPendulum::ComHeightOnSlope(eps * step.l, z0, step.l, step.h));
    EXPECT_NEAR(planner->EvalOutput(planner_context, "L_des")[0], L_des, 1e-14);
    EXPECT_GT(std::abs(lip->lip().OrbitalEnergy(Eigen::Vector2d(-0.25, 0.9)) - E_star), 0.05);

    // After each impact the energy is E* and L⁺ = L_des; the post-impact momentum repeats step after step.
    double previous_post_impact_L = NAN;
    int steps = 0;
    double t = 0;
    while (steps < 8) {
      t += 0.002;
      ASSERT_TRUE(sim.AdvanceTo(t).ok());
      ASSERT_LT(t, 10.0) << "the walker stopped stepping";
      const int taken = static_cast<int>(lip_context.discrete_state()[2]);
      if (taken == steps) continue;
      steps = taken;
      // Flow back to the impact time to read the post-impact state exactly.
      const double t_impact = sim.statistics().events.back().time;
      const Eigen::Vector2d post = lip->lip().Flow(lip_context.continuous_state(), t_impact - t);
      EXPECT_NEAR(post[0], (eps - 1) * step.l, 1e-9);
      EXPECT_NEAR(post[1], L_des, 1e-8) << "step " << steps;
      EXPECT_NEAR(lip->EvalOutput(lip_context, "orbital_energy")[0], E_star, 1e-8);
      if (!std::isnan(previous_post_impact_L)) { EXPECT_NEAR(post[1], previous_post_impact_L, 1e-9); }
      previous_post_impact_L = post[1];
      EXPECT_EQ(planner->EvalOutput(planner_context, "status")[0], 0.0);
    }
    EXPECT_NEAR(lip->EvalOutput(lip_context, "stance_foot")[0], 8 * step.l, 1e-12);
    EXPECT_NEAR(lip->EvalOutput(lip_context, "stance_foot")[1], 8 * step.h, 1e-12);
    // The MPC target output is [p_comf^{z,d}, u_des, T̂].
    const Eigen::VectorXd& target = planner->EvalOutput(planner_context, "vertical_com_target");
    EXPECT_EQ(target[1], planner->EvalOutput(planner_context, "u_des")[0]);
    EXPECT_EQ(target[2], planner->EvalOutput(planner_context, "time_to_impact")[0]);
  }
}

TEST(MomentumRegulationPlannerSystem, BadInputNamesTheSystem) {
  MomentumRegulationPlannerSystem planner("planner");
  auto context = planner.CreateDefaultLeafContext();
  planner.FixInputPort(*context, planner.GetInputPortIndex("com_state"), Eigen::Vector4d(0.0, 0.8, 0.5, 0.0));
  planner.FixInputPort(*context, planner.GetInputPortIndex("angular_momentum"), Eigen::VectorXd::Constant(1, 0.4));
  planner.FixInputPort(*context, planner.GetInputPortIndex("step"), Eigen::Vector2d(-0.4, 0.0));
  planner.FixInputPort(*context, planner.GetInputPortIndex("pre_impact_com_height"), Eigen::VectorXd::Constant(1, 0.8));
  try {
    planner.EvalOutput(*context, "u_des");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("planner"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("step length"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rome
