// SpringMassJumpPlanner / SpringMassLandingPlanner (hopping paper Eq. (14)-(16)): every constraint recomputed from
// the returned nodes (Hermite–Simpson defects with SpringMassModel, bounds, lift-off force, Eq. (14), rest conditions)
// to 1e-6; a forward RK4 re-integration of the ROM under the planned L̈(t) reproduces x_N and ẋ_N to 1e-3; the landing
// ends at rest with F = m g and stays there; the warm-started re-solve converges; the apex rise H for the paper's
// 0.423 s air time against the ballistic closed form.
#include "systems/planners/spring_mass_hop_planner.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "systems/rom/cassie_leg_stiffness.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kStandingLegLength = 0.85;  // [m] ≈ L(q_knee = −1.2 rad), Cassie's nominal pose

SpringMassParams Rom(LegStiffnessVariant variant) {
  SpringMassParams p;
  if (variant == LegStiffnessVariant::kIdentified) {
    static const MultibodyModel model =
        MultibodyModel::Load(rome::test::SourcePath("robots/cassie/cassie.urdf"), "", {.euler_floating_base = true});
    static const SpringMassParams identified = CassieSpringMassParams(model, LegStiffnessVariant::kIdentified);
    p = identified;
  }
  return p;
}

// RK4 of the ROM from z0 under v(t) = the plan's first-order-hold L̈, over [0, T] (steps per collocation interval).
Eigen::Vector4d Rk4(const SpringMassModel& rom, const SpringMassPlan& plan, double t_end, int steps) {
  Eigen::Vector4d z = plan.InitialState();
  const double h = t_end / steps;
  auto v = [&](double t) { return plan.LegLengthAcceleration(std::min(t, plan.duration)); };
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    const Eigen::Vector4d k1 = rom.Derivative(z, v(t));
    const Eigen::Vector4d k2 = rom.Derivative(z + 0.5 * h * k1, v(t + 0.5 * h));
    const Eigen::Vector4d k3 = rom.Derivative(z + 0.5 * h * k2, v(t + 0.5 * h));
    const Eigen::Vector4d k4 = rom.Derivative(z + h * k3, v(t + h));
    z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return z;
}

double MaxDefect(const SpringMassModel& rom, const SpringMassPlan& plan) {
  double worst = 0.0;
  for (int k = 0; k + 1 < plan.states.cols(); ++k) {
    const double h = plan.times(k + 1) - plan.times(k);
    // Hermite–Simpson: midpoint state from the cubic through (z_k, f_k), (z_{k+1}, f_{k+1}), midpoint input averaged.
    const Eigen::Vector4d f0 = rom.Derivative(plan.states.col(k), plan.inputs(k));
    const Eigen::Vector4d f1 = rom.Derivative(plan.states.col(k + 1), plan.inputs(k + 1));
    const Eigen::Vector4d zc = 0.5 * (plan.states.col(k) + plan.states.col(k + 1)) + h / 8.0 * (f0 - f1);
    const Eigen::Vector4d fc = rom.Derivative(zc, 0.5 * (plan.inputs(k) + plan.inputs(k + 1)));
    const Eigen::Vector4d d = plan.states.col(k + 1) - plan.states.col(k) - h / 6.0 * (f0 + 4.0 * fc + f1);
    worst = std::max(worst, d.cwiseAbs().maxCoeff());
  }
  return worst;
}

void ExpectLegBounds(const SpringMassPlan& plan, double min_L, double max_L, double max_speed, double max_acc) {
  for (int k = 0; k < plan.states.cols(); ++k) {
    EXPECT_GE(plan.states(2, k), min_L - 1e-6);
    EXPECT_LE(plan.states(2, k), max_L + 1e-6);
    EXPECT_LE(std::abs(plan.states(3, k)), max_speed + 1e-6);
    EXPECT_LE(std::abs(plan.inputs(k)), max_acc + 1e-6);
  }
}

class SpringMassHop : public ::testing::TestWithParam<LegStiffnessVariant> {};

TEST_P(SpringMassHop, JumpSatisfiesConstraintsAndReintegrates) {
  const SpringMassParams params = Rom(GetParam());
  const SpringMassModel rom(params);
  SpringMassJumpParams jp;
  jp.apex_rise = 0.20;
  const SpringMassJumpPlanner planner(params, jp);
  const Eigen::Vector4d z0 = rom.StaticState(kStandingLegLength);
  const SpringMassPlan plan = planner.Solve(z0);
  ASSERT_TRUE(plan.success()) << plan.message;
  EXPECT_LT(plan.max_violation, 1e-6);
  // Independent recomputation of each constraint from the nodes.
  EXPECT_LT(MaxDefect(rom, plan), 1e-6);
  EXPECT_LT((plan.InitialState() - z0).norm(), 1e-9);
  EXPECT_GE(plan.leg_force.minCoeff(), -1e-6);
  EXPECT_NEAR(rom.LegForce(plan.FinalState()), 0.0, 1e-6);
  const Eigen::Vector4d zN = plan.FinalState();
  EXPECT_NEAR(zN(0) + zN(1) * zN(1) / (2 * 9.81) - zN(0), jp.apex_rise, 1e-6);  // Eq. (14), x_des = x_N + H
  ExpectLegBounds(plan, jp.min_leg_length, jp.max_leg_length, jp.max_leg_speed, jp.max_leg_acceleration);
  EXPECT_GE(plan.duration, jp.min_duration - 1e-9);
  EXPECT_LE(plan.duration, jp.max_duration + 1e-9);
  // Forward RK4 (200 steps per interval) under the planned L̈(t).
  const Eigen::Vector4d z_rk4 = Rk4(rom, plan, plan.duration, 200 * jp.num_intervals);
  EXPECT_NEAR(z_rk4(0), zN(0), 1e-3);
  EXPECT_NEAR(z_rk4(1), zN(1), 1e-3);
  std::printf(
      "[%s] jump: T = %.4f s, x0 = %.4f m, x_N = %.4f m, xdot_N = %.4f m/s, L_N = %.4f m, %d iterations, "
      "%.1f ms, violation %.2e, defect %.2e; RK4 error x %.2e m, xdot %.2e m/s\n",
      ToString(GetParam()).c_str(), plan.duration, z0(0), zN(0), zN(1), zN(2), plan.iterations, 1e3 * plan.solve_time_s,
      plan.max_violation, MaxDefect(rom, plan), std::abs(z_rk4(0) - zN(0)), std::abs(z_rk4(1) - zN(1)));
}

TEST_P(SpringMassHop, LandingEndsAtRestAndResolvesWarm) {
  const SpringMassParams params = Rom(GetParam());
  const SpringMassModel rom(params);
  const Eigen::Vector4d z_stand = rom.StaticState(kStandingLegLength);
  SpringMassJumpParams jp;
  jp.apex_rise = 0.20;
  const SpringMassPlan jump = SpringMassJumpPlanner(params, jp).Solve(z_stand);
  ASSERT_TRUE(jump.success()) << jump.message;
  const SpringMassFlight flight = PredictFlight(rom, jump.FinalState());
  SpringMassLandingParams lp;
  lp.rest_height = z_stand(0);
  SpringMassLandingPlanner planner(params, lp);
  const SpringMassPlan plan = planner.Solve(flight.touchdown_state);
  ASSERT_TRUE(plan.success()) << plan.message;
  EXPECT_LT(plan.max_violation, 1e-6);
  EXPECT_LT(MaxDefect(rom, plan), 1e-6);
  const double W = params.mass * params.gravity;
  const Eigen::Vector4d zN = plan.FinalState();
  EXPECT_NEAR(zN(0), lp.rest_height, 1e-6);
  EXPECT_NEAR(zN(1), 0.0, 1e-6);
  EXPECT_NEAR(zN(3), 0.0, 1e-6);
  EXPECT_NEAR(rom.LegForce(zN), W, 1e-6 * W);  // F = m g
  EXPECT_NEAR(plan.inputs(plan.inputs.size() - 1), 0.0, 1e-6);
  for (int k = 1; k < plan.leg_force.size(); ++k) EXPECT_GE(plan.leg_force(k), lp.min_force_fraction * W - 1e-6);
  EXPECT_LE((plan.states.row(2) - plan.states.row(0)).maxCoeff(), lp.max_spring_compression + 1e-6);
  ExpectLegBounds(plan, lp.min_leg_length, lp.max_leg_length, lp.max_leg_speed, lp.max_leg_acceleration);
  // RK4 to T reproduces the end state, and with L held after T the mass stays at rest (an equilibrium of the ROM).
  const Eigen::Vector4d z_rk4 = Rk4(rom, plan, plan.duration, 200 * lp.num_intervals);
  EXPECT_NEAR(z_rk4(0), zN(0), 1e-3);
  EXPECT_NEAR(z_rk4(1), zN(1), 1e-3);
  const Eigen::Vector4d z_later = Rk4(rom, plan, plan.duration + 0.5, 200 * lp.num_intervals + 5000);
  EXPECT_NEAR(z_later(0), lp.rest_height, 2e-3);
  EXPECT_NEAR(z_later(1), 0.0, 2e-2);
  std::printf(
      "[%s] landing: touchdown xdot = %.4f m/s, T = %.4f s, L_N = %.4f m, %d iterations, %.1f ms, violation "
      "%.2e; RK4 error x %.2e m, xdot %.2e m/s\n",
      ToString(GetParam()).c_str(), flight.touchdown_state(1), plan.duration, zN(2), plan.iterations,
      1e3 * plan.solve_time_s, plan.max_violation, std::abs(z_rk4(0) - zN(0)), std::abs(z_rk4(1) - zN(1)));
  // Re-solve at "touchdown" from a measured post-impact state that differs from the prediction.
  Eigen::Vector4d measured = flight.touchdown_state;
  measured(1) *= 0.9;
  measured(0) -= 0.01;
  const SpringMassPlan warm = planner.Resolve(measured);
  ASSERT_TRUE(warm.success()) << warm.message;
  EXPECT_LT(warm.max_violation, 1e-6);
  EXPECT_LT((warm.InitialState() - measured).norm(), 1e-9);
  EXPECT_NEAR(rom.LegForce(warm.FinalState()), W, 1e-6 * W);
  SpringMassLandingPlanner cold_planner(params, lp);
  const SpringMassPlan cold = cold_planner.Solve(measured);
  ASSERT_TRUE(cold.success()) << cold.message;
  EXPECT_NEAR(warm.cost, cold.cost, 1e-3 * cold.cost);  // same local optimum
  std::printf("[%s] landing re-solve: warm %d iterations %.1f ms, cold %d iterations %.1f ms\n",
              ToString(GetParam()).c_str(), warm.iterations, 1e3 * warm.solve_time_s, cold.iterations,
              1e3 * cold.solve_time_s);
}

TEST_P(SpringMassHop, ApexRiseForPaperAirTime) {
  const SpringMassParams params = Rom(GetParam());
  const SpringMassModel rom(params);
  SpringMassPlan plan;
  const double H = ApexRiseForAirTime(params, {}, rom.StaticState(kStandingLegLength), 0.423, &plan);
  const SpringMassFlight flight = PredictFlight(rom, plan.FinalState());
  EXPECT_NEAR(flight.air_time, 0.423, 1e-5);
  // Ballistic closed form from and back to one height: H = g t² / 8 = 0.2194 m. The ROM lands when x returns to
  // L(T), which lies above the lift-off height x_N when the spring is still compressed at lift-off
  // (K s_N = −D ṡ_N > 0), so H is larger by about (L_N − x_N) / 2 ... (L_N − x_N).
  const double lift = plan.FinalState()(2) - plan.FinalState()(0);
  EXPECT_GE(H, 9.81 * 0.423 * 0.423 / 8.0 - 1e-6);
  EXPECT_LE(H, 9.81 * 0.423 * 0.423 / 8.0 + lift + 1e-3);
  // Air time by simulation of the ballistic flight with a fine explicit step, independent of PredictFlight.
  const double dt = 1e-6;
  double x = plan.FinalState()(0), v = plan.FinalState()(1), t = 0.0;
  const double L = plan.FinalState()(2);
  while (!(x <= L && v < 0.0)) {
    v -= 9.81 * dt;
    x += v * dt;
    t += dt;
  }
  EXPECT_NEAR(t, 0.423, 1e-4);
  std::printf(
      "[%s] apex rise for 0.423 s air time: H = %.5f m (ballistic g t^2/8 = %.5f m), lift-off x_N = %.4f m, "
      "L_N = %.4f m, xdot_N = %.4f m/s, apex %.4f m\n",
      ToString(GetParam()).c_str(), H, 9.81 * 0.423 * 0.423 / 8.0, plan.FinalState()(0), L, plan.FinalState()(1),
      flight.apex_height);
}

TEST(SpringMassHopPlanner, DefaultApexRiseGivesPaperAirTimeWithIdentifiedLegs) {
  const SpringMassParams params = Rom(LegStiffnessVariant::kIdentified);
  const SpringMassModel rom(params);
  const SpringMassPlan plan = SpringMassJumpPlanner(params, {}).Solve(rom.StaticState(kStandingLegLength));
  ASSERT_TRUE(plan.success()) << plan.message;
  EXPECT_NEAR(PredictFlight(rom, plan.FinalState()).air_time, 0.423, 1e-3);
}

TEST(SpringMassHopPlanner, BadInputIsNamed) {
  SpringMassJumpParams jp;
  jp.apex_rise = -0.1;
  try {
    SpringMassJumpPlanner planner({}, jp);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("apex_rise = -0.1"), std::string::npos) << e.what();
  }
  const SpringMassJumpPlanner planner({}, {});
  EXPECT_THROW(planner.Solve(Eigen::Vector4d(0.4, 0, 0.45, 0)), std::invalid_argument);  // L below 0.6 m
  SpringMassLandingParams lp;
  lp.rest_height = 0.3;
  EXPECT_THROW(SpringMassLandingPlanner({}, lp), std::invalid_argument);
  EXPECT_THROW(PredictFlight(SpringMassModel(), Eigen::Vector4d(0.8, -1.0, 0.8, 0.0)), std::domain_error);
}

INSTANTIATE_TEST_SUITE_P(Variants, SpringMassHop,
                         ::testing::Values(LegStiffnessVariant::kPublished, LegStiffnessVariant::kIdentified),
                         [](const auto& info) { return ToString(info.param); });

}  // namespace
}  // namespace rome
