// VerticalComMpcSystem in closed loop with a double-integrator plant p̈ = u (the COM height), re-solved at
// 1 kHz with the time to impact counting down: the plant reaches [p_comf^{z,d}, u_des] at the predicted impact time.
#include "systems/planners/vertical_com_mpc_system.h"

#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"

namespace rome {
namespace {

// p̈ = a, where a is the third entry of the input [p_d, ṗ_d, p̈_d] (acceleration feed-forward only, as in the paper).
class DoubleIntegrator final : public LeafSystem {
 public:
  DoubleIntegrator(double p0, double v0) : LeafSystem("plant") {
    DeclareInputPort("command", 3);
    DeclareContinuousState(Eigen::Vector2d(p0, v0));
    DeclareOutputPort(
        "state", 2, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = c.continuous_state()[1];
    (*xdot)[1] = EvalInput(c, 0)[2];
  }
};

struct ClosedLoopResult {
  Eigen::Vector2d final_state;
  double failures;
  double min_acceleration;
  double relaxations;
};

ClosedLoopResult Simulate(double p0, double v0, double pf, double vf, double T_impact,
                          VerticalComMpcSystemParams params) {
  DiagramBuilder builder;
  builder.AddSystem(std::make_unique<DoubleIntegrator>(p0, v0));
  auto* mpc = builder.AddSystem(std::make_unique<VerticalComMpcSystem>("mpc", params));
  builder.AddSystem(std::make_unique<TrajectorySource>("target", 3, [=](double t, Eigen::Ref<Eigen::VectorXd> y) {
    y << pf, vf, T_impact - t;  // the predicted time to impact counts down
  }));
  builder.Connect("plant", "state", "mpc", "com_vertical_state");
  builder.Connect("target", "y", "mpc", "target");
  builder.Connect("mpc", "com_height_desired", "plant", "command");
  auto diagram = builder.Build();
  SimulatorConfig config;
  config.relative_tolerance = 1e-11;
  config.absolute_tolerance = 1e-12;
  Simulator sim(*diagram, config);
  double min_a = INFINITY;
  const LeafContext& mpc_context = diagram->GetSubsystemContext(*mpc, sim.get_context());
  sim.set_monitor([&](const Context&) {
    min_a = std::min(min_a, mpc->EvalOutput(mpc_context, "com_height_desired")[2]);
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(T_impact);
  EXPECT_TRUE(status.ok()) << status.ToString();
  const auto& plant_context = diagram->GetSubsystemContext(diagram->GetLeafByPath("plant"), sim.get_context());
  return {plant_context.continuous_state(), mpc->EvalOutput(mpc_context, "qp_failures")[0], min_a,
          mpc->EvalOutput(mpc_context, "terminal_relaxations")[0]};
}

TEST(VerticalComMpcSystem, ClosedLoopReachesTheTerminalStateAtThePredictedImpactTime) {
  VerticalComMpcSystemParams params;
  params.mpc.horizon_steps = 20;
  params.mpc.min_horizon_s = 1e-3;  // track the countdown to the last sample
  params.control_period_s = 1e-3;
  // Smooth case (contact constraint inactive): the terminal state is met to integration accuracy.
  // Active case: the plan ends in a free-fall arc (u = −g), where the terminal state is on the boundary of the
  // reachable set; re-planning with the 1 ms zero-order hold drifts just outside it (by ~3e-4 m/s), the
  // equality QP becomes infeasible and the relaxed terminal cost steers to the closest reachable state.
  struct Case {
    double p0, v0, pf, vf, T, p_tolerance, v_tolerance;
    bool expect_relaxations;
  };
  for (const Case& c :
       {Case{0.82, -0.05, 0.80, 0.25, 0.35, 1e-8, 1e-8, false}, Case{0.80, 0.5, 0.735, -1.5, 0.3, 1e-6, 1e-3, true}}) {
    const ClosedLoopResult run = Simulate(c.p0, c.v0, c.pf, c.vf, c.T, params);
    std::printf(
        "closed loop to T = %.3f s: terminal error p %.3e m, v %.3e m/s, failures %g, terminal relaxations %g, min "
        "accel %.4f\n",
        c.T, run.final_state[0] - c.pf, run.final_state[1] - c.vf, run.failures, run.relaxations, run.min_acceleration);
    EXPECT_NEAR(run.final_state[0], c.pf, c.p_tolerance);
    EXPECT_NEAR(run.final_state[1], c.vf, c.v_tolerance);
    EXPECT_EQ(run.relaxations > 0, c.expect_relaxations);
    EXPECT_EQ(run.failures, 0.0);
    EXPECT_GE(run.min_acceleration, -9.81 - 1e-9);  // contact constraint holds along the executed plan
  }
}

TEST(VerticalComMpcSystem, QpFailureKeepsThePreviousPlanAndCounts) {
  VerticalComMpcSystemParams params;
  params.mpc.relax_terminal_on_infeasible = false;
  VerticalComMpcSystem system("mpc", params);
  auto context = system.CreateDefaultLeafContext();
  system.FixInputPort(*context, 0, Eigen::Vector2d(0.80, 0.0));
  system.FixInputPort(*context, 1, Eigen::Vector3d(0.80, 0.2, 0.3));
  const auto& update = system.periodic_events().at(0).update;
  Eigen::VectorXd next = context->discrete_state();
  ASSERT_TRUE(update(*context, &next).ok());
  context->get_mutable_discrete_state() = next;
  const Eigen::VectorXd good = next;
  // Desired output at t = 0.1 from the plan started at 0.
  context->SetTime(0.1);
  const Eigen::Vector3d before = system.EvalOutput(*context, "com_height_desired");
  // Now an infeasible target, with the relaxation switched off (ṗ must fall by 5 m/s in 0.3 s).
  system.FixInputPort(*context, 0, Eigen::Vector2d(0.80, 2.0));
  system.FixInputPort(*context, 1, Eigen::Vector3d(0.80, -3.0, 0.3));
  next = context->discrete_state();
  ASSERT_TRUE(update(*context, &next).ok());
  context->get_mutable_discrete_state() = next;
  EXPECT_EQ(system.EvalOutput(*context, "qp_failures")[0], 1.0);
  EXPECT_EQ(system.EvalOutput(*context, "qp_status")[0], static_cast<double>(QpStatus::kInfeasible));
  EXPECT_EQ(next.tail(system.horizon_steps()), good.tail(system.horizon_steps()));
  EXPECT_EQ(Eigen::Vector3d(system.EvalOutput(*context, "com_height_desired")),
            before);  // the old plan, continued in time
}

TEST(VerticalComMpcSystem, HoldsThePlanWhenTheImpactIsNear) {
  VerticalComMpcSystemParams params;
  params.hold_plan_below_horizon_s = 0.05;
  VerticalComMpcSystem system("mpc", params);
  auto context = system.CreateDefaultLeafContext();
  const auto& update = system.periodic_events().at(0).update;
  // Far from the impact: solved from the measured state.
  system.FixInputPort(*context, 0, Eigen::Vector2d(0.80, 0.1));
  system.FixInputPort(*context, 1, Eigen::Vector3d(0.80, -0.4, 0.3));
  Eigen::VectorXd next = context->discrete_state();
  ASSERT_TRUE(update(*context, &next).ok());
  context->get_mutable_discrete_state() = next;
  const Eigen::VectorXd plan = next;
  EXPECT_EQ(plan[VerticalComMpcSystem::kSolves], 1.0);
  // T̂ = 0.04 s < 0.05 s: no re-solve even though the measured state moved; the plan continues in time, so the
  // output at t is the plan's state and acceleration at t (a piecewise-constant-acceleration double integrator).
  context->SetTime(0.26);
  system.FixInputPort(*context, 0, Eigen::Vector2d(0.79, -0.2));
  system.FixInputPort(*context, 1, Eigen::Vector3d(0.80, -0.4, 0.04));
  next = context->discrete_state();
  ASSERT_TRUE(update(*context, &next).ok());
  EXPECT_EQ(next, plan);
  context->get_mutable_discrete_state() = next;
  const Eigen::Vector3d held = system.EvalOutput(*context, "com_height_desired");
  const Eigen::Vector3d expected = VerticalComMpc::EvaluatePlan(0.80, 0.1, plan.tail(system.horizon_steps()),
                                                                plan[VerticalComMpcSystem::kPlanDt], 0.26);
  EXPECT_NEAR((held - expected).norm(), 0.0, 1e-15);
  // The held plan ends at the planned terminal state (0.80 m, −0.4 m/s) at its horizon 0.3 s (equality QP).
  const Eigen::Vector3d end = VerticalComMpc::EvaluatePlan(0.80, 0.1, plan.tail(system.horizon_steps()),
                                                           plan[VerticalComMpcSystem::kPlanDt], 0.3);
  EXPECT_NEAR(end[0], 0.80, 1e-9);
  EXPECT_NEAR(end[1], -0.4, 1e-9);
  VerticalComMpcSystemParams bad;
  bad.hold_plan_below_horizon_s = -1;
  EXPECT_THROW(VerticalComMpcSystem("mpc", bad), std::exception);
}

}  // namespace
}  // namespace rome
