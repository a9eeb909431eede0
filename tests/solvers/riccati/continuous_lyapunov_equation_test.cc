#include "solvers/riccati/continuous_lyapunov_equation.h"

#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace rome {
namespace {

TEST(ContinuousLyapunovEquation, DiagonalClosedForm) {
  // A = diag(a_i), Q = diag(q_i) ⇒ P_ii = q_i / (−2 a_i).
  const Eigen::Vector3d a(-1.0, -2.5, -0.1);
  const Eigen::Vector3d q(2.0, 1.0, 0.3);
  const Eigen::MatrixXd P =
      SolveContinuousLyapunovEquation(a.asDiagonal().toDenseMatrix(), q.asDiagonal().toDenseMatrix());
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(P(i, i), q(i) / (-2.0 * a(i)), 1e-14);
    for (int j = 0; j < 3; ++j) {
      if (i != j) { EXPECT_NEAR(P(i, j), 0.0, 1e-14); }
    }
  }
}

TEST(ContinuousLyapunovEquation, DampedOscillatorClosedForm) {
  // ẍ + 2ζω ẋ + ω² x = 0, Q = I. Solve Aᵀ P + P A = −I by hand:
  // P = [ (ω⁴ + ω² + 1)/(4ζω³) ... ] — derived entries:
  //   p12 = 1/(2ω²), p22 = (1 + ω²)/(4ζω³), p11 = 2ζω p12 + ω² p22 ... (see below)
  const double omega = 1.7;
  const double zeta = 0.3;
  Eigen::Matrix2d A;
  A << 0.0, 1.0, -omega * omega, -2.0 * zeta * omega;
  const Eigen::Matrix2d Q = Eigen::Matrix2d::Identity();
  const Eigen::MatrixXd P = SolveContinuousLyapunovEquation(A, Q);
  // Entry equations of Aᵀ P + P A + I = 0 with P = [p11 p12; p12 p22]:
  //  (1,1): −2ω² p12 + 1 = 0                         ⇒ p12 = 1/(2ω²)
  //  (2,2): 2 p12 − 4ζω p22 + 1 = 0                   ⇒ p22 = (2 p12 + 1)/(4ζω)
  //  (1,2): p11 − 2ζω p12 − ω² p22 = 0                ⇒ p11 = 2ζω p12 + ω² p22
  const double w2 = omega * omega;
  const double p12 = 1.0 / (2.0 * w2);
  const double p22 = (2.0 * p12 + 1.0) / (4.0 * zeta * omega);
  const double p11 = 2.0 * zeta * omega * p12 + w2 * p22;
  EXPECT_NEAR(P(0, 1), p12, 1e-13);
  EXPECT_NEAR(P(1, 0), p12, 1e-13);
  EXPECT_NEAR(P(1, 1), p22, 1e-13);
  EXPECT_NEAR(P(0, 0), p11, 1e-13);
  EXPECT_LT(ContinuousLyapunovRelativeResidual(A, Q, P), 1e-14);
}

TEST(ContinuousLyapunovEquation, RandomStableResidualAndEnergyIntegral) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (int n : {3, 8, 24}) {
    Eigen::MatrixXd M(n, n);
    for (int i = 0; i < n * n; ++i) M.data()[i] = normal(rng);
    // Shift so that A is Hurwitz, with complex eigenvalue pairs.
    const double shift = M.eigenvalues().real().maxCoeff() + 0.5;
    const Eigen::MatrixXd A = M - shift * Eigen::MatrixXd::Identity(n, n);
    Eigen::MatrixXd L(n, n);
    for (int i = 0; i < n * n; ++i) L.data()[i] = normal(rng);
    const Eigen::MatrixXd Q = L * L.transpose() + Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd P = SolveContinuousLyapunovEquation(A, Q);
    const double residual = ContinuousLyapunovRelativeResidual(A, Q, P);
    EXPECT_LT(residual, 1e-12) << "n = " << n;
    EXPECT_LT((P - P.transpose()).norm(), 1e-12 * P.norm());
    // P > 0 because A is Hurwitz and Q > 0.
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(P);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
  }
}

TEST(ContinuousLyapunovEquation, MatchesCostToGoIntegral) {
  // xᵀ P x = ∫₀^∞ x(t)ᵀ Q x(t) dt along ẋ = A x. Integrate with RK4 on a fine grid.
  Eigen::Matrix2d A;
  A << -0.5, 2.0, -1.0, -0.8;
  Eigen::Matrix2d Q;
  Q << 2.0, 0.3, 0.3, 1.0;
  const Eigen::MatrixXd P = SolveContinuousLyapunovEquation(A, Q);
  Eigen::Vector2d x(1.0, -0.5);
  const double expected = x.dot(P * x);
  // RK4 on the augmented state s = [x; J] with J̇ = xᵀ Q x, to t = 40 (e^(−0.65·40) ≈ 5e-12).
  auto f = [&](const Eigen::Vector3d& s) {
    const Eigen::Vector2d xs = s.head<2>();
    Eigen::Vector3d ds;
    ds << A * xs, xs.dot(Q * xs);
    return ds;
  };
  Eigen::Vector3d s(x(0), x(1), 0.0);
  const double h = 2.5e-3;
  for (int k = 0; k < 16000; ++k) {
    const Eigen::Vector3d k1 = f(s), k2 = f(s + 0.5 * h * k1), k3 = f(s + 0.5 * h * k2), k4 = f(s + h * k3);
    s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  const double J = s(2);
  EXPECT_NEAR(J, expected, 1e-9 * expected);
}

TEST(ContinuousLyapunovEquation, RejectsNonHurwitzAndBadSizes) {
  Eigen::Matrix2d A;
  A << 0.0, 1.0, 0.0, 0.0;  // double integrator: eigenvalues 0, 0
  try {
    SolveContinuousLyapunovEquation(A, Eigen::Matrix2d::Identity());
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not Hurwitz"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SolveContinuousLyapunovEquation(-Eigen::Matrix2d::Identity(), Eigen::Matrix3d::Identity()),
               std::invalid_argument);
  Eigen::Matrix2d Q_asym;
  Q_asym << 1.0, 2.0, 0.0, 1.0;
  EXPECT_THROW(SolveContinuousLyapunovEquation(-Eigen::Matrix2d::Identity(), Q_asym), std::invalid_argument);
}

}  // namespace
}  // namespace rome
