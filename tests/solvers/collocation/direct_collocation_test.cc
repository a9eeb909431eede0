#include "solvers/collocation/direct_collocation.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "solvers/nlp/derivative_checker.h"

namespace rome {
namespace {

// ---------------------------------------------------------------------------------------------
// Dynamics written once as template functors (converted to StateInputFunction).
struct DoubleIntegrator {
  template <class T>
  void operator()(const Eigen::Matrix<T, -1, 1>& x, const Eigen::Matrix<T, -1, 1>& u,
                  Eigen::Matrix<T, -1, 1>& xdot) const {
    xdot.resize(2);
    xdot << x(1), u(0);
  }
};

constexpr double kGravity = 9.81;  // [m/s²]

// Planar point mass in flight, x = [x, z, ẋ, ż].
struct PlanarBallistic {
  template <class T>
  void operator()(const Eigen::Matrix<T, -1, 1>& x, const Eigen::Matrix<T, -1, 1>&,
                  Eigen::Matrix<T, -1, 1>& xdot) const {
    xdot.resize(4);
    xdot << x(2), x(3), T(0.0), T(-kGravity);
  }
};

// Vertical point mass, x = [z, ż].
struct VerticalBallistic {
  template <class T>
  void operator()(const Eigen::Matrix<T, -1, 1>& x, const Eigen::Matrix<T, -1, 1>&,
                  Eigen::Matrix<T, -1, 1>& xdot) const {
    xdot.resize(2);
    xdot << x(1), T(-kGravity);
  }
};

// Torque-driven pendulum θ̈ = −(g/l) sin θ − b θ̇ + u, x = [θ, θ̇].
struct Pendulum {
  template <class T>
  void operator()(const Eigen::Matrix<T, -1, 1>& x, const Eigen::Matrix<T, -1, 1>& u,
                  Eigen::Matrix<T, -1, 1>& xdot) const {
    using std::sin;
    xdot.resize(2);
    xdot << x(1), -kGravity * sin(x(0)) - 0.1 * x(1) + u(0);
  }
};

// RK4 re-integration of ẋ = f(x, u(t)) with the collocated input trajectory.
template <class F>
Eigen::VectorXd Rk4(const F& f, Eigen::VectorXd x, const PiecewisePolynomial& u, double t0, double t1, int steps) {
  auto eval = [&](const Eigen::VectorXd& xs, double t) {
    const NodeVector xa = InitializeAutoDiff<NodeScalar>(xs, 0, 0);
    const NodeVector ua = InitializeAutoDiff<NodeScalar>(u.Value(t), 0, 0);
    NodeVector y;
    f(xa, ua, y);
    return ExtractValue(y);
  };
  const double h = (t1 - t0) / steps;
  for (int i = 0; i < steps; ++i) {
    const double t = t0 + i * h;
    const Eigen::VectorXd k1 = eval(x, t), k2 = eval(x + 0.5 * h * k1, t + 0.5 * h),
                          k3 = eval(x + 0.5 * h * k2, t + 0.5 * h), k4 = eval(x + h * k3, t + h);
    x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return x;
}

// Trapezoid defects recomputed from the returned nodes (independent of the NLP code).
double RecomputedMaxDefect(const CollocationPhaseSolution& s, const StateInputFunction& f) {
  double worst = 0.0;
  const int N = static_cast<int>(s.times.size());
  Eigen::MatrixXd fx(s.states.rows(), N);
  for (int k = 0; k < N; ++k) {
    NodeVector y;
    f(InitializeAutoDiff<NodeScalar>(s.states.col(k), 0, 0), InitializeAutoDiff<NodeScalar>(s.inputs.col(k), 0, 0), y);
    fx.col(k) = ExtractValue(y);
  }
  for (int k = 0; k + 1 < N; ++k) {
    const double h = s.times(k + 1) - s.times(k);
    worst = std::max(
        worst, (s.states.col(k + 1) - s.states.col(k) - 0.5 * h * (fx.col(k) + fx.col(k + 1))).cwiseAbs().maxCoeff());
  }
  return worst;
}

DirectCollocation MakeMinimumEnergyTransfer(int num_nodes) {
  CollocationPhase phase;
  phase.name = "transfer";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = num_nodes;
  phase.dynamics = DoubleIntegrator();
  phase.min_duration = phase.max_duration = 1.0;
  phase.running_cost = [](const NodeVector&, const NodeVector& u) -> NodeScalar { return u(0) * u(0); };
  DirectCollocation dc("min_energy_double_integrator", {phase});
  dc.SetNodeStateBounds(0, 0, Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, 0.0));
  dc.SetNodeStateBounds(0, -1, Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 0.0));
  return dc;
}

TEST(DirectCollocation, MinimumEnergyDoubleIntegratorMatchesClosedForm) {
  // min ∫₀¹ u² dt, ẍ = u, x(0) = ẋ(0) = 0, x(1) = 1, ẋ(1) = 0:
  // u*(t) = 6 − 12t, x*(t) = 3t² − 2t³, ẋ*(t) = 6t − 6t², cost 12.
  double previous_error = 0.0;
  for (int N : {11, 21, 41}) {
    const DirectCollocation dc = MakeMinimumEnergyTransfer(N);
    const CollocationResult r = dc.Solve();
    ASSERT_TRUE(r.success()) << r.nlp.message;
    const CollocationPhaseSolution& s = r.phases.at(0);
    double state_error = 0.0, input_error = 0.0, endpoint_input_error = 0.0;
    for (int k = 0; k < N; ++k) {
      const double t = s.times(k);
      state_error = std::max(
          state_error,
          (s.states.col(k) - Eigen::Vector2d(3 * t * t - 2 * t * t * t, 6 * t - 6 * t * t)).cwiseAbs().maxCoeff());
      const double du = std::abs(s.inputs(0, k) - (6.0 - 12.0 * t));
      if (k == 0 || k == N - 1) {
        endpoint_input_error = std::max(endpoint_input_error, du);
      } else {
        input_error = std::max(input_error, du);
      }
    }
    const double h = 1.0 / (N - 1);
    // Trapezoid rule: local error h³/12 · x⃛ (|x⃛| = 12) ⇒ O(h²) globally. Measured constants:
    // state ≈ 2.9 h², interior input ≈ 21 h², cost − 12 ≈ 47 h². The two endpoint inputs carry
    // the known boundary artifact of trapezoidal collocation (their cost and defect weights are
    // h/2), which decays slower; it stays below 0.5 and does not affect the states.
    EXPECT_LT(state_error, 4.0 * h * h) << "N = " << N;
    EXPECT_LT(input_error, 30.0 * h * h) << "N = " << N;
    EXPECT_LT(endpoint_input_error, 0.5) << "N = " << N;
    EXPECT_GT(r.nlp.cost, 12.0) << "the discretization can only add cost here";
    EXPECT_NEAR(r.nlp.cost, 12.0, 60.0 * h * h) << "N = " << N;
    EXPECT_LT(r.max_defect, 1e-8);
    EXPECT_LT(RecomputedMaxDefect(s, DoubleIntegrator()), 1e-8);
    if (previous_error > 0.0) { EXPECT_GT(previous_error / state_error, 3.5) << "second-order convergence, N = " << N; }
    previous_error = state_error;
    std::printf(
        "N = %2d: %d iterations, %.1f ms, |x − x*|∞ = %.2e, interior |u − u*|∞ = %.2e, "
        "endpoint |u − u*| = %.2e, cost = %.6f, max defect = %.1e\n",
        N, r.nlp.iterations, 1e3 * r.nlp.wall_time, state_error, input_error, endpoint_input_error, r.nlp.cost,
        r.max_defect);
  }
}

TEST(DirectCollocation, ReintegratedDoubleIntegratorStaysNearCollocatedTrajectory) {
  const DirectCollocation dc = MakeMinimumEnergyTransfer(21);
  const CollocationResult r = dc.Solve();
  ASSERT_TRUE(r.success()) << r.nlp.message;
  const CollocationPhaseSolution& s = r.phases.at(0);
  // RK4 (exact for this linear system with a piecewise-linear input, up to round-off) against
  // the cubic-Hermite state trajectory on a fine grid. The difference is the trapezoid
  // truncation error, O(h²) with h = 0.05 (measured ≈ 0.96 h²): stated bound 2 h² = 5e-3.
  double worst = 0.0;
  Eigen::VectorXd x = s.states.col(0);
  double t = 0.0;
  const int segments = 100;
  for (int i = 1; i <= segments; ++i) {
    const double t_next = static_cast<double>(i) / segments;
    x = Rk4(DoubleIntegrator(), x, s.input_trajectory, t, t_next, 4);
    t = t_next;
    worst = std::max(worst, (x - s.state_trajectory.Value(t)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 5e-3);
  // The Hermite trajectory's derivative equals f at the nodes (consistency with collocation).
  for (int k = 0; k < 21; ++k) {
    EXPECT_LT((s.state_trajectory.Derivative(s.times(k)) - s.state_derivatives.col(k)).norm(), 1e-9);
  }
  std::printf("double integrator re-integration: max |x_rk4 − x_col| = %.2e\n", worst);
}

TEST(DirectCollocation, NonlinearPendulumReintegrationConverges) {
  // Swing a damped pendulum from rest at θ = 0 to θ = 1 rad at rest in 2 s with minimum ∫u².
  double previous = 0.0;
  for (int N : {21, 41}) {
    CollocationPhase phase;
    phase.name = "swing";
    phase.num_states = 2;
    phase.num_inputs = 1;
    phase.num_nodes = N;
    phase.dynamics = Pendulum();
    phase.min_duration = phase.max_duration = 2.0;
    phase.input_lower = Eigen::VectorXd::Constant(1, -20.0);
    phase.input_upper = Eigen::VectorXd::Constant(1, 20.0);
    phase.running_cost = [](const NodeVector&, const NodeVector& u) -> NodeScalar { return u(0) * u(0); };
    DirectCollocation dc("pendulum_swing", {phase});
    dc.SetNodeStateBounds(0, 0, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
    dc.SetNodeStateBounds(0, -1, Eigen::Vector2d(1.0, 0.0), Eigen::Vector2d(1.0, 0.0));
    const CollocationResult r = dc.Solve();
    ASSERT_TRUE(r.success()) << r.nlp.message;
    const auto& s = r.phases.at(0);
    EXPECT_LT(RecomputedMaxDefect(s, Pendulum()), 1e-7);
    const Eigen::VectorXd x_end = Rk4(Pendulum(), s.states.col(0), s.input_trajectory, 0.0, 2.0, 2000);
    const double error = (x_end - Eigen::Vector2d(1.0, 0.0)).cwiseAbs().maxCoeff();
    // Open-loop replay drifts by the O(h²) collocation error (measured ≈ 5.7 h², h = 2/(N−1)):
    // stated bound 10 h², and second-order decay.
    const double h = 2.0 / (N - 1);
    EXPECT_LT(error, 10.0 * h * h) << "N = " << N;
    if (previous > 0.0) { EXPECT_GT(previous / error, 3.0) << "N = " << N; }
    previous = error;
    std::printf("pendulum N = %d: %d iterations, %.1f ms, final-state replay error %.2e\n", N, r.nlp.iterations,
                1e3 * r.nlp.wall_time, error);
  }
}

// Hybrid ballistic sequence: rise to apex (free T, ż = 0 at the end), fall to the ground (free T,
// z = 0 at the end), bounce reset (ż⁺ = −e ż⁻, horizontal coordinates dropped: 4 → 2 states),
// rise to the second apex (free T, ż = 0).
DirectCollocation MakeBouncingBall(double vx0, double vz0, double restitution, int N) {
  CollocationPhase rise;
  rise.name = "rise";
  rise.num_states = 4;
  rise.num_inputs = 0;
  rise.num_nodes = N;
  rise.dynamics = PlanarBallistic();
  rise.min_duration = 0.05;
  rise.max_duration = 3.0;
  rise.state_lower = Eigen::Vector4d(-100.0, 0.0, -100.0, -100.0);
  rise.state_upper = Eigen::Vector4d::Constant(100.0);
  CollocationPhase fall = rise;
  fall.name = "fall";
  CollocationPhase rebound;
  rebound.name = "rebound";
  rebound.num_states = 2;
  rebound.num_inputs = 0;
  rebound.num_nodes = N;
  rebound.dynamics = VerticalBallistic();
  rebound.min_duration = 0.05;
  rebound.max_duration = 3.0;
  rebound.state_lower = Eigen::Vector2d(0.0, -100.0);
  rebound.state_upper = Eigen::Vector2d::Constant(100.0);
  DirectCollocation dc("bouncing_ball", {rise, fall, rebound});
  dc.SetNodeStateBounds(0, 0, Eigen::Vector4d(0.0, 0.0, vx0, vz0), Eigen::Vector4d(0.0, 0.0, vx0, vz0));
  const auto vz = [](const NodeVector& x, const NodeVector&, NodeVector& y) {
    y.resize(1);
    y(0) = x(x.size() - 1);
  };
  const auto z = [](const NodeVector& x, const NodeVector&, NodeVector& y) {
    y.resize(1);
    y(0) = x(x.size() == 4 ? 1 : 0);
  };
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
  dc.AddNodeConstraint(0, -1, 1, vz, zero, zero, "apex");
  dc.AddNodeConstraint(1, -1, 1, z, zero, zero, "touchdown");
  dc.AddNodeConstraint(2, -1, 1, vz, zero, zero, "second_apex");
  dc.SetTransition(1, [restitution](const NodeVector& x, NodeVector& y) {
    y.resize(2);
    y << x(1), -restitution * x(3);
  });
  // Rough guess: T = 0.5 s everywhere, states at rest 1 m up.
  Eigen::MatrixXd x4 = Eigen::MatrixXd::Zero(4, N), x2 = Eigen::MatrixXd::Zero(2, N);
  x4.row(1).setConstant(1.0);
  x2.row(0).setConstant(1.0);
  dc.SetInitialGuess(0, x4, Eigen::MatrixXd(0, N), 0.5);
  dc.SetInitialGuess(1, x4, Eigen::MatrixXd(0, N), 0.5);
  dc.SetInitialGuess(2, x2, Eigen::MatrixXd(0, N), 0.5);
  return dc;
}

TEST(DirectCollocation, BouncingBallMatchesAnalyticApexes) {
  const double vx0 = 1.5, vz0 = 4.0, e = 0.8;
  const DirectCollocation dc = MakeBouncingBall(vx0, vz0, e, 11);
  const CollocationResult r = dc.Solve();
  ASSERT_TRUE(r.success()) << r.nlp.message;
  ASSERT_EQ(r.phases.size(), 3u);
  // Analytic: apex time vz0/g, height vz0²/2g; fall time = rise time; impact speed vz0;
  // second apex after e vz0/g at height e² vz0²/2g. Trapezoid collocation is exact for
  // constant acceleration, so only the NLP tolerance remains.
  const double T1 = vz0 / kGravity, h1 = vz0 * vz0 / (2.0 * kGravity);
  const auto& rise = r.phases[0];
  const auto& fall = r.phases[1];
  const auto& rebound = r.phases[2];
  EXPECT_NEAR(rise.duration, T1, 1e-7);
  EXPECT_NEAR(rise.states(1, 10), h1, 1e-7);
  EXPECT_NEAR(rise.states(0, 10), vx0 * T1, 1e-7);
  EXPECT_NEAR(fall.duration, T1, 1e-7);
  EXPECT_NEAR(fall.states(3, 10), -vz0, 1e-7);
  EXPECT_NEAR(rebound.start_time, 2.0 * T1, 1e-7);
  EXPECT_NEAR(rebound.states(1, 0), e * vz0, 1e-7);
  EXPECT_NEAR(rebound.duration, e * T1, 1e-7);
  EXPECT_NEAR(rebound.states(0, 10), e * e * h1, 1e-7);
  // The interpolated trajectory hits the apex height mid-flight as well (exact parabola).
  EXPECT_NEAR(rise.state_trajectory.Value(0.5 * T1)(1), vz0 * 0.5 * T1 - 0.5 * kGravity * 0.25 * T1 * T1, 1e-7);
  EXPECT_LT(r.max_defect, 1e-8);
  EXPECT_LT(RecomputedMaxDefect(rise, PlanarBallistic()), 1e-8);
  EXPECT_LT(RecomputedMaxDefect(rebound, VerticalBallistic()), 1e-8);
  // Differing state sizes cannot be concatenated; the error says which phase.
  try {
    r.ConcatenatedStateTrajectory();
    FAIL();
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("rebound"), std::string::npos) << err.what();
  }
  std::printf("bouncing ball: %d iterations, %.1f ms, apex error %.1e m, apex time error %.1e s\n", r.nlp.iterations,
              1e3 * r.nlp.wall_time, std::abs(rise.states(1, 10) - h1), std::abs(rise.duration - T1));
}

TEST(DirectCollocation, ConstraintJacobianMatchesFiniteDifferences) {
  // At a random point (free durations, a reset map, node constraints, running cost).
  const DirectCollocation dc = MakeBouncingBall(1.5, 4.0, 0.8, 6);
  auto nlp = dc.BuildNlp();
  Eigen::VectorXd z = Eigen::VectorXd::Random(nlp->num_variables());
  z = z.cwiseMax(nlp->variable_lower_bounds()).cwiseMin(nlp->variable_upper_bounds());
  for (int i = 0; i < z.size(); ++i) {
    // Durations (lower bound 0.05 s) away from zero.
    if (nlp->variable_lower_bounds()(i) == 0.05) z(i) = 0.3 + 0.1 * i / z.size();
  }
  DerivativeCheckResult check = CheckDerivatives(*nlp, z);
  EXPECT_LT(check.max_jacobian_error, 1e-7);
  EXPECT_EQ(check.max_missing_jacobian_entry, 0.0);

  CollocationPhase phase;
  phase.name = "swing";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = 7;
  phase.dynamics = Pendulum();
  phase.min_duration = 0.5;
  phase.max_duration = 3.0;
  phase.duration_cost = 0.3;
  phase.running_cost = [](const NodeVector& x, const NodeVector& u) -> NodeScalar {
    return u(0) * u(0) + x(0) * x(1) * x(1);
  };
  DirectCollocation pendulum("pendulum", {phase});
  pendulum.AddPathConstraint(
      0, 1,
      [](const NodeVector& x, const NodeVector& u, NodeVector& y) {
        y.resize(1);
        y(0) = x(1) * u(0);  // mechanical power limit
      },
      Eigen::VectorXd::Constant(1, -5.0), Eigen::VectorXd::Constant(1, 5.0), "power");
  pendulum.SetTerminalCost(
      [](const NodeVector& x, const NodeVector&) -> NodeScalar { return 10.0 * (x(0) - 1.0) * (x(0) - 1.0); });
  auto nlp2 = pendulum.BuildNlp();
  Eigen::VectorXd z2 = Eigen::VectorXd::Random(nlp2->num_variables());
  z2(z2.size() - 1) = 1.7;  // duration
  check = CheckDerivatives(*nlp2, z2);
  EXPECT_LT(check.max_gradient_error, 1e-7);
  EXPECT_LT(check.max_jacobian_error, 1e-7);
  EXPECT_EQ(check.max_missing_jacobian_entry, 0.0);
  // The same problems with the Lagrangian Hessian (forward differences of exact gradients inside, so compare to the
  // checker's finite differences at the 1e-5 level), then solved with it.
  pendulum.SetExactHessian(true);
  auto nlp3 = pendulum.BuildNlp();
  ASSERT_TRUE(nlp3->has_lagrangian_hessian());
  check = CheckDerivatives(*nlp3, z2);
  EXPECT_LT(check.max_hessian_error, 1e-5);
  DirectCollocation ball = MakeBouncingBall(1.5, 4.0, 0.8, 6);
  ball.SetExactHessian(true);
  auto nlp4 = ball.BuildNlp();
  check = CheckDerivatives(*nlp4, z);
  EXPECT_LT(check.max_hessian_error, 1e-5);
  std::printf("pendulum NLP: %d variables, %d constraints, %d Jacobian nonzeros\n", nlp2->num_variables(),
              nlp2->num_constraints(), nlp2->constraint_jacobian_sparsity().nnz());
}

TEST(DirectCollocation, PeriodicTransitionClosesTheCycle) {
  // ẋ = u on [0, 1], min ∫ u², with the periodic reset x_0 = x_{N-1} − 1 (a "step" of length 1, as a walking gait
  // re-expressed about the next foot): the optimum is u ≡ 1, cost 1 (Cauchy-Schwarz). A second state with ẏ = −y and
  // the swap-free reset y_0 = 2 y_{N-1} tests the Jacobian of a non-identity map.
  CollocationPhase phase;
  phase.name = "step";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = 11;
  phase.dynamics = [](const NodeVector& x, const NodeVector& u, NodeVector& y) {
    y.resize(2);
    y(0) = u(0);
    y(1) = -x(1) + 0.0 * u(0);
  };
  phase.running_cost = [](const NodeVector&, const NodeVector& u) -> NodeScalar { return u(0) * u(0); };
  DirectCollocation dc("periodic", {phase});
  dc.SetPeriodicTransition([](const NodeVector& x, NodeVector& y) {
    y.resize(2);
    y(0) = x(0) - 1.0;
    y(1) = 2.0 * x(1) * x(1) + 0.5 * x(1);
  });
  auto nlp = dc.BuildNlp();
  EXPECT_EQ(nlp->num_constraints(), 10 * 2 + 2);
  Eigen::VectorXd z = Eigen::VectorXd::Random(nlp->num_variables());
  const DerivativeCheckResult check = CheckDerivatives(*nlp, z);
  EXPECT_LT(check.max_jacobian_error, 1e-7);
  EXPECT_EQ(check.max_missing_jacobian_entry, 0.0);
  const CollocationResult r = dc.Solve();
  ASSERT_TRUE(r.success()) << r.nlp.message;
  EXPECT_NEAR(r.nlp.cost, 1.0, 1e-7);
  EXPECT_NEAR(r.phases[0].states(0, 10) - r.phases[0].states(0, 0), 1.0, 1e-8);
  EXPECT_LT((r.phases[0].inputs.array() - 1.0).abs().maxCoeff(), 1e-5);
  // y: y_0 = 2 y_end² + y_end/2 with y_end ≈ e^{-1} y_0 (trapezoid: ((1 − h/2)/(1 + h/2))^10 y_0); y = 0 is one fixed
  // point, the other satisfies 1 = 2 ρ y_0 ρ + ρ/2 ⇒ check the reset equation itself.
  const double y0 = r.phases[0].states(1, 0), y1 = r.phases[0].states(1, 10);
  EXPECT_NEAR(y0, 2 * y1 * y1 + 0.5 * y1, 1e-8);
  EXPECT_THROW(dc.SetPeriodicTransition(StateFunction()), std::invalid_argument);
  // Same answer with the Lagrangian Hessian.
  dc.SetExactHessian(true);
  const CollocationResult r2 = dc.Solve();
  ASSERT_TRUE(r2.success()) << r2.nlp.message;
  EXPECT_NEAR(r2.nlp.cost, 1.0, 1e-7);
  EXPECT_LE(r2.nlp.iterations, r.nlp.iterations);
}

TEST(DirectCollocation, RejectsBadDefinitions) {
  CollocationPhase phase;
  phase.name = "bad";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = 1;
  phase.dynamics = DoubleIntegrator();
  try {
    DirectCollocation("dc", {phase});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'bad'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("num_nodes"), std::string::npos) << e.what();
  }
  phase.num_nodes = 5;
  phase.min_duration = 2.0;
  phase.max_duration = 1.0;
  EXPECT_THROW(DirectCollocation("dc", {phase}), std::invalid_argument);
  phase.max_duration = 2.0;
  phase.dynamics = nullptr;
  EXPECT_THROW(DirectCollocation("dc", {phase}), std::invalid_argument);
  phase.dynamics = DoubleIntegrator();
  CollocationPhase other = phase;
  other.num_states = 3;
  DirectCollocation dc("dc", {phase, other});
  EXPECT_THROW(dc.BuildNlp(), std::invalid_argument);  // sizes differ, no transition map
  EXPECT_THROW(dc.SetNodeStateBounds(0, 5, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()), std::out_of_range);
  EXPECT_THROW(dc.SetTransition(1, nullptr), std::out_of_range);
  // More node variables than the node scalar holds: named, with the count.
  CollocationPhase wide = phase;
  wide.name = "wide";
  wide.num_states = kMaxNodeVariables;
  try {
    DirectCollocation("dc", {wide});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'wide'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("got " + std::to_string(kMaxNodeVariables + 1)), std::string::npos)
        << e.what();
  }
  // Dynamics returning the wrong size are reported by name.
  CollocationPhase wrong = phase;
  wrong.name = "wrong_size";
  wrong.dynamics = [](const NodeVector& x, const NodeVector&, NodeVector& y) { y = x.head(1); };
  DirectCollocation dc2("dc2", {wrong});
  try {
    dc2.Solve();
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("wrong_size"), std::string::npos) << e.what();
  }
}

// Hermite–Simpson defects: a driven pendulum integrated by the collocation constraints alone (states fixed at the
// start, fixed duration, no cost) converges at 4th order to the RK4 reference (trapezoid: 2nd order); with a free
// duration the sparse Jacobian of the Hermite–Simpson defects matches finite differences.
TEST(DirectCollocation, HermiteSimpsonIsFourthOrderAndItsJacobianIsExact) {
  const StateInputFunction pendulum = Pendulum();
  const PiecewisePolynomial u =
      PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 2.0), Eigen::RowVector2d(1.0, -2.0));
  const Eigen::Vector2d x0(0.3, 0.0);
  const Eigen::VectorXd reference = Rk4(Pendulum(), x0, u, 0.0, 2.0, 200000);
  double previous[2] = {0.0, 0.0};
  for (int N : {11, 21, 41}) {
    for (int m = 0; m < 2; ++m) {
      CollocationPhase phase;
      phase.name = "pendulum";
      phase.num_states = 2;
      phase.num_inputs = 1;
      phase.num_nodes = N;
      phase.dynamics = pendulum;
      phase.method = m == 0 ? CollocationMethod::kTrapezoidal : CollocationMethod::kHermiteSimpson;
      phase.min_duration = phase.max_duration = 2.0;
      DirectCollocation dc("integrate", {phase});
      dc.SetNodeStateBounds(0, 0, x0, x0);
      Eigen::MatrixXd inputs(1, N);
      for (int k = 0; k < N; ++k) inputs(0, k) = u.Value(2.0 * k / (N - 1))(0);
      for (int k = 0; k < N; ++k)
        dc.AddNodeConstraint(
            0, k, 1,
            [](const NodeVector&, const NodeVector& v, NodeVector& y) {
              y.resize(1);
              y(0) = v(0);
            },
            inputs.col(k), inputs.col(k), "input");
      const CollocationResult r = dc.Solve();
      ASSERT_TRUE(r.success()) << r.nlp.message;
      EXPECT_LT(r.max_defect, 1e-8);
      const double error = (r.phases[0].states.col(N - 1) - reference).cwiseAbs().maxCoeff();
      if (N > 11) {
        const double order = std::log2(previous[m] / error);
        EXPECT_NEAR(order, m == 0 ? 2.0 : 4.0, 0.3) << (m == 0 ? "trapezoid" : "Hermite-Simpson") << " N = " << N;
      }
      previous[m] = error;
      std::printf("%s N = %d: end-state error %.3e\n", m == 0 ? "trapezoid      " : "Hermite-Simpson", N, error);
    }
  }
  CollocationPhase phase;
  phase.name = "swing";
  phase.num_states = 2;
  phase.num_inputs = 1;
  phase.num_nodes = 7;
  phase.dynamics = pendulum;
  phase.method = CollocationMethod::kHermiteSimpson;
  phase.min_duration = 0.5;
  phase.max_duration = 3.0;
  DirectCollocation dc("swing", {phase});
  std::unique_ptr<NlpProblem> nlp = dc.BuildNlp();
  Eigen::VectorXd z = Eigen::VectorXd::Random(nlp->num_variables());
  z(z.size() - 1) = 1.7;  // duration
  const DerivativeCheckResult check = CheckDerivatives(*nlp, z);
  EXPECT_LT(check.max_jacobian_error, 1e-7);
  EXPECT_EQ(check.max_missing_jacobian_entry, 0.0);
}

}  // namespace
}  // namespace rome
