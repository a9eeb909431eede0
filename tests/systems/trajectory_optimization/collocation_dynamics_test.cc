// CollocationDynamicsFromSystem: DirectCollocation with its dynamics taken from a LeafSystem, against the closed-form
// minimum-effort transfer of a double integrator; the chained Jacobians against hand-derived ones; errors.
#include "systems/trajectory_optimization/collocation_dynamics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "tests/common/error_of.h"

namespace rome {
namespace {

// ẍ = u as a block: x = (position, velocity), input u.
class DoubleIntegrator final : public LeafSystem {
 public:
  DoubleIntegrator() : LeafSystem("double_integrator") {
    DeclareContinuousState(2);
    DeclareInputPort("u", 1);
  }

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    *xdot = Eigen::Vector2d(c.continuous_state()[1], EvalInput(c, 0)[0]);
  }
};

// θ̈ = −(g/l) sin θ − b θ̇ + k τ, with the parameters as a numeric parameter (taken from the context).
class Pendulum final : public LeafSystem {
 public:
  Pendulum() : LeafSystem("pendulum") {
    DeclareContinuousState(2);
    DeclareInputPort("tau", 1);
    DeclareNumericParameter("g_over_l_b_k", Eigen::Vector3d(9.81, 0.2, 1.0));
  }

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    const Eigen::VectorXd& x = c.continuous_state();
    const Eigen::VectorXd& p = c.numeric_parameter(0);
    *xdot = Eigen::Vector2d(x[1], -p[0] * std::sin(x[0]) - p[1] * x[1] + p[2] * EvalInput(c, 0)[0]);
  }
};

// min ∫₀¹ u² dt, ẍ = u, x(0) = ẋ(0) = 0, x(1) = 1, ẋ(1) = 0. Pontryagin: the costate of ẋ is linear in t, so
// u*(t) = 6 − 12 t, x*(t) = 3t² − 2t³, ẋ*(t) = 6t − 6t², cost 12.
CollocationResult SolveMinimumEffortTransfer(int N, StateInputFunction dynamics) {
  CollocationPhase phase;
  phase.name = "transfer";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = N;
  phase.dynamics = std::move(dynamics);
  phase.min_duration = phase.max_duration = 1.0;
  phase.running_cost = [](const NodeVector&, const NodeVector& u) -> NodeScalar { return u(0) * u(0); };
  DirectCollocation dc("min_effort_transfer", {phase});
  dc.SetNodeStateBounds(0, 0, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, 0.0));
  dc.SetNodeStateBounds(0, -1, Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 0.0));
  return dc.Solve();
}

TEST(CollocationDynamicsFromSystem, MinimumEffortTransferMatchesClosedForm) {
  DoubleIntegrator plant;
  auto context = plant.CreateDefaultLeafContext();
  const int N = 21;
  const CollocationResult r = SolveMinimumEffortTransfer(N, CollocationDynamicsFromSystem(plant, *context, "u"));
  ASSERT_TRUE(r.success()) << r.nlp.message;
  const CollocationPhaseSolution& s = r.phases.at(0);
  double state_error = 0.0, interior_input_error = 0.0;
  for (int k = 0; k < N; ++k) {
    const double t = s.times(k);
    state_error = std::max(
        state_error,
        (s.states.col(k) - Eigen::Vector2d(3 * t * t - 2 * t * t * t, 6 * t - 6 * t * t)).cwiseAbs().maxCoeff());
    if (k > 0 && k < N - 1)
      interior_input_error = std::max(interior_input_error, std::abs(s.inputs(0, k) - (6.0 - 12.0 * t)));
  }
  // Trapezoid rule: O(h²) with h = 1/20; the same bounds as the AutoDiff-dynamics test of DirectCollocation
  // (tests/solvers/collocation/direct_collocation_test.cc): state 4 h², interior input 30 h², cost 60 h².
  const double h = 1.0 / (N - 1);
  EXPECT_LT(state_error, 4.0 * h * h);
  EXPECT_LT(interior_input_error, 30.0 * h * h);
  EXPECT_NEAR(r.nlp.cost, 12.0, 60.0 * h * h);
  EXPECT_LT(r.max_defect, 1e-8);
  std::printf("N = %d: |x − x*|∞ = %.2e, interior |u − u*|∞ = %.2e, cost − 12 = %.2e, %d iterations\n", N, state_error,
              interior_input_error, r.nlp.cost - 12.0, r.nlp.iterations);

  // The same problem with the dynamics written as an AutoDiff function (exact Jacobians) has the same discrete
  // optimum: the finite-difference Jacobians (error ~1e-10) move it by far less than Ipopt's tolerance (1e-8).
  const CollocationResult exact =
      SolveMinimumEffortTransfer(N, [](const NodeVector& x, const NodeVector& u, NodeVector& xdot) {
        xdot.resize(2);
        xdot << x(1), u(0);
      });
  ASSERT_TRUE(exact.success()) << exact.nlp.message;
  EXPECT_LT((exact.phases[0].states - s.states).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((exact.phases[0].inputs - s.inputs).cwiseAbs().maxCoeff(), 1e-6);
}

// The AutoDiff derivatives of the function are ∂f/∂(x, u) (central differences) chained onto the seeds.
TEST(CollocationDynamicsFromSystem, DerivativesAreTheChainedJacobians) {
  Pendulum plant;
  auto context = plant.CreateDefaultLeafContext();
  context->get_mutable_numeric_parameter(0) << 4.0, 0.5, 2.0;  // taken from the context
  const StateInputFunction f = CollocationDynamicsFromSystem(plant, *context, "tau");
  const Eigen::Vector2d x(0.7, -1.3);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 0.4);
  const NodeVector xa = InitializeAutoDiff<NodeScalar>(x, 3, 0), ua = InitializeAutoDiff<NodeScalar>(u, 3, 2);
  NodeVector y;
  f(xa, ua, y);
  EXPECT_NEAR(y[1].value(), -4.0 * std::sin(0.7) - 0.5 * -1.3 + 2.0 * 0.4, 1e-15);
  Eigen::Matrix<double, 2, 3> J;
  J << 0, 1, 0, -4.0 * std::cos(0.7), -0.5, 2.0;
  // Central-difference bound h²/6 · 4 + 4 ε |f| / h with h = ε^(1/3): about 2e-10.
  EXPECT_LT((ExtractJacobian(y, 3) - J).cwiseAbs().maxCoeff(), 1e-9) << ExtractJacobian(y, 3);
  // Values only (seeds of size 0): the same value, no derivatives.
  NodeVector y_value;
  f(InitializeAutoDiff<NodeScalar>(x, 0, 0), InitializeAutoDiff<NodeScalar>(u, 0, 0), y_value);
  EXPECT_EQ(y_value[1].value(), y[1].value());
  EXPECT_EQ(y_value[1].derivatives().size(), 0);
  // Only the state seeded (a reset-map style call): ∂/∂x only.
  NodeVector y_x;
  f(InitializeAutoDiff<NodeScalar>(x), InitializeAutoDiff<NodeScalar>(u, 0, 0), y_x);
  EXPECT_LT((ExtractJacobian(y_x, 2) - J.leftCols(2)).cwiseAbs().maxCoeff(), 1e-9);
}

using test::ErrorOf;

TEST(CollocationDynamicsFromSystem, ErrorsNameTheSystem) {
  Pendulum plant;
  auto context = plant.CreateDefaultLeafContext();
  EXPECT_EQ(ErrorOf([&] { CollocationDynamicsFromSystem(plant, *context, "torque"); }),
            "system 'pendulum' has no input port 'torque' (it has 'tau')");
  const StateInputFunction f = CollocationDynamicsFromSystem(plant, *context, "tau");
  NodeVector y;
  EXPECT_EQ(ErrorOf([&] {
              f(InitializeAutoDiff<NodeScalar>(Eigen::Vector3d::Zero()),
                InitializeAutoDiff<NodeScalar>(Eigen::VectorXd::Zero(1)), y);
            }),
            "CollocationDynamicsFromSystem: system 'pendulum': x has size 3, the system has 2 continuous states");
  DoubleIntegrator other;
  EXPECT_EQ(ErrorOf([&] { CollocationDynamicsFromSystem(other, *context, "u"); }),
            "CollocationDynamicsFromSystem: system 'double_integrator': was given the context of system 'pendulum'");
}

}  // namespace
}  // namespace rome
