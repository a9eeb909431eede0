// Footed H-LIP transition QP, Eq. (11)-(15): a standing start (DSP, the right foot unloading, then a left SSP) that
// must end on the lateral P2 orbit. Checks: the terminal state to 1e-9, Eq. (14) at every node (so the unloaded foot
// has u = 0), the torque limit, the node states against a fine RK4 integration of the continuous footed H-LIP under the
// held torques (independent of the ZOH matrices), and the KKT conditions of Eq. (15) rebuilt here from the plan.
// normal_force_pivots: the same checks against an RK4 integration of the point mass on its two loaded feet,
// m z0 ÿ = F_L (y − y_L) + F_R (y − y_R) + u_L + u_R with each interval's mean forces; with node heights, m z_k.
#include "systems/planners/footed_hlip_transition_planner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "systems/rom/hybrid_linear_inverted_pendulum.h"

namespace rome {
namespace {

FootedHlipTransitionData StandingStart(double dsp_duration, int dsp_intervals, double ssp_duration, int ssp_intervals) {
  const double m = 76, g = 9.81, mg = m * g;
  FootedHlipTransitionData d;
  const int N = dsp_intervals + ssp_intervals + 1;
  d.node_times.resize(N);
  d.left_normal_force.resize(N);
  d.right_normal_force.resize(N);
  for (int k = 0; k < N; ++k) {
    if (k <= dsp_intervals) {
      const double s = static_cast<double>(k) / dsp_intervals;
      d.node_times(k) = dsp_duration * s;
      d.left_normal_force(k) = 0.5 * mg * (1 + s);
      d.right_normal_force(k) = 0.5 * mg * (1 - s);
    } else {
      const double s = static_cast<double>(k - dsp_intervals) / ssp_intervals;
      d.node_times(k) = dsp_duration + ssp_duration * s;
      d.left_normal_force(k) = mg * (1 + 0.2 * std::sin(M_PI * s));  // the height oscillates: F ≠ m g (footnote 1)
      d.right_normal_force(k) = 0.0;
    }
  }
  for (int k = 0; k + 1 < N; ++k) d.single_support.push_back(k >= dsp_intervals);
  d.stance_left = true;
  d.left_foot_y = 0.125;
  d.right_foot_y = -0.125;
  d.z0 = 0.9;
  d.initial_state = Eigen::Vector2d(0.0, 0.0);  // standing: the mid-point of the feet, at rest
  // End of the left stance on the P2 orbit of gait A (W = 0.25 m).
  const HybridLinearInvertedPendulum h({.z0 = 0.9, .ssp_duration = 0.4, .dsp_duration = 0.1});
  const Eigen::Vector2d pre = h.P2PreImpactState(0.25);
  d.final_state = Eigen::Vector2d(d.left_foot_y + pre(0), pre(1));
  return d;
}

// `sub` classical RK4 steps of q' = f(q) over a time T (the tests' independent integration of the continuous models).
template <class F>
Eigen::Vector2d Rk4(const F& f, Eigen::Vector2d q, double T, int sub) {
  const double h = T / sub;
  for (int j = 0; j < sub; ++j) {
    const Eigen::Vector2d k1 = f(q), k2 = f(q + 0.5 * h * k1), k3 = f(q + 0.5 * h * k2), k4 = f(q + h * k3);
    q += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return q;
}

// Largest gap between a plan's node k + 1 and an RK4 integration (200 sub-steps) from node k of the point mass on
// its two loaded feet, m z ÿ = F_L (y − y_L) + F_R (y − y_R) + u_L + u_R, with the interval's mean forces and held
// torques; z = the mean of the interval's two node heights, or z0 without heights.
double PointMassRk4Error(const FootedHlipTransitionData& d, const FootedHlipTransitionPlan& plan, double mass,
                         bool use_heights) {
  double worst = 0.0;
  for (int k = 0; k + 1 < static_cast<int>(d.node_times.size()); ++k) {
    const double FL = 0.5 * (d.left_normal_force(k) + d.left_normal_force(k + 1));
    const double FR = 0.5 * (d.right_normal_force(k) + d.right_normal_force(k + 1));
    const double mz = mass * (use_heights ? 0.5 * (d.node_heights(k) + d.node_heights(k + 1)) : d.z0);
    const double u = plan.left_torque(k) + plan.right_torque(k);
    auto f = [&](const Eigen::Vector2d& q) {
      return Eigen::Vector2d(q(1), (FL * (q(0) - d.left_foot_y) + FR * (q(0) - d.right_foot_y) + u) / mz);
    };
    const Eigen::Vector2d q = Rk4(f, plan.states.col(k), d.node_times(k + 1) - d.node_times(k), 200);
    worst = std::max(worst, (q - plan.states.col(k + 1)).cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(FootedHlipTransitionPlanner, HitsTheTerminalStateWithinTheZmpBounds) {
  const FootedHlipTransitionPlanner planner;
  const FootedHlipTransitionParams& p = planner.params();
  // A short DSP, so that the ZMP bounds bind.
  const FootedHlipTransitionData d = StandingStart(0.3, 15, 0.4, 20);
  const FootedHlipTransitionPlan plan = planner.Solve(d);
  ASSERT_TRUE(plan.success()) << plan.message;
  const int N = static_cast<int>(d.node_times.size());
  EXPECT_LT((plan.states.col(0) - d.initial_state).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((plan.states.col(N - 1) - d.final_state).cwiseAbs().maxCoeff(), 1e-9);
  for (int k = 0; k < N; ++k) {
    const double tol = 1e-9;
    EXPECT_GE(plan.left_torque(k), -p.foot_width_left_of_ankle * d.left_normal_force(k) - tol);
    EXPECT_LE(plan.left_torque(k), p.foot_width_right_of_ankle * d.left_normal_force(k) + tol);
    EXPECT_GE(plan.right_torque(k), -p.foot_width_left_of_ankle * d.right_normal_force(k) - tol);
    EXPECT_LE(plan.right_torque(k), p.foot_width_right_of_ankle * d.right_normal_force(k) + tol);
    EXPECT_LE(std::abs(plan.left_torque(k)), p.max_ankle_roll_torque + tol);
  }
  // The swing foot (F = 0) has no torque in SSP.
  EXPECT_LT(plan.right_torque.tail(20).cwiseAbs().maxCoeff(), 1e-9);
  // The ZMP bounds bind somewhere (otherwise the test would not exercise Eq. (14)).
  int active = 0;
  for (int k = 0; k < N; ++k) {
    if (std::abs(std::abs(plan.left_torque(k)) - 0.06 * d.left_normal_force(k)) < 1e-6 && d.left_normal_force(k) > 0)
      ++active;
  }
  EXPECT_GT(active, 0);

  // Fine RK4 of ÿ = λ²(y − y_stance) + u/(m z0) (SSP) or (u_L + u_R)/(m z0) (DSP) with the torques held.
  const double lambda2 = p.gravity / d.z0, mz = p.mass * d.z0;
  Eigen::Vector2d x = d.initial_state;
  double worst = 0.0;
  for (int k = 0; k + 1 < N; ++k) {
    const bool ssp = d.single_support[k];
    const double u = ssp ? plan.left_torque(k) : plan.left_torque(k) + plan.right_torque(k);
    auto f = [&](const Eigen::Vector2d& s) {
      return Eigen::Vector2d(s(1), (ssp ? lambda2 * (s(0) - d.left_foot_y) : 0.0) + u / mz);
    };
    x = Rk4(f, x, d.node_times(k + 1) - d.node_times(k), 500);
    worst = std::max(worst, (x - plan.states.col(k + 1)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-10);

  // KKT of Eq. (15) on the torques alone: with the dynamics eliminated, Y^{N-1} = c + Σ_k M_k u^k is affine in the
  // torques, so optimality means 2u = −M^T ν + (ZMP/limit multipliers) for some ν ∈ R²: at every node whose torque is
  // strictly inside its bounds, 2 u_i^k lies on the span of the rows of M_k. Check that with a least-squares ν.
  // M_k (effect of u^k on the final state) from the continuous model: propagate a unit torque impulse by RK4 as above.
  // Here we use the interior-node condition only (independent of the solver's multipliers).
  std::vector<int> interior;
  for (int k = 0; k + 1 < N; ++k) {
    const double F = d.left_normal_force(k), uk = plan.left_torque(k);
    if (std::abs(uk) < 0.06 * F - 1e-6 && std::abs(uk) < p.max_ankle_roll_torque - 1e-6) interior.push_back(k);
  }
  ASSERT_GE(interior.size(), 3u);
  auto propagate = [&](int k0) {  // dY_final / du_L^{k0} by finite sensitivity of the linear flow (exact: linear)
    Eigen::Vector2d s(0, 0);
    for (int k = k0; k + 1 < N; ++k) {
      const bool ssp = d.single_support[k];
      const double u = k == k0 ? 1.0 : 0.0;
      auto f = [&](const Eigen::Vector2d& q) { return Eigen::Vector2d(q(1), (ssp ? lambda2 * q(0) : 0.0) + u / mz); };
      s = Rk4(f, s, d.node_times(k + 1) - d.node_times(k), 200);
    }
    return s;
  };
  Eigen::MatrixXd M(interior.size(), 2);
  Eigen::VectorXd rhs(interior.size());
  for (size_t i = 0; i < interior.size(); ++i) {
    M.row(i) = propagate(interior[i]).transpose();
    rhs(i) = 2 * plan.left_torque(interior[i]);
  }
  const Eigen::Vector2d nu = M.colPivHouseholderQr().solve(rhs);
  EXPECT_LT((M * nu - rhs).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, rhs.cwiseAbs().maxCoeff()));
}

TEST(FootedHlipTransitionPlanner, NormalForcePivotsFollowThePointMassOnItsLoadedFeet) {
  FootedHlipTransitionParams p;
  p.normal_force_pivots = true;
  const FootedHlipTransitionData d = StandingStart(0.8, 20, 0.4, 20);
  const FootedHlipTransitionPlan plan = FootedHlipTransitionPlanner(p).Solve(d);
  ASSERT_TRUE(plan.success()) << plan.message;
  const int N = static_cast<int>(d.node_times.size());
  EXPECT_LT((plan.states.col(N - 1) - d.final_state).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((plan.states.col(0) - d.initial_state).cwiseAbs().maxCoeff(), 1e-9);
  const double mz = p.mass * d.z0;
  for (int k = 0; k + 1 < N; ++k) {
    for (int foot = 0; foot < 2; ++foot) {  // Eq. (14)
      const double F = foot == 0 ? d.left_normal_force(k) : d.right_normal_force(k),
                   u = foot == 0 ? plan.left_torque(k) : plan.right_torque(k);
      EXPECT_GE(u, -p.foot_width_left_of_ankle * F - 1e-9);
      EXPECT_LE(u, p.foot_width_right_of_ankle * F + 1e-9);
    }
    const double FL = 0.5 * (d.left_normal_force(k) + d.left_normal_force(k + 1));
    const double FR = 0.5 * (d.right_normal_force(k) + d.right_normal_force(k + 1));
    EXPECT_NEAR(plan.interval_stiffness(k), (FL + FR) / mz, 1e-12);
  }
  EXPECT_LT(PointMassRk4Error(d, plan, p.mass, /*use_heights=*/false), 1e-9);
}

// node_heights: each interval moves the mass on its own height z_k (the mean of its nodes'), as the footed-aSLIP NLP's
// lateral rows do. Checked against an RK4 integration of m z_k ÿ = F_L (y − y_L) + F_R (y − y_R) + u_L + u_R with z_k
// computed here from the heights; the same plan with z0 everywhere misses that integration (the heights matter).
TEST(FootedHlipTransitionPlanner, NodeHeightsMoveEachIntervalOnItsOwnHeight) {
  FootedHlipTransitionParams p;
  p.normal_force_pivots = true;
  FootedHlipTransitionData d = StandingStart(0.8, 20, 0.4, 20);
  const int N = static_cast<int>(d.node_times.size());
  d.node_heights.resize(N);
  for (int k = 0; k < N; ++k)
    d.node_heights(k) = 0.86 + 0.03 * std::sin(2 * M_PI * d.node_times(k) / 1.2);  // 0.83-0.89 m
  const FootedHlipTransitionPlan plan = FootedHlipTransitionPlanner(p).Solve(d);
  ASSERT_TRUE(plan.success()) << plan.message;
  EXPECT_LT((plan.states.col(N - 1) - d.final_state).cwiseAbs().maxCoeff(), 1e-9);
  ASSERT_EQ(plan.interval_height.size(), N - 1);
  for (int k = 0; k + 1 < N; ++k) {
    EXPECT_NEAR(plan.interval_height(k), 0.5 * (d.node_heights(k) + d.node_heights(k + 1)), 1e-15);
    for (int foot = 0; foot < 2; ++foot) {  // Eq. (14)
      const double F = foot == 0 ? d.left_normal_force(k) : d.right_normal_force(k),
                   u = foot == 0 ? plan.left_torque(k) : plan.right_torque(k);
      EXPECT_GE(u, -p.foot_width_left_of_ankle * F - 1e-9);
      EXPECT_LE(u, p.foot_width_right_of_ankle * F + 1e-9);
    }
  }
  const double with_heights = PointMassRk4Error(d, plan, p.mass, /*use_heights=*/true);
  EXPECT_LT(with_heights, 1e-9);
  FootedHlipTransitionData flat = d;
  flat.node_heights.resize(0);
  const FootedHlipTransitionPlan z0_plan = FootedHlipTransitionPlanner(p).Solve(flat);
  ASSERT_TRUE(z0_plan.success()) << z0_plan.message;
  const double without = PointMassRk4Error(d, z0_plan, p.mass, /*use_heights=*/true);
  std::printf("  node states against RK4 on the node heights: %.2e with them, %.2e with z0 = %.2f m everywhere\n",
              with_heights, without, d.z0);
  EXPECT_GT(without, 1e-4);
  // Bad heights are named.
  FootedHlipTransitionData bad = d;
  bad.node_heights(4) = -0.1;
  try {
    FootedHlipTransitionPlanner(p).Solve(bad);
    ADD_FAILURE() << "a negative height accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("node_heights"), std::string::npos) << e.what();
  }
  bad = d;
  bad.node_heights.conservativeResize(N - 1);
  EXPECT_THROW(FootedHlipTransitionPlanner(p).Solve(bad), std::invalid_argument);
}

TEST(FootedHlipTransitionPlanner, ReportsAnInfeasibleTransition) {
  FootedHlipTransitionData d = StandingStart(0.1, 5, 0.4, 20);
  d.final_state = Eigen::Vector2d(1.0, 0.0);  // a metre sideways in half a second with ±45 N m of ankle roll
  const FootedHlipTransitionPlan plan = FootedHlipTransitionPlanner().Solve(d);
  EXPECT_EQ(plan.status, QpStatus::kInfeasible);
  EXPECT_NE(plan.message.find("footed H-LIP transition QP"), std::string::npos);
}

TEST(FootedHlipTransitionPlanner, RejectsBadData) {
  FootedHlipTransitionData d = StandingStart(0.6, 30, 0.4, 20);
  d.left_normal_force(3) = -1.0;
  EXPECT_THROW(FootedHlipTransitionPlanner().Solve(d), std::invalid_argument);
  d = StandingStart(0.6, 30, 0.4, 20);
  d.single_support.pop_back();
  EXPECT_THROW(FootedHlipTransitionPlanner().Solve(d), std::invalid_argument);
  EXPECT_THROW(FootedHlipTransitionPlanner({.mass = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
