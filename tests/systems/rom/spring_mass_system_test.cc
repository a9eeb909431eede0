// SpringMassSystem / SpringMassModel: the published K(L), D(L) against the spec's table (walking paper, Appendix 3);
// the simulated ROM settles at the closed-form static deflection m g/(n_legs K(L)); energy conserved with D = 0 and
// fixed L; n_legs legs under m move exactly as one leg under m/n_legs; flight is ballistic.
#include "systems/rom/spring_mass_system.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "framework/simulator.h"
#include "tests/common/allocation_counter.h"

namespace rome {
namespace {

SimulatorConfig Tight() {
  SimulatorConfig config;
  config.relative_tolerance = 1e-11;
  config.absolute_tolerance = 1e-12;
  return config;
}

TEST(SpringMassModel, PublishedStiffnessMatchesSpecTable) {
  // Spec hopping.md A1.2 [D]: values of the walking paper's quartic (c = 1) computed independently.
  const double L[] = {0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  const double K[] = {2526.8, 2881.2, 3142.7, 3674.8, 4897.0, 7285.0};
  const double D[] = {37.75, 43.06, 46.99, 54.98, 73.28, 109.00};
  const SpringMassModel model;
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(model.Stiffness(L[i]), K[i], 0.06) << "L = " << L[i];
    EXPECT_NEAR(model.Damping(L[i]), D[i], 0.006) << "L = " << L[i];
  }
}

TEST(SpringMassModel, BadParametersAreNamed) {
  SpringMassParams p;
  p.mass = -1.0;
  try {
    SpringMassModel m(p);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mass = -1"), std::string::npos) << e.what();
  }
  p = {};
  p.n_legs = 0;
  EXPECT_THROW(SpringMassModel m(p), std::invalid_argument);
  EXPECT_THROW(ParseLegStiffnessVariant("stiff"), std::invalid_argument);
  EXPECT_EQ(ParseLegStiffnessVariant("identified"), LegStiffnessVariant::kIdentified);
  EXPECT_THROW(SpringMassModel().StaticDeflection(0.2), std::domain_error);  // K(0.2) < 0
}

TEST(SpringMassSystem, SettlesAtStaticDeflection) {
  // Released with the spring uncompressed (s = 0) at rest, L fixed: the damped oscillation must settle at
  // s = m g / (n_legs K(L)) (spec A6 acceptance 2: 4.44 cm at L = 0.8 m and 3.92 cm at 0.85 m, m = 33.3 kg, 2 legs).
  for (double L : {0.8, 0.85}) {
    SpringMassSystemParams params;
    params.initial_state = Eigen::Vector4d(L, 0.0, L, 0.0);
    SpringMassSystem system("rom", params);
    Simulator sim(system, Tight());
    system.FixInputPort(sim.get_mutable_context(), 0, Eigen::VectorXd::Zero(1));
    ASSERT_TRUE(sim.AdvanceTo(20.0).ok());
    const Eigen::VectorXd z = system.EvalOutput(sim.get_context(), "state");
    const double s = z(2) - z(0);
    const double expected = 33.3 * 9.81 / (2.0 * system.model().Stiffness(L));
    EXPECT_NEAR(s, expected, 1e-7) << "L = " << L;
    EXPECT_NEAR(s, L == 0.8 ? 0.0444 : 0.0392, 5e-5);  // spec's numbers
    EXPECT_NEAR(system.EvalOutput(sim.get_context(), "leg_force")[0], 33.3 * 9.81, 1e-4);
    std::printf("published K: L = %.2f m, settled s = %.5f m, m g/(2K) = %.5f m\n", L, s, expected);
  }
}

TEST(SpringMassSystem, EnergyConservedWithoutDampingAndFixedLegLength) {
  SpringMassSystemParams params;
  params.model.leg.damping = {};  // D = 0
  params.initial_state = Eigen::Vector4d(0.76, -0.3, 0.8, 0.0);
  SpringMassSystem system("rom", params);
  Simulator sim(system, Tight());
  system.FixInputPort(sim.get_mutable_context(), 0, Eigen::VectorXd::Zero(1));
  auto total = [&] { return system.EvalOutput(sim.get_context(), "energy").sum(); };
  const double E0 = total();
  double worst = 0.0, min_s = 1.0;
  for (int k = 1; k <= 200; ++k) {
    ASSERT_TRUE(sim.AdvanceTo(0.01 * k).ok());
    worst = std::max(worst, std::abs(total() - E0));
    const Eigen::VectorXd z = system.EvalOutput(sim.get_context(), "state");
    min_s = std::min(min_s, z(2) - z(0));
  }
  EXPECT_GT(min_s, 0.0);  // stays in stance: the conservative spring-mass oscillator
  EXPECT_LT(worst, 1e-7 * E0);
  // Passive period 2π / sqrt(n_legs K / m) (spec A6: 14.9 rad/s at L = 0.8 m): velocity returns after one period.
  const double omega = std::sqrt(2.0 * system.model().Stiffness(0.8) / 33.3);
  EXPECT_NEAR(omega, 14.9, 0.05);
  std::printf("energy drift over 2 s (D = 0, L fixed): %.3e J of %.3f J; omega = %.3f rad/s\n", worst, E0, omega);
}

TEST(SpringMassSystem, TwoLegsUnderMassEqualOneLegUnderHalfMass) {
  SpringMassSystemParams two;
  two.initial_state = Eigen::Vector4d(0.8, -0.5, 0.8, 0.3);
  SpringMassSystemParams one = two;
  one.model.n_legs = 1;
  one.model.mass = two.model.mass / 2.0;
  SpringMassSystem a("two", two), b("one", one);
  Simulator sa(a, Tight()), sb(b, Tight());
  a.FixInputPort(sa.get_mutable_context(), 0, Eigen::VectorXd::Constant(1, -2.0));
  b.FixInputPort(sb.get_mutable_context(), 0, Eigen::VectorXd::Constant(1, -2.0));
  ASSERT_TRUE(sa.AdvanceTo(0.5).ok());
  ASSERT_TRUE(sb.AdvanceTo(0.5).ok());
  EXPECT_LT((a.EvalOutput(sa.get_context(), "state") - b.EvalOutput(sb.get_context(), "state")).norm(), 1e-8);
}

TEST(SpringMassSystem, FlightIsBallistic) {
  // Mass above the leg (s < 0) moving up: F = 0, x(t) = x0 + v0 t − g t²/2 until it comes back to the leg.
  SpringMassSystemParams params;
  params.initial_state = Eigen::Vector4d(0.9, 2.0, 0.85, 0.0);
  SpringMassSystem system("rom", params);
  Simulator sim(system, Tight());
  system.FixInputPort(sim.get_mutable_context(), 0, Eigen::VectorXd::Zero(1));
  ASSERT_TRUE(sim.AdvanceTo(0.3).ok());
  const Eigen::VectorXd z = system.EvalOutput(sim.get_context(), "state");
  EXPECT_NEAR(z(0), 0.9 + 2.0 * 0.3 - 0.5 * 9.81 * 0.09, 1e-8);
  EXPECT_NEAR(z(1), 2.0 - 9.81 * 0.3, 1e-8);
  EXPECT_EQ(system.EvalOutput(sim.get_context(), "leg_force")[0], 0.0);
}

TEST(SpringMassSystem, FlowAndOutputsAllocateNothing) {
  SpringMassSystem system("rom", {});
  auto context = system.CreateDefaultContext();
  auto& leaf = static_cast<LeafContext&>(*context);
  system.FixInputPort(leaf, 0, Eigen::VectorXd::Constant(1, 1.5));
  Eigen::VectorXd xdot(4);
  system.CalcTimeDerivatives(leaf, &xdot);
  system.EvalOutput(leaf, "energy");
  system.EvalOutput(leaf, "leg_force");
  long allocations = 0;
  for (int k = 0; k < 20; ++k) {
    leaf.get_mutable_continuous_state()(0) = 0.75 + 0.001 * k;
    leaf.InvalidateCache();
    allocations += test::CountAllocations([&] {
      system.CalcTimeDerivatives(leaf, &xdot);
      system.EvalOutput(leaf, "leg_force");
      system.EvalOutput(leaf, "energy");
    });
  }
  EXPECT_EQ(allocations, 0);
}

TEST(SpringMassSystem, RefusesANonFiniteInitialStateOrANonPositiveLegLength) {
  const auto message = [](const Eigen::Vector4d& z) {
    SpringMassSystemParams params;
    params.initial_state = z;
    try {
      SpringMassSystem system("hopper", params);
    } catch (const std::runtime_error& e) { return std::string(e.what()); }
    return std::string("accepted");
  };
  EXPECT_EQ(message({0.78, NAN, 0.8, 0.0}),
            "system 'hopper': params.initial_state[1] (xdot [m/s]) = nan must be finite");
  EXPECT_EQ(message({0.78, 0.0, 0.0, 0.0}),
            "system 'hopper': params.initial_state[2] (L [m]) = 0 must be finite and > 0");
  EXPECT_EQ(message({0.78, 0.0, 0.8, 0.0}), "accepted");
}

}  // namespace
}  // namespace rome
