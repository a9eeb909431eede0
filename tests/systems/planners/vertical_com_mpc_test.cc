// VerticalComMpc, Eq. (28): dynamics and boundary conditions exact, minimum-norm closed form when the contact
// constraint is inactive, KKT conditions when it is active, infeasibility reported, soft terminal mode.
#include "systems/planners/vertical_com_mpc.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Dense>

namespace rome {
namespace {

// Terminal state of the double integrator under piecewise-constant inputs, integrated interval by interval.
Eigen::Vector2d Propagate(double p, double v, const Eigen::VectorXd& u, double dt) {
  for (int k = 0; k < u.size(); ++k) {
    p += dt * v + 0.5 * dt * dt * u[k];
    v += dt * u[k];
  }
  return {p, v};
}

TEST(VerticalComMpc, SatisfiesDynamicsAndBoundaryConditions) {
  VerticalComMpc mpc({.horizon_steps = 20});
  const double p0 = 0.82, v0 = -0.05, pf = 0.80, vf = 0.25, T = 0.35;
  ASSERT_EQ(mpc.Solve(p0, v0, pf, vf, T), QpStatus::kOptimal);
  EXPECT_NEAR(mpc.dt(), T / 20, 1e-16);
  const Eigen::Vector2d end = Propagate(p0, v0, mpc.inputs(), mpc.dt());
  EXPECT_NEAR(end[0], pf, 1e-12);
  EXPECT_NEAR(end[1], vf, 1e-12);
  // Stored trajectory obeys z_{k+1} = A z_k + B u_k exactly and starts at the measured state.
  EXPECT_EQ(mpc.positions()[0], p0);
  EXPECT_EQ(mpc.velocities()[0], v0);
  for (int k = 0; k < 20; ++k) {
    const double dt = mpc.dt(), u = mpc.inputs()[k];
    EXPECT_NEAR(mpc.positions()[k + 1], mpc.positions()[k] + dt * mpc.velocities()[k] + 0.5 * dt * dt * u, 1e-15);
    EXPECT_NEAR(mpc.velocities()[k + 1], mpc.velocities()[k] + dt * u, 1e-15);
  }
  EXPECT_NEAR(mpc.positions()[20], pf, 1e-12);
  EXPECT_NEAR(mpc.velocities()[20], vf, 1e-12);
  // EvaluatePlan reproduces the knots.
  const Eigen::Vector3d at_end = VerticalComMpc::EvaluatePlan(p0, v0, mpc.inputs(), mpc.dt(), T);
  EXPECT_NEAR(at_end[0], pf, 1e-12);
  EXPECT_NEAR(at_end[1], vf, 1e-12);
  // Unconstrained here: the solution is the minimum-norm u = Mᵀ (M Mᵀ)⁻¹ r of the two terminal rows.
  ASSERT_TRUE((mpc.inputs().array() > -9.81 + 1e-3).all());
  Eigen::MatrixXd M(2, 20);
  const double dt = mpc.dt();
  for (int k = 0; k < 20; ++k) {
    M(0, k) = dt * dt * (20 - k - 0.5);
    M(1, k) = dt;
  }
  const Eigen::Vector2d r(pf - p0 - T * v0, vf - v0);
  const Eigen::VectorXd u_min_norm = M.transpose() * (M * M.transpose()).ldlt().solve(r);
  EXPECT_NEAR((mpc.inputs() - u_min_norm).lpNorm<Eigen::Infinity>(), 0.0, 1e-9);
  // The continuous-time minimum-energy input is affine in time: so is the discrete one (second differences 0).
  for (int k = 1; k + 1 < 20; ++k)
    EXPECT_NEAR(mpc.inputs()[k + 1] - 2 * mpc.inputs()[k] + mpc.inputs()[k - 1], 0.0, 1e-9);
}

TEST(VerticalComMpc, ContactConstraintIsActiveWhereTheUnconstrainedPlanWouldPull) {
  // Rising, must arrive lower and moving down fast, with the position change close to the most a late free fall
  // allows: the minimum-norm (affine) plan would pull on the ground near the end.
  const int N = 20;
  VerticalComMpc mpc({.horizon_steps = N});
  const double p0 = 0.80, v0 = 0.5, pf = 0.735, vf = -1.5, T = 0.3, g = 9.81;
  const double dt = T / N;
  Eigen::MatrixXd M(2, N);
  for (int k = 0; k < N; ++k) {
    M(0, k) = dt * dt * (N - k - 0.5);
    M(1, k) = dt;
  }
  const Eigen::Vector2d r(pf - p0 - T * v0, vf - v0);
  const Eigen::VectorXd u_min_norm = M.transpose() * (M * M.transpose()).ldlt().solve(r);
  ASSERT_LT(u_min_norm.minCoeff(), -g - 1.0) << "test case does not exercise the contact constraint";

  ASSERT_EQ(mpc.Solve(p0, v0, pf, vf, T), QpStatus::kOptimal);
  const Eigen::VectorXd& u = mpc.inputs();
  EXPECT_GE(u.minCoeff(), -g - 1e-9);
  int active = 0;
  for (int k = 0; k < N; ++k) active += std::abs(u[k] + g) < 1e-9;
  EXPECT_GT(active, 0);
  const Eigen::Vector2d end = Propagate(p0, v0, u, dt);
  EXPECT_NEAR(end[0], pf, 1e-12);
  EXPECT_NEAR(end[1], vf, 1e-12);
  // KKT: 2u + M̃ᵀ y_eq + y_bounds = 0, y_bounds <= 0 only on active bounds (solver's sign convention).
  const QpKktResiduals kkt = ComputeQpKktResiduals(mpc.qp());
  EXPECT_LT(kkt.Max(), 1e-8) << kkt.stationarity << " " << kkt.primal_feasibility << " " << kkt.dual_feasibility << " "
                             << kkt.complementarity;
  for (int k = 0; k < N; ++k) {
    const double y = mpc.qp().y_bounds()[k];
    EXPECT_LE(y, 1e-12);
    if (std::abs(u[k] + g) > 1e-7) { EXPECT_NEAR(y, 0.0, 1e-12); }
  }
  // The constrained optimum costs more than the (infeasible) minimum-norm plan.
  EXPECT_GT(u.squaredNorm(), u_min_norm.squaredNorm());
  std::printf("contact-constrained plan: %d of %d inputs at u = -g, cost %.4f vs unconstrained %.4f (m^2/s^4)\n",
              active, N, u.squaredNorm(), u_min_norm.squaredNorm());
}

TEST(VerticalComMpc, ReportsInfeasibilityAndKeepsThePreviousPlan) {
  VerticalComMpc mpc({.horizon_steps = 10, .relax_terminal_on_infeasible = false});
  ASSERT_EQ(mpc.Solve(0.8, 0.0, 0.8, 0.1, 0.3), QpStatus::kOptimal);
  const Eigen::VectorXd before = mpc.inputs();
  // Needs ṗ to drop by 5 m/s in 0.3 s: more than gravity can do (g T = 2.9 m/s).
  EXPECT_EQ(mpc.Solve(0.8, 2.0, 0.8, -3.0, 0.3), QpStatus::kInfeasible);
  EXPECT_EQ(mpc.status(), QpStatus::kInfeasible);
  EXPECT_EQ(mpc.inputs(), before);
  EXPECT_EQ(mpc.Solve(0.8, NAN, 0.8, 0.0, 0.3), QpStatus::kInvalidInput);
  EXPECT_EQ(mpc.inputs(), before);
}

TEST(VerticalComMpc, WeightedTerminalCostIsAlwaysFeasibleAndCloseWhenFeasible) {
  VerticalComMpcParams params;
  params.horizon_steps = 20;
  params.terminal_condition = VerticalComMpcParams::TerminalCondition::kWeightedCost;
  VerticalComMpc soft(params);
  VerticalComMpc hard({.horizon_steps = 20});
  ASSERT_EQ(soft.Solve(0.82, -0.05, 0.80, 0.25, 0.35), QpStatus::kOptimal);
  ASSERT_EQ(hard.Solve(0.82, -0.05, 0.80, 0.25, 0.35), QpStatus::kOptimal);
  const Eigen::Vector2d end = Propagate(0.82, -0.05, soft.inputs(), soft.dt());
  EXPECT_NEAR(end[0], 0.80, 1e-6);
  EXPECT_NEAR(end[1], 0.25, 1e-5);
  EXPECT_LT((soft.inputs() - hard.inputs()).lpNorm<Eigen::Infinity>(), 1e-2);
  // Where the equality version is infeasible, the soft one returns the closest reachable plan: free fall.
  ASSERT_EQ(soft.Solve(0.8, 2.0, 0.8, -3.0, 0.3), QpStatus::kOptimal);
  EXPECT_NEAR(soft.inputs().maxCoeff(), -9.81, 1e-9);
  // The equality version with relaxation (default) falls back to exactly that plan and says so.
  ASSERT_EQ(hard.Solve(0.8, 2.0, 0.8, -3.0, 0.3), QpStatus::kOptimal);
  EXPECT_TRUE(hard.terminal_relaxed());
  EXPECT_NEAR((hard.inputs() - soft.inputs()).lpNorm<Eigen::Infinity>(), 0.0, 1e-9);
  ASSERT_EQ(hard.Solve(0.82, -0.05, 0.80, 0.25, 0.35), QpStatus::kOptimal);
  EXPECT_FALSE(hard.terminal_relaxed());
}

TEST(VerticalComMpc, WarmStartAndShortHorizonClamp) {
  VerticalComMpc mpc({.horizon_steps = 20, .min_horizon_s = 0.05});
  ASSERT_EQ(mpc.Solve(0.80, 0.5, 0.735, -1.5, 0.3), QpStatus::kOptimal);
  const int cold = mpc.qp().iterations();
  ASSERT_EQ(mpc.Solve(0.80, 0.5, 0.735, -1.5, 0.299), QpStatus::kOptimal);  // next tick, same active set
  EXPECT_LE(mpc.qp().iterations(), cold);
  ASSERT_EQ(mpc.Solve(0.80, 0.0, 0.80, 0.1, 0.001), QpStatus::kOptimal);
  EXPECT_NEAR(mpc.dt(), 0.05 / 20, 1e-16);  // horizon raised to min_horizon_s
  EXPECT_THROW(VerticalComMpc({.horizon_steps = 0}), std::invalid_argument);
}

// The push bound u_k <= a_max (ours). Closed form of the reach: from rest to rest in T with −g <= p̈ <= a_max, the
// highest rise accelerates at a_max for t_1 = g T / (a_max + g) and then falls freely, Δp_max = ½ a_max t_1 T (the
// area under the triangular velocity); the piecewise-constant plan reaches at most that.
TEST(VerticalComMpc, PushBoundKeepsThePlanInsideTheReachOfTheLeg) {
  const double g = 9.81, a_max = 6.0, T = 0.3, p0 = 0.63;
  const double rise_max = 0.5 * a_max * (g * T / (a_max + g)) * T;  // 0.1676 m
  VerticalComMpcParams params{.horizon_steps = 40, .max_acceleration = a_max};
  params.terminal_position_weight = 1e3;  // the planar-Cassie diagram's: the terminal velocity comes first
  VerticalComMpc mpc(params);
  // Inside the reach: the terminal state is met exactly, under the bound.
  ASSERT_EQ(mpc.Solve(p0, 0.0, p0 + 0.9 * rise_max, 0.0, T), QpStatus::kOptimal);
  EXPECT_FALSE(mpc.terminal_relaxed());
  EXPECT_LE(mpc.inputs().maxCoeff(), a_max + 1e-9);
  EXPECT_NEAR(mpc.positions()[40], p0 + 0.9 * rise_max, 1e-9);
  EXPECT_NEAR(mpc.velocities()[40], 0.0, 1e-9);
  // The paper's plan (no bound) asks for more than a_max there: the minimum-energy input peaks at 6 Δp / T².
  VerticalComMpc paper({.horizon_steps = 40});
  ASSERT_EQ(paper.Solve(p0, 0.0, p0 + 0.9 * rise_max, 0.0, T), QpStatus::kOptimal);
  EXPECT_NEAR(paper.inputs().maxCoeff(), 6 * 0.9 * rise_max / (T * T), 0.05 * 6 * 0.9 * rise_max / (T * T));
  EXPECT_GT(paper.inputs().maxCoeff(), a_max);
  // Out of reach: the relaxed plan stays under the bound, arrives nearly at rest and at most at the reach.
  ASSERT_EQ(mpc.Solve(p0, 0.0, p0 + 1.3 * rise_max, 0.0, T), QpStatus::kOptimal);
  EXPECT_TRUE(mpc.terminal_relaxed());
  EXPECT_LE(mpc.inputs().maxCoeff(), a_max + 1e-9);
  EXPECT_GE(mpc.inputs().minCoeff(), -g - 1e-9);
  const Eigen::Vector2d end = Propagate(p0, 0.0, mpc.inputs(), mpc.dt());
  EXPECT_LT(std::abs(end[1]), 0.1);
  EXPECT_LT(end[0] - p0, rise_max + T * std::abs(end[1]));
  EXPECT_GT(end[0] - p0, 0.9 * rise_max);
  EXPECT_THROW(VerticalComMpc({.horizon_steps = 20, .max_acceleration = -10.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
