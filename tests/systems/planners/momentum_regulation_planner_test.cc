// MomentumRegulationPlanner: Eq. (17)-(18), (25)-(27) against the LIP closed form, and the step-to-step map
// of the LIP walker under momentum regulation (a ROM orbit that repeats).
#include "systems/planners/momentum_regulation_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rome {
namespace {

TEST(MomentumRegulationPlanner, ImpactMapOfThePlannedInputGivesLdes) {
  const MomentumRegulationPlanner planner({.target_orbital_energy = 0.4, .impact_fraction = 0.6});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> length(0.2, 0.8), height(-0.2, 0.25), px(-0.2, 0.0), energy(0.05, 0.8),
      zdes(0.7, 0.9);
  const LinearInvertedPendulum lip({.z0 = 0.8});
  for (int trial = 0; trial < 200; ++trial) {
    MomentumRegulationInput in;
    in.step_length = length(rng);
    in.step_height = height(rng);
    in.p_com_x = px(rng);
    in.p_com_z = 0.8 + in.step_height / in.step_length * in.p_com_x;
    in.L_y = *lip.MomentumOnOrbit(energy(rng), in.p_com_x);  // enough energy to reach ε l
    in.pdot_com_x = in.L_y / 0.8 + 0.05;
    in.pre_impact_com_height = zdes(rng) + in.step_height * 0.6;
    const MomentumRegulationPlan plan = planner.Plan(in);
    ASSERT_EQ(plan.status & ~static_cast<std::uint32_t>(MomentumRegulationPlan::kTimeToImpactClamped), 0u)
        << plan.status;
    // Eq. (17) with the predicted pre-impact state (x⁻ = ε l, L⁻ = L̂⁻, ṗ^{x−} = current ṗ^x) and u = u_des.
    const Eigen::Vector2d post = MomentumRegulationPlanner::ImpactMap(
        plan.pre_impact_position, plan.L_pre_impact, in.pdot_com_x, plan.u_des, in.step_length, in.step_height);
    EXPECT_NEAR(post[1], plan.L_des, 1e-13);
    EXPECT_NEAR(post[0], (0.6 - 1.0) * in.step_length, 1e-15);
    // The post-impact orbital energy with the post-impact LIP height z0⁺ is E*.
    const LinearInvertedPendulum lip_plus({.z0 = plan.post_impact_height});
    EXPECT_NEAR(lip_plus.OrbitalEnergy(post), 0.4, 1e-12);
  }
}

TEST(MomentumRegulationPlanner, ReproducesTheMomentumOfAKnownLipOrbit) {
  // A LIP orbit on the virtual slope of a step (l, h): post-impact state ((ε−1) l, L⁺), z0 constant.
  const double z0 = 0.82, eps = 0.6, L_plus = 0.9;
  for (const auto& [l, h] : {std::pair{0.4, 0.0}, std::pair{0.5, 0.2}, std::pair{0.4, -0.1}, std::pair{0.7, 0.0}}) {
    const LinearInvertedPendulum lip({.z0 = z0});
    const Eigen::Vector2d post((eps - 1) * l, L_plus);
    const double E_star = lip.OrbitalEnergy(post);
    const MomentumRegulationPlanner planner({.target_orbital_energy = E_star, .impact_fraction = eps});
    // Pre-impact COM height relative to the stance foot, on the virtual slope at x = ε l.
    const double p_z_minus = LinearInvertedPendulum::ComHeightOnSlope(eps * l, z0, l, h);
    EXPECT_NEAR(planner.DesiredPostImpactMomentum(l, h, p_z_minus), L_plus, 1e-13) << "l = " << l << ", h = " << h;

    // Eq. (25) and (27) from a mid-step state of that orbit predict its pre-impact momentum and impact time.
    const Eigen::Vector2d mid = lip.Flow(post, 0.12);
    MomentumRegulationInput in;
    in.p_com_x = mid[0];
    in.p_com_z = LinearInvertedPendulum::ComHeightOnSlope(mid[0], z0, l, h);
    in.pdot_com_x = mid[1] / z0;
    in.L_y = mid[1];
    in.step_length = l;
    in.step_height = h;
    in.pre_impact_com_height = p_z_minus;
    const MomentumRegulationPlan plan = planner.Plan(in);
    ASSERT_TRUE(plan.ok());
    EXPECT_NEAR(plan.slope_adjusted_height, z0, 1e-14);
    const TimeToImpact T = lip.TimeToReach(eps * l, post);
    ASSERT_TRUE(T.ok());
    EXPECT_NEAR(plan.time_to_impact, T.time_s - 0.12, 1e-12);
    const Eigen::Vector2d pre = lip.Flow(post, T.time_s);
    EXPECT_NEAR(pre[0], eps * l, 1e-12);
    EXPECT_NEAR(plan.L_pre_impact, pre[1], 1e-12);
  }
}

// One step of the LIP walker: flow from the post-impact state to x = ε l, then Eq. (17) with u decided by
// the planner at phase `decision_fraction` of the step (0 = right after impact, 1 = at impact).
Eigen::Vector2d StepMap(const LinearInvertedPendulum& lip, const MomentumRegulationPlanner& planner,
                        const Eigen::Vector2d& post, double l, double h, double decision_fraction) {
  const double eps = planner.params().impact_fraction;
  const TimeToImpact T = lip.TimeToReach(eps * l, post);
  EXPECT_TRUE(T.ok());
  const Eigen::Vector2d decision = lip.Flow(post, decision_fraction * T.time_s);
  MomentumRegulationInput in;
  in.p_com_x = decision[0];
  in.p_com_z = LinearInvertedPendulum::ComHeightOnSlope(decision[0], lip.z0(), l, h);
  in.pdot_com_x = decision[1] / lip.z0();
  in.L_y = decision[1];
  in.step_length = l;
  in.step_height = h;
  in.pre_impact_com_height = LinearInvertedPendulum::ComHeightOnSlope(eps * l, lip.z0(), l, h);
  const double u = planner.Plan(in).u_des;
  const Eigen::Vector2d pre = lip.Flow(post, T.time_s);
  return MomentumRegulationPlanner::ImpactMap(pre[0], pre[1], pre[1] / lip.z0(), u, l, h);
}

TEST(MomentumRegulationPlanner, FlatGroundGaitIsAFixedPointOfTheStepToStepMap) {
  const LinearInvertedPendulum lip({.z0 = 0.8});
  const MomentumRegulationPlanner planner({.target_orbital_energy = 0.3, .impact_fraction = 0.6});
  const double l = 0.4;
  const double L_star = planner.DesiredPostImpactMomentum(l, 0.0, 0.8);
  // From a perturbed start (not on the orbit, not at the post-impact position), any decision phase.
  for (double phase : {0.0, 0.5, 1.0}) {
    Eigen::Vector2d post(-0.25, 0.8);
    for (int k = 0; k < 12; ++k) {
      const Eigen::Vector2d next = StepMap(lip, planner, post, l, 0.0, phase);
      if (k >= 1) { EXPECT_NEAR(next[1], post[1], 1e-9) << "step " << k << " does not repeat"; }
      post = next;
    }
    EXPECT_NEAR(post[1], L_star, 1e-12);
    EXPECT_NEAR(post[0], -0.4 * l, 1e-15);
    EXPECT_NEAR(lip.OrbitalEnergy(post), 0.3, 1e-12);
  }
}

TEST(MomentumRegulationPlanner, StairGaitConvergesToAFixedPointWhenDecidedEarly) {
  // On stairs, u_des decided at the start of the step uses ṗ^x then instead of ṗ^{x−}; the error term h(ṗ^x − ṗ^{x−})
  // makes the step-to-step map a contraction L⁺_{k+1} = L_des + (h/z0)(L⁺_k − L⁻(L⁺_k)) instead of deadbeat.
  const LinearInvertedPendulum lip({.z0 = 0.8});
  const MomentumRegulationPlanner planner({.target_orbital_energy = 0.4, .impact_fraction = 0.6});
  const double l = 0.5, h = 0.2;
  const double L_des =
      planner.DesiredPostImpactMomentum(l, h, LinearInvertedPendulum::ComHeightOnSlope(0.6 * l, 0.8, l, h));
  // Fixed point of the scalar map by bisection: L = L_des + (h/z0)(L − sqrt(z0 g ((εl)² − ((ε−1)l)²) + L²)).
  const double c = 0.8 * 9.81 * ((0.6 * l) * (0.6 * l) - (0.4 * l) * (0.4 * l));
  auto residual = [&](double L) { return L_des + h / 0.8 * (L - std::sqrt(c + L * L)) - L; };
  double lo = 0.1, hi = 2.0;
  for (int i = 0; i < 200; ++i) ((residual(0.5 * (lo + hi)) > 0) ? lo : hi) = 0.5 * (lo + hi);
  const double L_fixed = 0.5 * (lo + hi);
  EXPECT_GT(std::abs(L_fixed - L_des), 1e-3);  // not deadbeat

  Eigen::Vector2d post(-0.3, 0.9);  // perturbed start
  std::vector<double> errors;
  for (int k = 0; k < 40; ++k) {
    post = StepMap(lip, planner, post, l, h, 0.0);
    errors.push_back(std::abs(post[1] - L_fixed));
  }
  EXPECT_LT(errors.back(), 1e-12);
  EXPECT_GT(errors[1], 1e-4);  // it really started away from the orbit
  for (int k = 2; k < 10; ++k) EXPECT_LT(errors[k], 0.5 * errors[k - 1]) << "no contraction at step " << k;
  // After convergence the post-impact momentum repeats.
  const Eigen::Vector2d again = StepMap(lip, planner, post, l, h, 0.0);
  EXPECT_NEAR(again[1], post[1], 1e-12);
  // Deciding at the impact itself is deadbeat to L_des.
  EXPECT_NEAR(StepMap(lip, planner, post, l, h, 1.0)[1], L_des, 1e-12);
}

TEST(MomentumRegulationPlanner, ABoundedUdesShedsExcessMomentumOverSeveralSteps) {
  // Flat ground, decided at the impact (deadbeat when unbounded). From a start far faster than the E* orbit, the
  // unbounded planner reaches L* in one impact with u < u_min; bounded, every impact sheds exactly l u_min (Eq. (17),
  // h = 0) until the remainder fits, then the gait repeats on the E* orbit.
  const LinearInvertedPendulum lip({.z0 = 0.8});
  const double l = 0.4, u_min = -1.0;
  const MomentumRegulationPlanner unbounded({.target_orbital_energy = 0.3, .impact_fraction = 0.6});
  const MomentumRegulationPlanner bounded(
      {.target_orbital_energy = 0.3, .impact_fraction = 0.6, .min_pre_impact_vertical_velocity_mps = u_min});
  const double L_star = unbounded.DesiredPostImpactMomentum(l, 0.0, 0.8);
  const Eigen::Vector2d start(-0.4 * l, 1.6);
  EXPECT_NEAR(StepMap(lip, unbounded, start, l, 0.0, 1.0)[1], L_star, 1e-12);

  Eigen::Vector2d post = start;
  int bounded_impacts = 0;
  for (int k = 0; k < 12; ++k) {
    const TimeToImpact T = lip.TimeToReach(0.6 * l, post);
    ASSERT_TRUE(T.ok());
    const Eigen::Vector2d pre = lip.Flow(post, T.time_s);
    const Eigen::Vector2d next = StepMap(lip, bounded, post, l, 0.0, 1.0);
    if (pre[1] + l * u_min > L_star + 1e-12) {  // the bound binds: exactly l u_min shed
      EXPECT_NEAR(next[1], pre[1] + l * u_min, 1e-12) << "step " << k;
      ++bounded_impacts;
    } else {
      EXPECT_NEAR(next[1], L_star, 1e-12) << "step " << k;
    }
    EXPECT_LT(next[1], pre[1]) << "step " << k;  // never gains momentum on the way down to L*
    post = next;
  }
  EXPECT_GE(bounded_impacts, 2);
  EXPECT_NEAR(lip.OrbitalEnergy(post), 0.3, 1e-12);

  // The status bit, and no change where Eq. (26) stays above the bound.
  MomentumRegulationInput in;
  in.step_length = l;
  in.p_com_x = 0.6 * l;
  in.p_com_z = 0.8;
  in.pre_impact_com_height = 0.8;
  in.L_y = 1.6;
  in.pdot_com_x = 1.6 / 0.8;
  MomentumRegulationPlan plan = bounded.Plan(in);
  EXPECT_EQ(plan.u_des, u_min);
  EXPECT_TRUE(plan.status & MomentumRegulationPlan::kPreImpactVelocityClamped);
  EXPECT_LT(unbounded.Plan(in).u_des, u_min);
  in.L_y = L_star + 0.05;
  in.pdot_com_x = in.L_y / 0.8;
  plan = bounded.Plan(in);
  EXPECT_FALSE(plan.status & MomentumRegulationPlan::kPreImpactVelocityClamped);
  EXPECT_EQ(plan.u_des, unbounded.Plan(in).u_des);

  for (double bad : {0.5, std::nan("")}) {
    try {
      MomentumRegulationPlanner({.min_pre_impact_vertical_velocity_mps = bad});
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("min_pre_impact_vertical_velocity_mps"), std::string::npos) << e.what();
    }
  }
}

TEST(MomentumRegulationPlanner, ReportsPredictionFailures) {
  const MomentumRegulationPlanner planner({.target_orbital_energy = 0.4,
                                           .impact_fraction = 0.6,
                                           .min_time_to_impact_s = 0.02,
                                           .max_time_to_impact_s = 1.5});
  MomentumRegulationInput in;
  in.step_length = 0.5;
  in.p_com_z = 0.8;
  in.pre_impact_com_height = 0.8;
  // Far behind the foot with little momentum: falls back, never reaches ε l.
  in.p_com_x = -0.3;
  in.L_y = 0.1;
  in.pdot_com_x = 0.1 / 0.8;
  MomentumRegulationPlan plan = planner.Plan(in);
  EXPECT_EQ(plan.status, static_cast<std::uint32_t>(MomentumRegulationPlan::kTimeToImpactInsufficientEnergy));
  EXPECT_EQ(plan.time_to_impact, 1.5);
  // Ahead of ε l, slow: Eq. (25) has a negative radicand (L̂⁻ clamped to 0) and ε l is out of reach.
  in.p_com_x = 0.4;
  plan = planner.Plan(in);
  EXPECT_TRUE(plan.status & MomentumRegulationPlan::kPreImpactMomentumClamped);
  EXPECT_TRUE(plan.status & MomentumRegulationPlan::kTimeToImpactInsufficientEnergy);
  EXPECT_EQ(plan.L_pre_impact, 0.0);
  // Past the pre-impact position (late impact): T̂ = min.
  in.p_com_x = 0.35;
  in.L_y = 0.6;
  plan = planner.Plan(in);
  EXPECT_EQ(plan.status, static_cast<std::uint32_t>(MomentumRegulationPlan::kTimeToImpactPassed));
  EXPECT_EQ(plan.time_to_impact, 0.02);
  // Bad input names the quantity.
  in.step_length = 0.0;
  try {
    planner.Plan(in);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("step length"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MomentumRegulationPlanner({.impact_fraction = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
