// LqrController: balances a cart-pole about the upright in closed loop with the Simulator; the linearisation it is
// built from and its output law against hand-derived values.
#include "systems/controllers/lqr_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "framework/diagram.h"
#include "framework/linearize.h"
#include "framework/simulator.h"
#include "tests/systems/controllers/riccati_references.h"

namespace rome {
namespace {

// Cart-pole, point mass m_p on a massless rod of length l, cart of mass m_c on a frictionless rail.
// x = (p, θ, ṗ, θ̇) with θ from the upright (counter-clockwise), u = f [N] on the cart. With D = m_c + m_p sin²θ:
//   p̈ = (f + m_p sin θ (l θ̇² − g cos θ)) / D,
//   θ̈ = ((m_c + m_p) g sin θ − f cos θ − m_p l θ̇² sin θ cos θ) / (l D).
class CartPole final : public LeafSystem {
 public:
  static constexpr double m_c = 1.0, m_p = 0.3, l = 0.6, g = 9.81;
  CartPole() : LeafSystem("cart_pole") {
    DeclareContinuousState(4);
    DeclareInputPort("f", 1);
    DeclareOutputPort(
        "x", 4, [](const LeafContext& c, Eigen::VectorXd* x) { *x = c.continuous_state(); }, Feedthrough::None());
  }
  // Jacobians at the upright with f = 0 (first-order terms of the equations above).
  static Eigen::Matrix4d UprightA() {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    A(0, 2) = A(1, 3) = 1;
    A(2, 1) = -m_p * g / m_c;
    A(3, 1) = (m_c + m_p) * g / (l * m_c);
    return A;
  }
  static Eigen::Vector4d UprightB() { return Eigen::Vector4d(0, 0, 1 / m_c, -1 / (l * m_c)); }

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    const Eigen::VectorXd& x = c.continuous_state();
    const double f = EvalInput(c, 0)[0], s = std::sin(x[1]), co = std::cos(x[1]), w = x[3];
    const double D = m_c + m_p * s * s;
    xdot->resize(4);
    *xdot << x[2], w, (f + m_p * s * (l * w * w - g * co)) / D,
        ((m_c + m_p) * g * s - f * co - m_p * l * w * w * s * co) / (l * D);
  }
};

Eigen::MatrixXd Weights() { return Eigen::Vector4d(10, 10, 1, 1).asDiagonal(); }

TEST(LqrController, LinearisedCartPoleMatchesHandDerivedMatrices) {
  CartPole plant;
  auto context = plant.CreateDefaultLeafContext();
  plant.FixInputPort(*context, 0, Eigen::VectorXd::Zero(1));
  const LinearSystemMatrices lin = Linearize(plant, *context, "f", "x");
  // Truncation h²/6 · |∂³f| with h = ε^(1/3) and |∂³f| ≲ 100 here, round-off ε |f| / h with f = 0: below 1e-8.
  EXPECT_LT((lin.A - CartPole::UprightA()).cwiseAbs().maxCoeff(), 1e-8) << lin.A;
  EXPECT_LT((lin.B - CartPole::UprightB()).cwiseAbs().maxCoeff(), 1e-8) << lin.B;
  EXPECT_LT((lin.C - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(lin.D.cwiseAbs().maxCoeff(), 1e-12);
}

// The convenience function (Linearize + CARE) against two references built on the hand-derived (A, B) and not on
// ROME's Riccati solver: S from the Hamiltonian's stable invariant subspace (Eigen's eigensolver) and the CARE
// residual written out; and K = R⁻¹BᵀS.
TEST(LqrController, ConvenienceGainMatchesHamiltonianReference) {
  CartPole plant;
  auto context = plant.CreateDefaultLeafContext();
  plant.FixInputPort(*context, 0, Eigen::VectorXd::Zero(1));
  const Eigen::MatrixXd R = Eigen::MatrixXd::Constant(1, 1, 0.5);
  const LinearQuadraticRegulatorResult from_system = LinearQuadraticRegulator(plant, *context, Weights(), R, "f");
  const Eigen::MatrixXd A = CartPole::UprightA(), B = CartPole::UprightB();
  const Eigen::MatrixXd S_ref = HamiltonianStableSubspaceSolution(A, B, Weights(), R);
  const Eigen::MatrixXd K_ref = R.inverse() * B.transpose() * S_ref;
  EXPECT_LT(RelativeCareResidual(A, B, Weights(), R, S_ref), 1e-9);
  // The linearisation differs from the exact matrices by ≲ 1e-9; S and K move by about that times their condition.
  EXPECT_LT(RelativeCareResidual(A, B, Weights(), R, from_system.S), 1e-7);
  EXPECT_LT((from_system.S - S_ref).norm() / S_ref.norm(), 1e-6);
  EXPECT_LT((from_system.K - K_ref).norm() / K_ref.norm(), 1e-6);
  // The block built from the exact (A, B) agrees to the Riccati solver's accuracy.
  const LqrController exact("lqr", A, B, Weights(), R, Eigen::Vector4d::Zero(), Eigen::VectorXd::Zero(1));
  EXPECT_LT((exact.S() - S_ref).norm() / S_ref.norm(), 1e-10);
  EXPECT_LT((exact.K() - K_ref).norm() / K_ref.norm(), 1e-10);
  std::printf(
      "cart-pole K = [%s], |K - K_ref|/|K_ref| = %.1e (linearised), %.1e (exact A, B)\n",
      [&] {
        std::string s;
        for (int i = 0; i < 4; ++i) s += (i ? ", " : "") + std::to_string(from_system.K(0, i));
        return s;
      }()
          .c_str(),
      (from_system.K - K_ref).norm() / K_ref.norm(), (exact.K() - K_ref).norm() / K_ref.norm());
}

// u = u0 − K (x − x0) at an arbitrary x.
TEST(LqrController, OutputIsAffineFeedbackAboutTheOperatingPoint) {
  const Eigen::Vector4d x0(0.5, 0, 0, 0);
  const Eigen::VectorXd u0 = Eigen::VectorXd::Constant(1, 0.25);
  const LqrController lqr("lqr", CartPole::UprightA(), CartPole::UprightB(), Weights(), Eigen::MatrixXd::Identity(1, 1),
                          x0, u0);
  auto context = lqr.CreateDefaultLeafContext();
  const Eigen::Vector4d x(0.1, -0.2, 0.3, 0.05);
  lqr.FixInputPort(*context, 0, x);
  const Eigen::Vector4d dx = x - x0;
  const double expected = u0[0] - lqr.K().row(0).dot(dx);
  const Eigen::VectorXd u = lqr.EvalOutput(*context, "u");
  EXPECT_NEAR(u[0], expected, 1e-14);
}

// From a 0.15 rad tilt the closed loop returns to the upright with the cart back at p = 0. The slowest closed-loop
// pole of (A − BK) sets the time: the state must be below 1e-3 after 8 s (the linear decay e^{σ t} with the
// slowest σ, computed below, reaches 1e-3 well before that; the test checks that margin too).
TEST(LqrController, BalancesCartPoleFromATilt) {
  const Eigen::MatrixXd R = Eigen::MatrixXd::Constant(1, 1, 0.5);
  DiagramBuilder builder;
  const CartPole* plant = builder.AddSystem(std::make_unique<CartPole>());
  auto plant_context = plant->CreateDefaultLeafContext();
  plant->FixInputPort(*plant_context, 0, Eigen::VectorXd::Zero(1));
  const LinearSystemMatrices lin = Linearize(*plant, *plant_context, "f", "x");
  const LqrController* lqr = builder.AddSystem(std::make_unique<LqrController>("lqr", lin, Weights(), R));
  builder.Connect("cart_pole", "x", "lqr", "x");
  builder.Connect("lqr", "u", "cart_pole", "f");
  auto diagram = builder.Build("balance");

  const double slowest = MaxRealEigenvalue(CartPole::UprightA() - CartPole::UprightB() * lqr->K());
  ASSERT_LT(slowest, 0.0);
  const double t_final = 8.0;
  EXPECT_LT(std::exp(slowest * t_final) * 0.15 * 10, 1e-3)
      << "slowest pole " << slowest;  // 10: transient growth allowance

  Simulator simulator(*diagram);
  LeafContext& x = diagram->GetMutableSubsystemContext(*plant, simulator.get_mutable_context());
  x.get_mutable_continuous_state() << 0.0, 0.15, 0.0, 0.0;
  double max_tilt = 0.0;
  simulator.set_monitor([&](const Context& c) {
    max_tilt = std::max(max_tilt, std::abs(diagram->GetSubsystemContext(*plant, c).continuous_state()[1]));
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = simulator.AdvanceTo(t_final);
  ASSERT_TRUE(status.ok()) << status.ToString();
  const Eigen::VectorXd& x_final = diagram->GetSubsystemContext(*plant, simulator.get_context()).continuous_state();
  EXPECT_LT(x_final.cwiseAbs().maxCoeff(), 1e-3) << x_final.transpose();
  EXPECT_LT(max_tilt, 0.3);  // never near falling
  std::printf("slowest closed-loop pole %.3f 1/s; after %.0f s |x|_inf = %.1e; max tilt %.3f rad; %ld steps\n", slowest,
              t_final, x_final.cwiseAbs().maxCoeff(), max_tilt, simulator.statistics().steps);
}

TEST(LqrController, ErrorsNameTheSystem) {
  try {
    LqrController("balance_lqr", CartPole::UprightA(), CartPole::UprightB(), Weights(), Eigen::MatrixXd::Identity(1, 1),
                  Eigen::Vector3d::Zero(), Eigen::VectorXd::Zero(1));
    FAIL() << "a wrong x0 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "system 'balance_lqr': x0 must have size 4, got 3");
  }
  try {
    LqrController("balance_lqr", CartPole::UprightA(), CartPole::UprightB(), Weights(), Eigen::MatrixXd::Zero(1, 1),
                  Eigen::Vector4d::Zero(), Eigen::VectorXd::Zero(1));
    FAIL() << "R = 0 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "system 'balance_lqr': LinearQuadraticRegulator: R must be positive definite, its smallest eigenvalue is 0");
  }
}

}  // namespace
}  // namespace rome
