// Transitional footed-aSLIP NLP, Eq. (9)-(10): standing → gait A and gait A → gait B. Checks every row and bound to
// 1e-6, free durations inside their bounds, the boundary states, Eq. (10) as a centre of pressure under the foot
// (x_cop − x_ankle = u/G_z ∈ [−L_h, L_t], from the ground reaction recomputed here), the lift-off guard, and forward
// re-integration (RK4) of the footed aSLIP under the planned inputs; and the static force balance behind the standing
// state (AslipRestLengthForForce).
#include "systems/planners/aslip_transition_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <stdexcept>

namespace rome {
namespace {

using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1>;

double Reintegrate(const AslipParams& p, const AslipTransitionData& d, const AslipTransition& t) {
  Vec x = t.collocation.phases[0].states.col(0);
  double worst = 0.0;
  for (int ph = 0; ph < 2; ++ph) {
    const CollocationPhaseSolution& s = t.collocation.phases[ph];
    const AslipContact c = AslipTransitionPlanner::PhaseContact(d, ph);
    const int N = static_cast<int>(s.times.size());
    const double h = s.duration / (N - 1);
    for (int k = 0; k + 1 < N; ++k) {
      const int sub = 100;
      const double dt = h / sub;
      for (int j = 0; j < sub; ++j) {
        auto u = [&](double tau) { return Vec(s.inputs.col(k) + (s.inputs.col(k + 1) - s.inputs.col(k)) * tau / h); };
        auto f = [&](const Vec& y, double tau) { return Vec(AslipDynamics<double>(p, c, y, u(tau))); };
        const double tt = j * dt;
        const Vec k1 = f(x, tt), k2 = f(x + 0.5 * dt * k1, tt + 0.5 * dt), k3 = f(x + 0.5 * dt * k2, tt + 0.5 * dt),
                  k4 = f(x + dt * k3, tt + dt);
        x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
      worst = std::max(worst, (x - s.states.col(k + 1)).head(2).cwiseAbs().maxCoeff());
    }
  }
  return worst;
}

void CheckTransition(const AslipTransitionPlanner& planner, const AslipTransitionData& d, const AslipTransition& t) {
  const AslipTransitionParams& q = planner.params();
  const AslipParams& p = q.bounds.aslip;
  ASSERT_TRUE(t.success()) << t.collocation.nlp.message;
  EXPECT_LE(t.max_constraint_violation, 1e-6);
  EXPECT_LE(t.collocation.max_defect, 1e-6);
  const double Td = t.collocation.phases[0].duration, Ts = t.collocation.phases[1].duration;
  EXPECT_GE(Td, q.min_dsp_duration - 1e-9);
  EXPECT_LE(Td, q.max_dsp_duration + 1e-9);
  EXPECT_GE(Ts, q.min_ssp_duration - 1e-9);
  EXPECT_LE(Ts, q.max_ssp_duration + 1e-9);
  EXPECT_LT((t.collocation.phases[0].states.col(0) - Vec(d.initial_state)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((t.collocation.phases[1].states.col(q.bounds.nodes_per_domain - 1) - Vec(d.final_state)).cwiseAbs().maxCoeff(), 1e-9);
  const double mg = p.mass * p.gravity;
  for (int ph = 0; ph < 2; ++ph) {
    const Eigen::MatrixXd G = t.GroundReactions(p, d, ph);
    const CollocationPhaseSolution& s = t.collocation.phases[ph];
    const AslipContact c = AslipTransitionPlanner::PhaseContact(d, ph);
    for (Eigen::Index k = 0; k < G.cols(); ++k) {
      for (int leg = 0; leg < 2; ++leg) {
        const double Gz = G(2 * leg + 1, k), u = s.inputs(2 + leg, k);
        if (!c.in_contact(leg)) {
          EXPECT_EQ(u, 0.0);
          continue;
        }
        EXPECT_GE(Gz, -1e-6 * mg);
        EXPECT_LE(std::abs(u), q.max_ankle_torque + 1e-6);
        // COP from the moment balance about the ankle pivot: x_cop − x_ankle = u / G_z.
        if (Gz > 0.01 * mg) {
          const double cop = u / Gz;
          EXPECT_GE(cop, -p.heel_length - 1e-6) << "phase " << ph << " node " << k << " leg " << leg;
          EXPECT_LE(cop, p.toe_length + 1e-6) << "phase " << ph << " node " << k << " leg " << leg;
        }
      }
    }
    if (ph == 0) {
      EXPECT_NEAR(G(2 * d.lifting_leg + 1, G.cols() - 1), 0.0, 1e-6 * mg);
    }
  }
  const double e = Reintegrate(p, d, t);
  // Stated bound: x, z within 3 cm over the whole open-loop transition (up to 1.6 s with h up to 50 ms; the SSP's
  // inverted-pendulum divergence, e^{λ T_SSP} ≈ 7, amplifies the trapezoid error of the DSP).
  EXPECT_LT(e, 3e-2);
  std::printf("T_DSP %.3f s, T_SSP %.3f s, %d iterations, %.0f ms, re-integration %.2g m\n", Td, Ts,
              t.collocation.nlp.iterations, 1e3 * t.collocation.nlp.wall_time, e);
}

TEST(AslipTransitionPlanner, StandingToGaitA) {
  AslipPeriodicGaitParams gait_a;
  const AslipPeriodicGait a = AslipPeriodicGaitPlanner(gait_a).Solve(1);
  ASSERT_TRUE(a.success());
  AslipTransitionParams params;
  params.bounds = gait_a;
  const AslipTransitionPlanner planner(params);
  AslipTransitionData d;
  d.initial_state = AslipTransitionPlanner::StandingState(gait_a.aslip, 0.9);
  d.final_state = a.collocation.phases[0].states.col(gait_a.nodes_per_domain - 1);  // left stance, landing at +l
  d.lifting_leg = 1;
  const std::string dir = ::testing::TempDir() + "/aslip_transition_cache_test";
  std::filesystem::remove_all(dir);
  const PlanCache cache(dir);
  const AslipTransition t = planner.Solve(d, &cache);
  CheckTransition(planner, d, t);
  // A second run with the same data starts at once from the cache; other data is another key.
  const AslipTransition again = planner.Solve(d, &cache);
  EXPECT_EQ(again.collocation.nlp.iterations, 0);
  EXPECT_EQ((again.collocation.nlp.x - t.collocation.nlp.x).cwiseAbs().maxCoeff(), 0.0);
  AslipTransitionData other = d;
  other.initial_state = AslipTransitionPlanner::StandingState(gait_a.aslip, 0.89);
  EXPECT_NE(cache.FileFor(planner.CacheKey(other)), cache.FileFor(planner.CacheKey(d)));
  std::filesystem::remove_all(dir);
}

TEST(AslipTransitionPlanner, GaitAToGaitB) {
  AslipPeriodicGaitParams gait_a, gait_b;
  gait_b.step_length = 0.40;
  const AslipPeriodicGait a = AslipPeriodicGaitPlanner(gait_a).Solve(1);
  const AslipPeriodicGait b = AslipPeriodicGaitPlanner(gait_b).Solve(1);
  ASSERT_TRUE(a.success() && b.success());
  AslipTransitionParams params;
  params.bounds = gait_a;
  const AslipTransitionPlanner planner(params);
  // Post-impact DSP state of A: plan leg 0 (trailing, at 0) = left, leg 1 (leading, at l_A) = right.
  AslipTransitionData d;
  d.initial_state = a.collocation.phases[1].states.col(0);
  d.left_foot_x = 0.0;
  d.right_foot_x = gait_a.step_length;
  d.lifting_leg = 0;
  // B's pre-impact state about its stance foot (plan leg 0) = right at l_A: shift x, swap legs.
  const Vec pre = b.collocation.phases[0].states.col(gait_b.nodes_per_domain - 1);
  d.final_state << pre(0) + gait_a.step_length, pre(1), pre(2), pre(3), pre(5), pre(4), pre(7), pre(6);
  // Guess: A's DSP, then B's SSP re-expressed the same way.
  d.dsp_state_guess = a.collocation.phases[1].states;
  d.dsp_duration_guess = gait_a.dsp_duration;
  d.ssp_state_guess = b.collocation.phases[0].states;
  d.ssp_state_guess.row(0).array() += gait_a.step_length;
  d.ssp_state_guess.row(4).swap(d.ssp_state_guess.row(5));
  d.ssp_state_guess.row(6).swap(d.ssp_state_guess.row(7));
  d.ssp_duration_guess = gait_b.ssp_duration;
  CheckTransition(planner, d, planner.Solve(d));
}

TEST(AslipTransitionPlanner, RestLengthBalancesTheStaticLoad) {
  const AslipParams p;
  for (const double r : {0.85, 0.9, 0.93}) {
    const double F = 0.5 * p.mass * p.gravity;
    const double L = AslipRestLengthForForce(p, r, F);
    EXPECT_NEAR(AslipStiffness(p, L) * (L - r), F, 1e-8);
  }
  // Standing: the two vertical legs hold the mass in equilibrium (zero acceleration).
  const Eigen::Matrix<double, 8, 1> x = AslipTransitionPlanner::StandingState(p, 0.9);
  const Eigen::Matrix<double, 8, 1> xdot = AslipDynamics<double>(p, AslipContact{true, true, 0, 0}, Vec(x), Vec::Zero(4));
  EXPECT_LT(xdot.segment<2>(2).norm(), 1e-9);
  EXPECT_THROW(AslipRestLengthForForce(p, -1.0, 100.0), std::invalid_argument);
}

}  // namespace
}  // namespace rome
