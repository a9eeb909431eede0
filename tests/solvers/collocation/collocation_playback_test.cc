// A collocated trajectory played back through the framework: TrajectorySource (the collocated input) drives a
// double-integrator LeafSystem integrated by the CVODE Simulator; the simulated state stays within the
// trapezoid rule's O(h²) error of the collocated cubic-Hermite state trajectory.
#include <gtest/gtest.h>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "solvers/collocation/direct_collocation.h"

namespace rome {
namespace {

struct DoubleIntegratorDynamics {
  template <class T>
  void operator()(const Eigen::Matrix<T, -1, 1>& x, const Eigen::Matrix<T, -1, 1>& u,
                  Eigen::Matrix<T, -1, 1>& xdot) const {
    xdot.resize(2);
    xdot << x(1), u(0);
  }
};

// ẍ = u as a framework block: input u (1), output state (2).
class DoubleIntegratorPlant final : public LeafSystem {
 public:
  DoubleIntegratorPlant() : LeafSystem("plant") {
    DeclareInputPort("u", 1);
    DeclareContinuousState(2);
    DeclareOutputPort(
        "state", 2, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = c.continuous_state()[1];
    (*xdot)[1] = EvalInput(c, 0)[0];
  }
};

TEST(CollocationPlayback, SimulatorReintegrationStaysNearCollocatedTrajectory) {
  CollocationPhase phase;
  phase.name = "transfer";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = 21;
  phase.dynamics = DoubleIntegratorDynamics();
  phase.min_duration = phase.max_duration = 1.0;
  phase.running_cost = [](const NodeVector&, const NodeVector& u) -> NodeScalar { return u(0) * u(0); };
  DirectCollocation dc("min_energy_double_integrator", {phase});
  dc.SetNodeStateBounds(0, 0, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, 0.0));
  dc.SetNodeStateBounds(0, -1, Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 0.0));
  const CollocationResult r = dc.Solve();
  ASSERT_TRUE(r.success()) << r.nlp.message;
  const PiecewisePolynomial& u = r.phases[0].input_trajectory;
  const PiecewisePolynomial& x_col = r.phases[0].state_trajectory;

  DiagramBuilder builder;
  builder.AddSystem(TrajectorySource::FromFunction("input", 1, u.AsFunction()));
  builder.AddSystem(std::make_unique<DoubleIntegratorPlant>());
  builder.Connect("input", "y", "plant", "u");
  builder.ExportOutput("plant", "state");
  auto diagram = builder.Build();
  SimulatorConfig config;
  config.relative_tolerance = 1e-10;
  config.absolute_tolerance = 1e-12;
  config.max_step_s = 0.01;  // the input is piecewise linear: small steps resolve its kinks
  Simulator sim(*diagram, config);
  double worst = 0;
  for (int i = 1; i <= 100; ++i) {
    const double t = 0.01 * i;
    ASSERT_TRUE(sim.AdvanceTo(t).ok());
    worst = std::max(worst, (diagram->EvalOutput(sim.get_context(), "state") - x_col.Value(t)).cwiseAbs().maxCoeff());
  }
  // Trapezoid truncation error with h = 0.05: stated bound 2 h² = 5e-3 (measured ~2.4e-3).
  EXPECT_LT(worst, 5e-3);
  EXPECT_GT(worst, 1e-5);  // the two really are different integrators
  // And the final state reaches the transfer target within the same bound.
  EXPECT_NEAR(diagram->EvalOutput(sim.get_context(), "state")[0], 1.0, 5e-3);
}

}  // namespace
}  // namespace rome
