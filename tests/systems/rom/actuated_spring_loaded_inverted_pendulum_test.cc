// aSLIP (walking paper, Appendix): K(L), D(L) against the spec's table; the Cartesian form against the paper's polar
// form (Appendix 1, with the spec's r1 fix) written out independently here; the corrected touchdown map (Appendix 2)
// against the continuity of the mass velocity; energy conservation with D = 0 and fixed L; the ankle-torque sign; and
// the hybrid block's touchdown and lift-off guards.
#include "systems/rom/actuated_spring_loaded_inverted_pendulum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/rom/actuated_spring_loaded_inverted_pendulum_system.h"

namespace rome {
namespace {

using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1>;

TEST(ActuatedSpringLoadedInvertedPendulum, StiffnessAndDampingMatchSpecTable) {
  // Spec §2.1 reference values (c = 2.28), rounded there to 1 N/m and 0.1 N s/m.
  const ActuatedSpringLoadedInvertedPendulumParams p;
  const double L[] = {0.6, 0.7, 0.8, 0.85, 0.9, 0.92, 0.95, 1.0};
  const double K[] = {6569, 7165, 8378, 9510, 11165, 12005, 13483, 16610};
  const double D[] = {98.2, 107.1, 125.4, 142.3, 167.1, 179.6, 201.8, 248.5};
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(AslipStiffness(p, L[i]), K[i], 0.5) << "L = " << L[i];
    EXPECT_NEAR(AslipDamping(p, L[i]), D[i], 0.05) << "L = " << L[i];
  }
  // c = 1 row of the spec.
  ActuatedSpringLoadedInvertedPendulumParams cassie;
  cassie.spring_scale = 1.0;
  EXPECT_NEAR(AslipStiffness(cassie, 0.9), 4897, 0.5);
  EXPECT_NEAR(AslipDamping(cassie, 1.0), 109.0, 0.05);
  // Static compression for m = 76 kg at L = 0.9 m is 0.067 m and sqrt(K/m) = 12.1 rad/s.
  EXPECT_NEAR(p.mass * p.gravity / AslipStiffness(p, 0.9), 0.067, 5e-4);
  EXPECT_NEAR(std::sqrt(AslipStiffness(p, 0.9) / p.mass), 12.1, 0.05);
}

// The paper's polar form, Appendix 1 (SSP with the r → r1 fix; DSP as printed), leg angle e = (−sin q, cos q).
struct Polar {
  double r, q, rd, qd;
};
Polar ToPolar(const Vec& x, double foot_x) {
  const double dx = x(0) - foot_x, dz = x(1);
  Polar P;
  P.r = std::hypot(dx, dz);
  P.q = std::atan2(-dx, dz);
  const Eigen::Vector2d e(-std::sin(P.q), std::cos(P.q)), eq(-std::cos(P.q), -std::sin(P.q));
  P.rd = e.dot(x.segment<2>(2));
  P.qd = eq.dot(x.segment<2>(2)) / P.r;
  return P;
}
// Cartesian mass acceleration from polar rdd, qdd about a pivot.
Eigen::Vector2d PolarToCartesian(const Polar& P, double rdd, double qdd) {
  const Eigen::Vector2d e(-std::sin(P.q), std::cos(P.q)), eq(-std::cos(P.q), -std::sin(P.q));
  return (rdd - P.r * P.qd * P.qd) * e + (2 * P.rd * P.qd + P.r * qdd) * eq;
}

TEST(ActuatedSpringLoadedInvertedPendulum, CartesianFormEqualsPolarAppendix) {
  const ActuatedSpringLoadedInvertedPendulumParams p;
  const double m = p.mass, g = p.gravity;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    Vec x(8), u(4);
    x << 0.1 * U(rng), 0.9 + 0.05 * U(rng), 0.6 + 0.3 * U(rng), 0.3 * U(rng), 0.95 + 0.04 * U(rng),
        0.93 + 0.04 * U(rng), 0.3 * U(rng), 0.3 * U(rng);
    u << 5 * U(rng), 5 * U(rng), 80 * U(rng), 80 * U(rng);
    const double f1 = -0.15 + 0.05 * U(rng), f2 = 0.2 + 0.05 * U(rng);
    const Polar P1 = ToPolar(x, f1), P2 = ToPolar(x, f2);
    auto force = [&](const Polar& P, double L, double Ld) {
      return AslipStiffness(p, L) * (L - P.r) + AslipDamping(p, L) * (Ld - P.rd);
    };
    const double F1 = force(P1, x(4), x(6)), F2 = force(P2, x(5), x(7));
    const double u1 = u(2), u2 = u(3);
    // SSP, leg 1 = left at f1.
    {
      const double rdd1 = F1 / m - g * std::cos(P1.q) + P1.r * P1.qd * P1.qd;
      const double qdd1 = (-2 * P1.qd * P1.rd + g * std::sin(P1.q) + u1 / (m * P1.r)) / P1.r;
      const Eigen::Vector2d expected = PolarToCartesian(P1, rdd1, qdd1);
      ActuatedSpringLoadedInvertedPendulumContact c{true, false, f1, f2};
      const Eigen::Matrix<double, 8, 1> xdot = AslipDynamics<double>(p, c, x, u);
      EXPECT_NEAR((xdot.segment<2>(2) - expected).norm(), 0.0, 1e-12) << "SSP trial " << trial;
      EXPECT_EQ(xdot(6), u(0));
      EXPECT_EQ(xdot(4), x(6));
    }
    // DSP: both polar charts must give the Cartesian acceleration.
    {
      const double dq = P1.q - P2.q;
      const double rdd1 =
          (F1 + F2 * std::cos(dq)) / m - g * std::cos(P1.q) + P1.r * P1.qd * P1.qd + u2 * std::sin(dq) / (m * P2.r);
      const double qdd1 = (-2 * P1.qd * P1.rd + g * std::sin(P1.q) - F2 * std::sin(dq) / m) / P1.r +
                          std::cos(dq) * u2 / (m * P1.r * P2.r) + u1 / (m * P1.r * P1.r);
      const double rdd2 =
          (F2 + F1 * std::cos(dq)) / m - g * std::cos(P2.q) + P2.r * P2.qd * P2.qd - u1 * std::sin(dq) / (m * P1.r);
      const double qdd2 = (-2 * P2.qd * P2.rd + g * std::sin(P2.q) + F1 * std::sin(dq) / m) / P2.r +
                          std::cos(dq) * u1 / (m * P1.r * P2.r) + u2 / (m * P2.r * P2.r);
      ActuatedSpringLoadedInvertedPendulumContact c{true, true, f1, f2};
      const Eigen::Matrix<double, 8, 1> xdot = AslipDynamics<double>(p, c, x, u);
      EXPECT_NEAR((xdot.segment<2>(2) - PolarToCartesian(P1, rdd1, qdd1)).norm(), 0.0, 1e-12) << "DSP leg 1 " << trial;
      EXPECT_NEAR((xdot.segment<2>(2) - PolarToCartesian(P2, rdd2, qdd2)).norm(), 0.0, 1e-12) << "DSP leg 2 " << trial;
    }
  }
}

TEST(ActuatedSpringLoadedInvertedPendulum, CorrectedTouchdownMapKeepsTheMassVelocity) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Vec x(8);
    x << 0.1 * U(rng), 0.9, 0.6 + 0.3 * U(rng), 0.3 * U(rng), 0.95, 0.95, 0, 0;
    const Polar P1 = ToPolar(x, -0.1), P2 = ToPolar(x, 0.25);
    const Eigen::Vector2d v2 = AslipPolarImpactMap(P1.r, P1.q, P1.rd, P1.qd, P2.r, P2.q);
    EXPECT_NEAR(v2(0), P2.rd, 1e-13);
    EXPECT_NEAR(v2(1), P2.qd, 1e-13);
    // Cartesian velocity rebuilt from leg 2's chart equals ṗ.
    const Eigen::Vector2d e2(-std::sin(P2.q), std::cos(P2.q)), eq2(-std::cos(P2.q), -std::sin(P2.q));
    EXPECT_NEAR((v2(0) * e2 + P2.r * v2(1) * eq2 - x.segment<2>(2)).norm(), 0.0, 1e-13);
  }
}

// Classic RK4 step of ẋ = f(x).
template <class F>
Vec Rk4(const F& f, const Vec& x, double h) {
  const Vec k1 = f(x), k2 = f(x + 0.5 * h * k1), k3 = f(x + 0.5 * h * k2), k4 = f(x + h * k3);
  return x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
}

TEST(ActuatedSpringLoadedInvertedPendulum, EnergyConservedWithoutDampingAtFixedRestLength) {
  ActuatedSpringLoadedInvertedPendulumParams p;
  p.d4 = p.d2 = p.d1 = p.d0 = 0.0;  // D = 0
  for (const bool dsp : {false, true}) {
    ActuatedSpringLoadedInvertedPendulumContact c{true, dsp, -0.05, 0.3};
    Vec x(8), u = Vec::Zero(4);
    x << 0.02, 0.9, 0.5, -0.1, 0.97, 0.98, 0.0, 0.0;  // L̇ = 0 and L̈ = 0: L fixed
    auto energy = [&](const Vec& s) {
      double E = p.mass * p.gravity * s(1) + 0.5 * p.mass * s.segment<2>(2).squaredNorm();
      for (int leg = 0; leg < 2; ++leg) {
        if (!c.in_contact(leg)) continue;
        const ActuatedSpringLoadedInvertedPendulumLeg<double> g = AslipLegState<double>(p, s, leg, c.foot_x(leg), 0.0);
        E += 0.5 * AslipStiffness(p, s(4 + leg)) * g.spring * g.spring;  // ∫ K ds with K constant
      }
      return E;
    };
    const double E0 = energy(x);
    auto f = [&](const Vec& s) { return Vec(AslipDynamics<double>(p, c, s, u)); };
    double worst = 0.0;
    for (int k = 0; k < 2000; ++k) {  // 0.2 s
      x = Rk4(f, x, 1e-4);
      worst = std::max(worst, std::abs(energy(x) - E0));
    }
    EXPECT_LT(worst / E0, 1e-10) << (dsp ? "DSP" : "SSP");
    EXPECT_GT(std::abs(x(1) - 0.9), 1e-3);  // it moved
  }
}

TEST(ActuatedSpringLoadedInvertedPendulum, PositiveAnkleTorqueOnAVerticalLegPushesTheMassBack) {
  const ActuatedSpringLoadedInvertedPendulumParams p;
  Vec x(8), u(4);
  x << 0.0, 0.9, 0, 0, 0.9, 0.9, 0, 0;
  u << 0, 0, 50, 0;
  const Eigen::Matrix<double, 8, 1> xdot =
      AslipDynamics<double>(p, ActuatedSpringLoadedInvertedPendulumContact{true, false, 0, 0}, x, u);
  EXPECT_NEAR(xdot(2), -50 / (0.9 * p.mass), 1e-12);
  // COP: x_cop − x_pivot = u / G_z (moment of G about the pivot is u).
  x(0) = 0.1;
  x(1) = 0.85;
  x(4) = 0.95;
  const ActuatedSpringLoadedInvertedPendulumLeg<double> g = AslipLegState<double>(p, x, 0, 0.0, 50.0);
  EXPECT_NEAR(x(0) * g.grf_z - x(1) * g.grf_x, 50.0, 1e-10);
}

TEST(ActuatedSpringLoadedInvertedPendulumSystem, TouchdownAndLiftoffGuardsFireWhereTheyShould) {
  ActuatedSpringLoadedInvertedPendulumSystemParams params;
  params.initial_mode = "left_stance";
  params.initial_state << -0.1, 0.9, 0.7, 0.0, 0.97, 0.93, 0.0, 0.0;
  params.initial_left_foot_x = 0.0;
  params.initial_right_foot_x = -0.3;
  DiagramBuilder builder;
  auto* aslip = builder.AddSystem(std::make_unique<ActuatedSpringLoadedInvertedPendulumSystem>("aslip", params));
  builder.AddSystem(std::make_unique<ConstantVectorSource>("ldd", Eigen::Vector2d::Zero()));
  builder.AddSystem(std::make_unique<ConstantVectorSource>("foothold", Eigen::VectorXd::Constant(1, 0.3)));
  builder.Connect("ldd", "y", "aslip", "leg_length_acceleration");
  builder.Connect("foothold", "y", "aslip", "next_foothold");
  auto diagram = builder.Build();
  SimulatorConfig config;
  config.relative_tolerance = 1e-10;
  config.absolute_tolerance = 1e-12;
  Simulator sim(*diagram, config);
  // Touchdown: run until the first event.
  int events = 0;
  for (double t = 0.01; t < 1.0 && events == 0; t += 0.01) {
    ASSERT_TRUE(sim.AdvanceTo(t).ok());
    events = static_cast<int>(sim.statistics().events.size());
  }
  ASSERT_EQ(events, 1);
  EXPECT_EQ(sim.statistics().events[0].guard, "touchdown");
  const LeafContext& c = diagram->GetSubsystemContext(*aslip, sim.get_context());
  EXPECT_EQ(c.discrete_state()(1), 0.3);
  // Lift-off of the trailing (left) leg when its vertical GRF reaches 0.
  for (double t = sim.get_context().time() + 0.001; t < 2.0 && events == 1; t += 0.001) {
    ASSERT_TRUE(sim.AdvanceTo(t).ok());
    events = static_cast<int>(sim.statistics().events.size());
  }
  ASSERT_EQ(events, 2);
  EXPECT_EQ(sim.statistics().events[1].guard, "liftoff");
  EXPECT_EQ(c.mode(), aslip->right_stance_mode());
}

}  // namespace
}  // namespace rome
