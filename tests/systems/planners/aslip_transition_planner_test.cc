// Transitional footed-aSLIP NLP, Eq. (9)-(10): standing → gait A and gait A → gait B. Checks every row and bound to
// 1e-6, free durations inside their bounds, the boundary states, Eq. (10) as a centre of pressure under the foot
// (x_cop − x_ankle = u/G_z ∈ [−L_h, L_t], from the ground reaction recomputed here), the lift-off guard, and forward
// re-integration (RK4) of the footed aSLIP under the planned inputs; and the static force balance behind the standing
// state (AslipRestLengthForForce). The lateral option (a step stance into gait A): the lateral ZMP rows of Eq. (14) as
// a lateral centre of pressure, the point-foot SSP, the DSP stance force floor, and re-integration of the 3D point mass
// with its lateral force from the CoP geometry (G_y = G_z (y − y_cop)/z).
#include "systems/planners/aslip_transition_planner.h"

#include <gtest/gtest.h>

#include "systems/rom/hybrid_linear_inverted_pendulum.h"
#include "tests/common/source_path.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <stdexcept>

namespace rome {
namespace {

using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1>;

// Open-loop RK4 re-integration of both phases of `t` from x0 (100 substeps per interval, inputs linear between nodes):
// f(contact, y, u) is ẏ; returns the largest |error(x, node state)| at the nodes.
template <class Dynamics, class Error>
double ReintegrateRk4(const AslipTransitionData& d, const AslipTransition& t, Vec x, Dynamics f, Error error) {
  double worst = 0.0;
  for (int ph = 0; ph < 2; ++ph) {
    const CollocationPhaseSolution& s = t.collocation.phases[ph];
    const ActuatedSpringLoadedInvertedPendulumContact c = AslipTransitionPlanner::PhaseContact(d, ph);
    const int N = static_cast<int>(s.times.size());
    const double h = s.duration / (N - 1);
    for (int k = 0; k + 1 < N; ++k) {
      const int sub = 100;
      const double dt = h / sub;
      auto u = [&](double tau) { return Vec(s.inputs.col(k) + (s.inputs.col(k + 1) - s.inputs.col(k)) * tau / h); };
      auto g = [&](const Vec& y, double tau) { return Vec(f(c, y, u(tau))); };
      for (int j = 0; j < sub; ++j) {
        const double tt = j * dt;
        const Vec k1 = g(x, tt), k2 = g(x + 0.5 * dt * k1, tt + 0.5 * dt), k3 = g(x + 0.5 * dt * k2, tt + 0.5 * dt),
                  k4 = g(x + dt * k3, tt + dt);
        x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
      worst = std::max(worst, error(x, Vec(s.states.col(k + 1))));
    }
  }
  return worst;
}

// The sagittal aSLIP re-integrated: the worst node error in x and z.
double Reintegrate(const ActuatedSpringLoadedInvertedPendulumParams& p, const AslipTransitionData& d,
                   const AslipTransition& t) {
  return ReintegrateRk4(
      d, t, t.collocation.phases[0].states.col(0),
      [&](const ActuatedSpringLoadedInvertedPendulumContact& c, const Vec& y, const Vec& u) {
        return Vec(AslipDynamics<double>(p, c, y, u));
      },
      [](const Vec& x, const Vec& node) { return (x - node).head(2).cwiseAbs().maxCoeff(); });
}

void CheckTransition(const AslipTransitionPlanner& planner, const AslipTransitionData& d, const AslipTransition& t) {
  const AslipTransitionParams& q = planner.params();
  const ActuatedSpringLoadedInvertedPendulumParams& p = q.bounds.aslip;
  ASSERT_TRUE(t.success()) << t.collocation.nlp.message;
  EXPECT_LE(t.max_constraint_violation, 1e-6);
  EXPECT_LE(t.collocation.max_defect, 1e-6);
  const double Td = t.collocation.phases[0].duration, Ts = t.collocation.phases[1].duration;
  EXPECT_GE(Td, q.min_dsp_duration - 1e-9);
  EXPECT_LE(Td, q.max_dsp_duration + 1e-9);
  EXPECT_GE(Ts, q.min_ssp_duration - 1e-9);
  EXPECT_LE(Ts, q.max_ssp_duration + 1e-9);
  EXPECT_LT((t.collocation.phases[0].states.col(0) - Vec(d.initial_state)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(
      (t.collocation.phases[1].states.col(q.bounds.nodes_per_domain - 1) - Vec(d.final_state)).cwiseAbs().maxCoeff(),
      1e-9);
  const double mg = p.mass * p.gravity;
  for (int ph = 0; ph < 2; ++ph) {
    const Eigen::MatrixXd G = t.GroundReactions(p, d, ph);
    const CollocationPhaseSolution& s = t.collocation.phases[ph];
    const ActuatedSpringLoadedInvertedPendulumContact c = AslipTransitionPlanner::PhaseContact(d, ph);
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
    if (ph == 0) { EXPECT_NEAR(G(2 * d.lifting_leg + 1, G.cols() - 1), 0.0, 1e-6 * mg); }
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
  const std::string dir = rome::test::ScratchDir() + "/aslip_transition_cache_test";
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

// A failure the same problem repeats (here the iteration limit, 5 iterations) is stored in the cache: the second Solve
// returns it without solving (no phases, the stored status and iterations), as a solve without the cache fails; the
// limit is part of the key, so the default limit is another problem, which plans.
TEST(AslipTransitionPlanner, ARepeatableFailureIsCachedAndNotSolvedAgain) {
  AslipPeriodicGaitParams gait_a;
  const AslipPeriodicGait a = AslipPeriodicGaitPlanner(gait_a).Solve(1);
  ASSERT_TRUE(a.success());
  AslipTransitionParams params;
  params.bounds = gait_a;
  params.bounds.max_iterations = 5;
  const AslipTransitionPlanner planner(params);
  AslipTransitionData d;
  d.initial_state = AslipTransitionPlanner::StandingState(gait_a.aslip, 0.9);
  d.final_state = a.collocation.phases[0].states.col(gait_a.nodes_per_domain - 1);
  d.lifting_leg = 1;
  const std::string dir = rome::test::ScratchDir() + "/aslip_transition_failure_cache_test";
  std::filesystem::remove_all(dir);
  const PlanCache cache(dir);
  const AslipTransition t = planner.Solve(d, &cache);
  ASSERT_FALSE(t.success());
  ASSERT_EQ(t.collocation.nlp.status, NlpStatus::kMaxIterations) << t.collocation.nlp.message;
  const AslipTransition again = planner.Solve(d, &cache);
  EXPECT_FALSE(again.success());
  EXPECT_EQ(again.collocation.nlp.status, t.collocation.nlp.status);
  EXPECT_EQ(again.collocation.nlp.iterations, t.collocation.nlp.iterations);
  EXPECT_TRUE(again.collocation.phases.empty());  // not solved
  EXPECT_NE(again.collocation.nlp.message.find("not solved again"), std::string::npos) << again.collocation.nlp.message;
  EXPECT_EQ(planner.Solve(d).collocation.nlp.status, t.collocation.nlp.status);  // the failure repeats without a cache
  AslipTransitionParams full = params;
  full.bounds.max_iterations = gait_a.max_iterations;
  const AslipTransition planned = AslipTransitionPlanner(full).Solve(d, &cache);
  EXPECT_TRUE(planned.success()) << planned.collocation.nlp.message;
  std::filesystem::remove_all(dir);
}

// Gait A's post-impact DSP state to gait B's pre-impact state, with the source gait's DSP and the target's SSP as
// guess.
AslipTransitionData GaitAToBData(const AslipPeriodicGaitParams& gait_a, const AslipPeriodicGaitParams& gait_b) {
  const AslipPeriodicGait a = AslipPeriodicGaitPlanner(gait_a).Solve(1);
  const AslipPeriodicGait b = AslipPeriodicGaitPlanner(gait_b).Solve(1);
  EXPECT_TRUE(a.success() && b.success());
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
  return d;
}

// The largest vertical GRF of any leg on any node, in m g.
double PeakForceFraction(const ActuatedSpringLoadedInvertedPendulumParams& p, const AslipTransitionData& d,
                         const AslipTransition& t) {
  double peak = 0.0;
  for (int ph = 0; ph < 2; ++ph) {
    const Eigen::MatrixXd G = t.GroundReactions(p, d, ph);
    peak = std::max({peak, G.row(1).maxCoeff(), G.row(3).maxCoeff()});
  }
  return peak / (p.mass * p.gravity);
}

TEST(AslipTransitionPlanner, GaitAToGaitB) {
  AslipPeriodicGaitParams gait_a, gait_b;
  gait_b.step_length = 0.40;
  const AslipTransitionData d = GaitAToBData(gait_a, gait_b);
  AslipTransitionParams params;
  params.bounds = gait_a;
  const AslipTransitionPlanner planner(params);
  const AslipTransition t = planner.Solve(d);
  CheckTransition(planner, d, t);

  // max_vertical_force_fraction (ours): with the bound 5 % below the unbounded plan's peak, every leg's vertical GRF
  // (recomputed here from the states and inputs) stays at or below it on every node, and the rest of Eq. (9)-(10)
  // holds.
  const double peak = PeakForceFraction(params.bounds.aslip, d, t);
  ASSERT_GT(peak, 1.1);
  AslipTransitionParams bounded = params;
  bounded.max_vertical_force_fraction = 0.95 * peak;
  const AslipTransitionPlanner bounded_planner(bounded);
  const AslipTransition tb = bounded_planner.Solve(d);
  CheckTransition(bounded_planner, d, tb);
  const double bounded_peak = PeakForceFraction(params.bounds.aslip, d, tb);
  std::printf("peak vertical GRF: %.3f m g unbounded, %.3f m g with the bound %.3f\n", peak, bounded_peak,
              bounded.max_vertical_force_fraction);
  EXPECT_LE(bounded_peak, bounded.max_vertical_force_fraction + 1e-6);
  EXPECT_NE(bounded_planner.CacheKey(d).text(), planner.CacheKey(d).text());
  bounded.max_vertical_force_fraction = 0.5;
  EXPECT_THROW(AslipTransitionPlanner{bounded}, std::invalid_argument);
}

TEST(AslipTransitionPlanner, RestLengthBalancesTheStaticLoad) {
  const ActuatedSpringLoadedInvertedPendulumParams p;
  for (const double r : {0.85, 0.9, 0.93}) {
    const double F = 0.5 * p.mass * p.gravity;
    const double L = AslipRestLengthForForce(p, r, F);
    EXPECT_NEAR(AslipStiffness(p, L) * (L - r), F, 1e-8);
  }
  // Standing: the two vertical legs hold the mass in equilibrium (zero acceleration).
  const Eigen::Matrix<double, 8, 1> x = AslipTransitionPlanner::StandingState(p, 0.9);
  const Eigen::Matrix<double, 8, 1> xdot =
      AslipDynamics<double>(p, ActuatedSpringLoadedInvertedPendulumContact{true, true, 0, 0}, Vec(x), Vec::Zero(4));
  EXPECT_LT(xdot.segment<2>(2).norm(), 1e-9);
  EXPECT_THROW(AslipRestLengthForForce(p, -1.0, 100.0), std::invalid_argument);
}

TEST(AslipTransitionPlanner, StepStanceToGaitAWithTheLateralMotion) {
  AslipPeriodicGaitParams gait_a;
  gait_a.height_min = 0.80;  // the walking diagram's heights
  gait_a.height_max = 0.88;
  const AslipPeriodicGait a = AslipPeriodicGaitPlanner(gait_a).Solve(1);
  ASSERT_TRUE(a.success()) << a.collocation.nlp.message;
  AslipTransitionParams params;
  params.bounds = gait_a;
  params.bounds.aslip.heel_length = 0.02;  // the exoskeleton's sole (0.07, 0.18) less 0.05 m
  params.bounds.aslip.toe_length = 0.13;
  params.min_ssp_duration = gait_a.ssp_duration;
  params.max_ssp_ankle_torque = 0.0;
  params.min_dsp_stance_force_fraction = 0.1;
  params.lateral = true;
  params.foot_width_left_of_ankle = params.foot_width_right_of_ankle = 0.03;
  const AslipTransitionPlanner planner(params);
  const ActuatedSpringLoadedInvertedPendulumParams& p = params.bounds.aslip;
  AslipTransitionData d;
  d.left_foot_x = 0.0;
  d.right_foot_x = -0.4;
  d.initial_state = AslipTransitionPlanner::StandingState(p, 0.84, d.left_foot_x, d.right_foot_x);
  d.final_state = a.collocation.phases[0].states.col(gait_a.nodes_per_domain - 1);
  d.lifting_leg = 1;
  const double W = 0.25;
  d.left_foot_y = W / 2;
  d.right_foot_y = -W / 2;
  const HybridLinearInvertedPendulum hlip(
      {.z0 = a.mean_height, .ssp_duration = gait_a.ssp_duration, .dsp_duration = gait_a.dsp_duration});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(W);
  d.final_lateral_state = Eigen::Vector2d(W / 2 + pre(0), pre(1));
  const AslipTransition t = planner.Solve(d);
  ASSERT_TRUE(t.success()) << t.collocation.nlp.message;
  EXPECT_LE(t.max_constraint_violation, 1e-6);
  const CollocationPhaseSolution &dsp = t.collocation.phases[0], &ssp = t.collocation.phases[1];
  ASSERT_EQ(dsp.states.rows(), 10);
  ASSERT_EQ(dsp.inputs.rows(), 6);
  EXPECT_LT((dsp.states.col(0).head(8) - Vec(d.initial_state)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((dsp.states.col(0).tail(2) - d.initial_lateral_state).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((ssp.states.col(ssp.states.cols() - 1).head(8) - Vec(d.final_state)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((ssp.states.col(ssp.states.cols() - 1).tail(2) - d.final_lateral_state).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GE(ssp.duration, gait_a.ssp_duration - 1e-9);
  const double mg = p.mass * p.gravity, foot_y[2] = {d.left_foot_y, d.right_foot_y};
  for (int ph = 0; ph < 2; ++ph) {
    const CollocationPhaseSolution& s = t.collocation.phases[ph];
    const Eigen::MatrixXd G = t.GroundReactions(p, d, ph);
    const ActuatedSpringLoadedInvertedPendulumContact c = AslipTransitionPlanner::PhaseContact(d, ph);
    for (Eigen::Index k = 0; k < G.cols(); ++k) {
      for (int leg = 0; leg < 2; ++leg) {
        const double Gz = G(2 * leg + 1, k), ux = s.inputs(4 + leg, k);
        if (!c.in_contact(leg)) {
          EXPECT_EQ(ux, 0.0);
          continue;
        }
        if (ph == 1) { EXPECT_NEAR(s.inputs(2 + leg, k), 0.0, 1e-9) << "point-foot SSP, node " << k; }
        if (ph == 0 && leg != d.lifting_leg) {
          EXPECT_GE(Gz, 0.1 * mg - 1e-6 * mg) << "DSP stance force floor, node " << k;
        }
        if (Gz > 0.01 * mg) {  // lateral CoP from u_x = −G_z y_cop (spec §2.3), inside [−W2, W1]
          const double y_cop = -ux / Gz;
          EXPECT_GE(y_cop, -0.03 - 1e-6) << "phase " << ph << " node " << k << " leg " << leg;
          EXPECT_LE(y_cop, 0.03 + 1e-6) << "phase " << ph << " node " << k << " leg " << leg;
        }
      }
    }
  }
  // Re-integration (RK4, inputs linear between nodes) of the 3D point mass: sagittal aSLIP, and laterally each leg's
  // GRF points from its CoP (y_i + y_cop,i) to the mass, G_y = G_z (y − y_i − y_cop,i)/z with y_cop,i = −u_x,i/G_z.
  const double worst_y = ReintegrateRk4(
      d, t, dsp.states.col(0),
      [&](const ActuatedSpringLoadedInvertedPendulumContact& c, const Vec& y, const Vec& ui) {
        Vec out(10);
        out.head(8) = AslipDynamics<double>(p, c, Vec(y.head(8)), Vec(ui.head(4)));
        double fy = 0.0;
        for (int leg = 0; leg < 2; ++leg) {
          if (!c.in_contact(leg)) continue;
          const ActuatedSpringLoadedInvertedPendulumLeg<double> g =
              AslipLegState<double>(p, y, leg, c.foot_x(leg), ui(2 + leg));
          const double y_cop = g.grf_z != 0.0 ? -ui(4 + leg) / g.grf_z : 0.0;
          fy += g.grf_z * (y(8) - foot_y[leg] - y_cop) / y(1);
        }
        out(8) = y(9);
        out(9) = fy / p.mass;
        return out;
      },
      [](const Vec& x, const Vec& node) { return std::abs(x(8) - node(8)); });
  // Stated bound: y within 2 cm over the open-loop 1.4 s (trapezoid defects, amplified by the SSP's divergence).
  EXPECT_LT(worst_y, 2e-2);
  std::printf("T_DSP %.3f s, T_SSP %.3f s, %d iterations, %.0f ms, lateral re-integration %.2g m\n", dsp.duration,
              ssp.duration, t.collocation.nlp.iterations, 1e3 * t.collocation.nlp.wall_time, worst_y);
}

TEST(AslipTransitionPlanner, StepStanceStandingStateIsInStaticEquilibrium) {
  const ActuatedSpringLoadedInvertedPendulumParams p;
  const Eigen::Matrix<double, 8, 1> x = AslipTransitionPlanner::StandingState(p, 0.84, 0.0, -0.4);
  EXPECT_NEAR(x(0), -0.2, 1e-12);
  // Sum of the two legs' ground reactions = (0, m g): zero acceleration of the mass.
  double gx = 0.0, gz = 0.0;
  for (int leg = 0; leg < 2; ++leg) {
    const ActuatedSpringLoadedInvertedPendulumLeg<double> g =
        AslipLegState<double>(p, Vec(x), leg, leg == 0 ? 0.0 : -0.4, 0.0);
    gx += g.grf_x;
    gz += g.grf_z;
    EXPECT_NEAR(g.grf_z, 0.5 * p.mass * p.gravity, 1e-6);
  }
  EXPECT_NEAR(gx, 0.0, 1e-6);
  EXPECT_NEAR(gz, p.mass * p.gravity, 1e-6);
}

}  // namespace
}  // namespace rome
