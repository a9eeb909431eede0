// H-LIP (walking paper Sec. III-B, ref [14]) and footed H-LIP (Sec. IV-B): λ, σ1, σ2 and the deadbeat gain against
// the spec's reference numbers; the step-to-step matrices against a fine numerical integration of the hybrid flow;
// (A + B K)² = 0; the P1 and P2 orbits repeat; the exact ZOH against the spec numbers and a matrix exponential; the
// hybrid block against the same closed forms.
#include "systems/rom/hybrid_linear_inverted_pendulum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include <unsupported/Eigen/MatrixFunctions>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/rom/hybrid_linear_inverted_pendulum_system.h"

namespace rome {
namespace {

TEST(HybridLinearInvertedPendulum, ReferenceNumbersOfTheSpec) {
  struct Case {
    double z0, Ts, Td, lambda, sigma1, sigma2, K2;
  };
  const Case cases[] = {{0.75, 0.3, 0.05, 3.6166, 7.3082, 1.7898, 0.3978},
                        {0.34, 0.4, 0.0, 5.3715, 6.7901, 4.2493, 0.1913},
                        {0.9, 0.4, 0.1, 3.3015, 5.7064, 1.9101, 0.4494}};
  for (const Case& c : cases) {
    const HybridLinearInvertedPendulum h({.z0 = c.z0, .ssp_duration = c.Ts, .dsp_duration = c.Td});
    EXPECT_NEAR(h.lambda(), c.lambda, 5e-5);
    EXPECT_NEAR(h.sigma1(), c.sigma1, 5e-5);
    EXPECT_NEAR(h.sigma2(), c.sigma2, 5e-5);
    EXPECT_EQ(h.DeadbeatGain()(0), 1.0);
    EXPECT_NEAR(h.DeadbeatGain()(1), c.K2, 5e-5);
    const Eigen::Matrix2d closed = h.StepToStepA() + h.StepToStepB() * h.DeadbeatGain();
    EXPECT_LT((closed * closed).cwiseAbs().maxCoeff(), 1e-14) << "z0 " << c.z0;
  }
}

// Fine RK4 of the hybrid H-LIP over one step from a pre-impact state: DSP (ÿ = 0) for T_DSP, reset Eq. (7), SSP.
Eigen::Vector2d IntegrateStep(const HybridLinearInvertedPendulumParams& p, Eigen::Vector2d x, double w) {
  const double l2 = p.gravity / p.z0;
  auto f = [&](const Eigen::Vector2d& s, bool ssp) { return Eigen::Vector2d(s(1), ssp ? l2 * s(0) : 0.0); };
  auto run = [&](double T, bool ssp) {
    const int n = 20000;
    const double h = T / n;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d k1 = f(x, ssp), k2 = f(x + 0.5 * h * k1, ssp), k3 = f(x + 0.5 * h * k2, ssp),
                            k4 = f(x + h * k3, ssp);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
  };
  run(p.dsp_duration, false);
  x(0) -= w;
  run(p.ssp_duration, true);
  return x;
}

TEST(HybridLinearInvertedPendulum, StepToStepMatricesMatchNumericalIntegration) {
  const HybridLinearInvertedPendulumParams p{.z0 = 0.9, .ssp_duration = 0.4, .dsp_duration = 0.1};
  const HybridLinearInvertedPendulum h(p);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-0.3, 0.3);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector2d x(U(rng), U(rng));
    const double w = U(rng);
    EXPECT_NEAR((IntegrateStep(p, x, w) - (h.StepToStepA() * x + h.StepToStepB() * w)).norm(), 0.0, 1e-11);
  }
}

TEST(HybridLinearInvertedPendulum, P2AndP1OrbitsRepeat) {
  const HybridLinearInvertedPendulumParams p{.z0 = 0.9, .ssp_duration = 0.4, .dsp_duration = 0.1};
  const HybridLinearInvertedPendulum h(p);
  // Spec §7 example: W_step = 0.25 m.
  const Eigen::Vector2d x = h.P2PreImpactState(0.25);
  EXPECT_NEAR(x(0), -0.11410, 5e-6);
  EXPECT_NEAR(x(1), -0.21795, 5e-6);
  const double w = h.P2Step(x);
  EXPECT_NEAR(w, -0.25, 1e-14);
  // Post-impact (start of the next SSP) position relative to the new stance foot is +0.11410.
  EXPECT_NEAR(x(0) + p.dsp_duration * x(1) - w, 0.11410, 5e-6);
  // Two steps with alternating w: x → −x → x, by the step-to-step map and by numerical integration.
  const Eigen::Vector2d x1 = h.StepToStepA() * x + h.StepToStepB() * w;
  EXPECT_NEAR((x1 + x).norm(), 0.0, 1e-12);
  EXPECT_NEAR((h.StepToStepA() * x1 - h.StepToStepB() * w - x).norm(), 0.0, 1e-12);
  EXPECT_NEAR((IntegrateStep(p, x, w) + x).norm(), 0.0, 1e-11);
  // Global sway about ±0.032 m: the mass position in the world over one SSP, feet at ±W/2.
  double sway = 0.0;
  const Eigen::Vector2d start(x(0) + p.dsp_duration * x(1) - w, x(1));  // relative to the new (right) stance foot
  for (int k = 0; k <= 400; ++k) {
    const Eigen::Vector2d s = h.SingleSupportTransition(p.ssp_duration * k / 400) * start;
    sway = std::max(sway, std::abs(s(0) - 0.125));
  }
  EXPECT_NEAR(sway, 0.032, 5e-4);
  // Every point on the σ2 line through the P2 point is a P2 orbit (Eq. (8)): x → −x with w = 2p + T_DSP v.
  for (double p0 : {-0.05, -0.2}) {
    const Eigen::Vector2d y(p0, h.sigma2() * p0);
    EXPECT_NEAR((h.StepToStepA() * y + h.StepToStepB() * h.P2Step(y) + y).norm(), 0.0, 1e-12);
  }
  // P1: x → x with constant step.
  const Eigen::Vector2d q = h.P1PreImpactState(0.2);
  EXPECT_NEAR((IntegrateStep(p, q, 0.2) - q).norm(), 0.0, 1e-11);
}

TEST(HybridLinearInvertedPendulum, RejectsBadParameters) {
  EXPECT_THROW(HybridLinearInvertedPendulum({.z0 = 0.0}), std::invalid_argument);
  EXPECT_THROW(HybridLinearInvertedPendulum({.z0 = 0.9, .ssp_duration = -1}), std::invalid_argument);
  EXPECT_THROW(HybridLinearInvertedPendulum({.z0 = 0.9, .ssp_duration = 0.4, .dsp_duration = -0.1}),
               std::invalid_argument);
  EXPECT_THROW(HybridLinearInvertedPendulum().P2PreImpactState(0.0), std::invalid_argument);
  try {
    HybridLinearInvertedPendulum({.z0 = -2});
  } catch (const std::invalid_argument& e) { EXPECT_NE(std::string(e.what()).find("z0"), std::string::npos); }
}

TEST(FootedLinearInvertedPendulum, ZeroOrderHoldMatchesSpecAndMatrixExponential) {
  const double m = 76, z0 = 0.9, T = 0.02, lambda = std::sqrt(9.81 / z0);  // 3.3015 1/s
  const FootedLinearInvertedPendulumStep ssp = FootedLinearInvertedPendulumDiscretization(lambda, T, m, z0, true);
  Eigen::Matrix2d A;
  A << 1.002181, 0.0200145, 0.218158, 1.002181;
  EXPECT_LT((ssp.A - A).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(ssp.B(0), 2.92504e-6, 1e-11);
  EXPECT_NEAR(ssp.B(1), 2.92610e-4, 1e-9);
  for (const bool single : {true, false}) {
    // exp([[A_c, B_c], [0, 0]] T) = [[A, B], [0, 1]].
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    M(0, 1) = 1;
    M(1, 0) = single ? lambda * lambda : 0.0;
    M(1, 2) = 1 / (m * z0);
    for (const double t : {0.02, 0.3}) {
      const Eigen::Matrix3d E = (M * t).exp();
      const FootedLinearInvertedPendulumStep s = FootedLinearInvertedPendulumDiscretization(lambda, t, m, z0, single);
      EXPECT_LT((E.topLeftCorner<2, 2>() - s.A).cwiseAbs().maxCoeff(), 1e-13);
      EXPECT_LT((E.topRightCorner<2, 1>() - s.B).cwiseAbs().maxCoeff(), 1e-16);
    }
  }
  // DSP equals the paper's P = [T²/(2 m z0); T/(m z0)].
  const FootedLinearInvertedPendulumStep dsp = FootedLinearInvertedPendulumDiscretization(lambda, T, m, z0, false);
  EXPECT_DOUBLE_EQ(dsp.B(0), T * T / (2 * m * z0));
  EXPECT_THROW(FootedLinearInvertedPendulumDiscretization(lambda, -1, m, z0, true), std::invalid_argument);
}

TEST(HybridLinearInvertedPendulumSystem, BlockFollowsTheP2Orbit) {
  const HybridLinearInvertedPendulumParams hp{.z0 = 0.9, .ssp_duration = 0.4, .dsp_duration = 0.1};
  const HybridLinearInvertedPendulum h(hp);
  const Eigen::Vector2d pre = h.P2PreImpactState(0.25);  // end of a left stance
  HybridLinearInvertedPendulumSystemParams params;
  params.hlip = hp;
  // Start at the beginning of a right stance (after the DSP following the left stance).
  params.initial_state = Eigen::Vector2d(pre(0) + hp.dsp_duration * pre(1) - h.P2Step(pre), pre(1));
  params.initial_stance_side = -1;
  params.initial_stance_foot_y = -0.125;
  DiagramBuilder builder;
  auto* hlip = builder.AddSystem(std::make_unique<HybridLinearInvertedPendulumSystem>("hlip", params));
  // A right stance ends with a step to the left (+W); the next one to the right. Use a square wave of w through a
  // constant per run segment.
  auto* step = builder.AddSystem(std::make_unique<ConstantVectorSource>("w", Eigen::VectorXd::Constant(1, 0.25)));
  (void)step;
  builder.Connect("w", "y", "hlip", "step");
  auto diagram = builder.Build();
  SimulatorConfig config;
  config.relative_tolerance = 1e-12;
  config.absolute_tolerance = 1e-13;
  Simulator sim(*diagram, config);
  ASSERT_TRUE(sim.AdvanceTo(0.4 - 1e-9).ok());
  const LeafContext& c = diagram->GetSubsystemContext(*hlip, sim.get_context());
  // End of the right stance: −(p, v) of the left-stance pre-impact state.
  EXPECT_NEAR((c.continuous_state() + pre).norm(), 0.0, 1e-7);
  ASSERT_TRUE(sim.AdvanceTo(0.5 + 1e-6).ok());  // through the DSP and the D→S reset with w = +0.25
  EXPECT_EQ(c.mode(), hlip->single_support_mode());
  EXPECT_NEAR(c.discrete_state()(1), 0.125, 1e-12);
  EXPECT_EQ(c.discrete_state()(2), 1.0);
  EXPECT_NEAR(c.continuous_state()(0), -params.initial_state(0), 1e-5);
  EXPECT_NEAR(hlip->EvalOutput(c, "com_y")(0), 0.125 + c.continuous_state()(0), 1e-15);
}

TEST(HybridLinearInvertedPendulumSystem, FootedBlockMatchesZeroOrderHold) {
  const HybridLinearInvertedPendulumParams hp{.z0 = 0.9, .ssp_duration = 0.4, .dsp_duration = 0.1};
  HybridLinearInvertedPendulumSystemParams params;
  params.hlip = hp;
  params.footed = true;
  params.initial_state = Eigen::Vector2d(-0.05, 0.1);
  DiagramBuilder builder;
  auto* hlip = builder.AddSystem(std::make_unique<HybridLinearInvertedPendulumSystem>("hlip", params));
  builder.AddSystem(std::make_unique<ConstantVectorSource>("w", Eigen::VectorXd::Constant(1, -0.25)));
  builder.AddSystem(std::make_unique<ConstantVectorSource>("u", Eigen::Vector2d(-30.0, 20.0)));
  builder.Connect("w", "y", "hlip", "step");
  builder.Connect("u", "y", "hlip", "ankle_roll_torque");
  auto diagram = builder.Build();
  SimulatorConfig config;
  config.relative_tolerance = 1e-12;
  config.absolute_tolerance = 1e-13;
  Simulator sim(*diagram, config);
  ASSERT_TRUE(sim.AdvanceTo(0.3).ok());
  const LeafContext& c = diagram->GetSubsystemContext(*hlip, sim.get_context());
  const HybridLinearInvertedPendulum h(hp);
  const FootedLinearInvertedPendulumStep s = FootedLinearInvertedPendulumDiscretization(h.lambda(), 0.3, 76, 0.9, true);
  // Left stance (side +1) uses u_L = −30 N m.
  EXPECT_NEAR((c.continuous_state() - (s.A * params.initial_state + s.B * -30.0)).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace rome
