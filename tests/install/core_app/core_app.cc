// ROME's core component from an installed copy: a harmonic oscillator simulated by the hybrid simulator and linearised,
// a QP, the scalar Riccati equation and a double integrator's LQR, each against its closed form.
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>

#include "framework/install_location.h"
#include "framework/linearize.h"
#include "framework/simulator.h"
#include "solvers/qp/dense_qp_solver.h"
#include "solvers/riccati/continuous_algebraic_riccati_equation.h"
#include "systems/controllers/linear_quadratic_regulator.h"

namespace {

// ẍ = −ω² x, x(0) = 1, ẋ(0) = 0: x(t) = cos ω t.
class Oscillator final : public rome::LeafSystem {
 public:
  explicit Oscillator(double omega) : LeafSystem("oscillator"), omega_(omega) {
    DeclareContinuousState(Eigen::Vector2d(1.0, 0.0));
  }

 private:
  void DoCalcTimeDerivatives(const rome::LeafContext& context, Eigen::VectorXd* xdot) const override {
    const Eigen::VectorXd& x = context.continuous_state();
    (*xdot)[0] = x[1];
    (*xdot)[1] = -omega_ * omega_ * x[0];
  }
  double omega_;
};

bool Check(const char* what, double got, double expected, double tolerance) {
  const bool ok = std::abs(got - expected) <= tolerance;
  std::cout << what << ": " << got << " (expected " << expected << ")" << (ok ? "" : "  FAIL") << "\n";
  return ok;
}

}  // namespace

int main() {
  bool ok = true;
  const double omega = 2.0, t = 1.3;
  Oscillator oscillator(omega);
  rome::Simulator sim(oscillator);
  const rome::SimulatorStatus status = sim.AdvanceTo(t);
  ok &= status.ok();
  ok &= Check("oscillator x(1.3)", static_cast<const rome::LeafContext&>(sim.get_context()).continuous_state()[0],
              std::cos(omega * t), 1e-6);

  // min ½(x₀² + x₁²) s.t. x₀ + x₁ = 1, x₀ ≥ 0.8: x = (0.8, 0.2).
  rome::DenseQpSolver qp(2, 1, 0);
  qp.H.setIdentity();
  qp.A_eq << 1.0, 1.0;
  qp.b_eq << 1.0;
  qp.lb << 0.8, -std::numeric_limits<double>::infinity();
  ok &= qp.Solve() == rome::QpStatus::kOptimal;
  ok &= Check("QP x0", qp.x()[0], 0.8, 1e-12) && Check("QP x1", qp.x()[1], 0.2, 1e-12);

  // Scalar CARE 2aP − P²b²/r + q = 0: P = r (a + √(a² + b² q / r)) / b².
  const double a = 1.0, b = 2.0, q = 3.0, r = 0.5;
  const Eigen::MatrixXd P = rome::SolveContinuousAlgebraicRiccatiEquation(
      Eigen::MatrixXd::Constant(1, 1, a), Eigen::MatrixXd::Constant(1, 1, b), Eigen::MatrixXd::Constant(1, 1, q),
      Eigen::MatrixXd::Constant(1, 1, r));
  ok &= Check("CARE P", P(0, 0), r * (a + std::sqrt(a * a + b * b * q / r)) / (b * b), 1e-10);
  // Linearize: A = [0 1; −ω² 0] exactly for this linear system (central differences are exact on it up to round-off).
  auto context = oscillator.CreateDefaultContext();
  const rome::LinearSystemMatrices lin = rome::Linearize(oscillator, *context, "", "");
  ok &= Check("A(1,0)", lin.A(1, 0), -omega * omega, 1e-8) && Check("A(0,1)", lin.A(0, 1), 1.0, 1e-8);

  // Double integrator, Q = I, R = 1: K = [√(q1/r), √((q2 + 2√(q1 r))/r)] = [1, √3].
  Eigen::Matrix2d A_di;
  A_di << 0.0, 1.0, 0.0, 0.0;
  const Eigen::MatrixXd K = rome::LinearQuadraticRegulator(A_di, Eigen::Vector2d(0.0, 1.0), Eigen::Matrix2d::Identity(),
                                                           Eigen::MatrixXd::Identity(1, 1))
                                .K;
  ok &= Check("LQR K0", K(0, 0), 1.0, 1e-9) && Check("LQR K1", K(0, 1), std::sqrt(3.0), 1e-9);
  std::cout << "data folder: " << rome::InstalledDataFolder() << "\n";
  return ok ? 0 : 1;
}
