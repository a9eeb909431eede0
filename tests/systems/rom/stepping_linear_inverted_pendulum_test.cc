// SteppingLinearInvertedPendulum: touchdown times against the closed-form time-to-impact Eq. (14), and the
// reset against the impact map Eq. (17) applied to the closed-form pre-impact state Eq. (13).
#include "systems/rom/stepping_linear_inverted_pendulum.h"

#include <gtest/gtest.h>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"

namespace rome {
namespace {

TEST(SteppingLinearInvertedPendulum, ImpactTimesAndResetsMatchClosedForm) {
  const double l = 0.5, h = 0.1, u = 0.15, eps = 0.6;
  SteppingLinearInvertedPendulumParams params;
  params.lip.z0 = 0.8;
  params.impact_fraction = eps;
  params.initial_x = -0.2;
  params.initial_L = 0.6;
  DiagramBuilder builder;
  auto* lip = builder.AddSystem(std::make_unique<SteppingLinearInvertedPendulum>("lip", params));
  builder.AddSystem(std::make_unique<ConstantVectorSource>("step", Eigen::Vector2d(l, h)));
  builder.AddSystem(std::make_unique<ConstantVectorSource>("u", Eigen::VectorXd::Constant(1, u)));
  builder.Connect("step", "y", "lip", "step");
  builder.Connect("u", "y", "lip", "impact_vertical_velocity");
  auto diagram = builder.Build();
  SimulatorConfig config;
  config.relative_tolerance = 1e-12;
  config.absolute_tolerance = 1e-13;
  Simulator sim(*diagram, config);

  // Closed-form hybrid trajectory: flow to x = ε l (Eq. (13)-(14)), then Eq. (17).
  Eigen::Vector2d s(params.initial_x, params.initial_L);
  double t = 0;
  const LinearInvertedPendulum& model = lip->lip();
  for (int step = 1; step <= 4; ++step) {
    const TimeToImpact T = model.TimeToReach(eps * l, s);
    ASSERT_TRUE(T.ok());
    t += T.time_s;
    const Eigen::Vector2d pre = model.Flow(s, T.time_s);
    s = Eigen::Vector2d(pre[0] - l, pre[1] + l * u - h * pre[1] / model.z0());
    ASSERT_TRUE(sim.AdvanceTo(t + 1e-3).ok());
    ASSERT_EQ(static_cast<int>(sim.statistics().events.size()), step);
    EXPECT_NEAR(sim.statistics().events.back().time, t, 1e-9);
    const Eigen::Vector2d expected = model.Flow(s, 1e-3);
    const LeafContext& c = diagram->GetSubsystemContext(*lip, sim.get_context());
    EXPECT_NEAR((c.continuous_state() - expected).norm(), 0.0, 1e-8) << "step " << step;
    EXPECT_NEAR(c.discrete_state()[0], step * l, 1e-12);
    EXPECT_NEAR(c.discrete_state()[1], step * h, 1e-12);
    EXPECT_EQ(c.discrete_state()[2], step);
    // com_state lies on the virtual slope.
    const Eigen::VectorXd& com = lip->EvalOutput(c, "com_state");
    EXPECT_NEAR(com[1], h / l * com[0] + model.z0(), 1e-14);
    EXPECT_NEAR(com[2] * model.z0(), c.continuous_state()[1], 1e-14);
  }
}

TEST(SteppingLinearInvertedPendulum, RejectsBadStepInput) {
  SteppingLinearInvertedPendulum lip("lip");
  auto context = lip.CreateDefaultLeafContext();
  lip.FixInputPort(*context, 0, Eigen::Vector2d(-0.3, 0.0));
  lip.FixInputPort(*context, 1, Eigen::VectorXd::Zero(1));
  try {
    lip.EvalOutput(*context, "com_state");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("step"), std::string::npos) << e.what();
  }
  SteppingLinearInvertedPendulumParams bad;
  bad.impact_fraction = 1.5;
  EXPECT_THROW(SteppingLinearInvertedPendulum("bad", bad), std::runtime_error);
}

}  // namespace
}  // namespace rome
