#include "solvers/riccati/continuous_algebraic_riccati_equation.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "solvers/riccati/continuous_lyapunov_equation.h"

namespace rome {
namespace {

TEST(ContinuousAlgebraicRiccatiEquation, DoubleIntegratorClosedForm) {
  // A = [0 1; 0 0], B = [0; 1], Q = I, R = 1 ⇒ P = [√3 1; 1 √3], K = [1 √3].
  Eigen::Matrix2d A;
  A << 0.0, 1.0, 0.0, 0.0;
  const Eigen::Vector2d B(0.0, 1.0);
  const auto solution = SolveContinuousAlgebraicRiccatiEquationWithDetails(A, B, Eigen::Matrix2d::Identity(),
                                                                           Eigen::Matrix<double, 1, 1>::Identity());
  const double s3 = std::sqrt(3.0);
  Eigen::Matrix2d expected;
  expected << s3, 1.0, 1.0, s3;
  EXPECT_LT((solution.P - expected).norm(), 1e-13);
  EXPECT_NEAR(solution.K(0, 0), 1.0, 1e-13);
  EXPECT_NEAR(solution.K(0, 1), s3, 1e-13);
  EXPECT_LT(solution.relative_residual, 1e-14);
  std::printf("double integrator: sign iterations %d, Newton polish %d, residual %.2e\n", solution.sign_iterations,
              solution.newton_refinements, solution.relative_residual);
}

TEST(ContinuousAlgebraicRiccatiEquation, ScalarClosedForm) {
  // a p·2 − p² b²/r + q = 0 ⇒ p = r (a + √(a² + b² q / r)) / b², for an unstable a.
  const double a = 2.0, b = 0.5, q = 3.0, r = 0.7;
  const Eigen::MatrixXd P =
      SolveContinuousAlgebraicRiccatiEquation(Eigen::MatrixXd::Constant(1, 1, a), Eigen::MatrixXd::Constant(1, 1, b),
                                              Eigen::MatrixXd::Constant(1, 1, q), Eigen::MatrixXd::Constant(1, 1, r));
  EXPECT_NEAR(P(0, 0), r * (a + std::sqrt(a * a + b * b * q / r)) / (b * b), 1e-12);
}

TEST(ContinuousAlgebraicRiccatiEquation, TripleIntegratorChainIsStabilizingAndMinimal) {
  // Chain of three integrators with Q = I, R = 1: the closed loop is the 3rd-order Butterworth-
  // like LQR pole set; check residual, stability and that P is the cost-to-go (Lyapunov
  // equation of the closed loop with Q + Kᵀ R K).
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  A(0, 1) = 1.0;
  A(1, 2) = 1.0;
  const Eigen::Vector3d B(0.0, 0.0, 1.0);
  const Eigen::Matrix3d Q = Eigen::Matrix3d::Identity();
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(1, 1);
  const auto sol = SolveContinuousAlgebraicRiccatiEquationWithDetails(A, B, Q, R);
  EXPECT_LT(sol.relative_residual, 1e-10);
  const Eigen::MatrixXd Acl = A - B * sol.K;
  EXPECT_LT(Acl.eigenvalues().real().maxCoeff(), 0.0);
  const Eigen::MatrixXd P_cost = SolveContinuousLyapunovEquation(Acl, Q + sol.K.transpose() * R * sol.K);
  EXPECT_LT((P_cost - sol.P).norm(), 1e-10 * sol.P.norm());
}

TEST(ContinuousAlgebraicRiccatiEquation, RandomSystemsResidual) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int n : {4, 12, 24}) {
    const int m = n / 2;
    Eigen::MatrixXd A(n, n), B(n, m), L(n, n), M(m, m);
    for (int i = 0; i < A.size(); ++i) A.data()[i] = normal(rng);
    for (int i = 0; i < B.size(); ++i) B.data()[i] = normal(rng);
    for (int i = 0; i < L.size(); ++i) L.data()[i] = normal(rng);
    for (int i = 0; i < M.size(); ++i) M.data()[i] = normal(rng);
    const Eigen::MatrixXd Q = L * L.transpose() / n + 0.1 * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd R = M * M.transpose() / m + Eigen::MatrixXd::Identity(m, m);
    const auto sol = SolveContinuousAlgebraicRiccatiEquationWithDetails(A, B, Q, R);
    EXPECT_LT(sol.relative_residual, 1e-10) << "n = " << n;
    EXPECT_LT((A - B * sol.K).eigenvalues().real().maxCoeff(), 0.0) << "n = " << n;
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sol.P).eigenvalues().minCoeff(), 0.0);
    std::printf("n = %d: sign iterations %d, Newton polish %d, residual %.2e\n", n, sol.sign_iterations,
                sol.newton_refinements, sol.relative_residual);
  }
}

TEST(ContinuousAlgebraicRiccatiEquation, RejectsNonStabilizable) {
  // Second state unstable (eigenvalue 1) and not reachable from u.
  Eigen::Matrix2d A;
  A << -1.0, 0.0, 0.0, 1.0;
  const Eigen::Vector2d B(1.0, 0.0);
  try {
    SolveContinuousAlgebraicRiccatiEquation(A, B, Eigen::Matrix2d::Identity(), Eigen::MatrixXd::Identity(1, 1));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not stabilizable"), std::string::npos) << e.what();
  }
}

// The PBH test at a complex eigenvalue: an unstable oscillation (0.5 ± 2i) the input cannot reach is rejected; the
// same oscillation driven through its second state is stabilized (closed-loop eigenvalues in the left half-plane).
TEST(ContinuousAlgebraicRiccatiEquation, PbhTestAtComplexEigenvalues) {
  Eigen::Matrix3d A;
  A << 0.5, 2.0, 0.0,  //
      -2.0, 0.5, 0.0,  //
      0.0, 0.0, -1.0;
  const Eigen::Matrix3d Q = Eigen::Matrix3d::Identity();
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(1, 1);
  try {
    SolveContinuousAlgebraicRiccatiEquation(A, Eigen::Vector3d(0.0, 0.0, 1.0), Q, R);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("not stabilizable"), std::string::npos) << what;
    EXPECT_NE(what.find("eigenvalue (0.5,"), std::string::npos) << what;  // 0.5 ± 2i, the uncontrollable pair
  }
  const Eigen::Vector3d B(0.0, 1.0, 1.0);
  const auto solution = SolveContinuousAlgebraicRiccatiEquationWithDetails(A, B, Q, R);
  const Eigen::Matrix3d closed_loop = A - B * solution.K;
  EXPECT_LT(closed_loop.eigenvalues().real().maxCoeff(), 0.0);
  EXPECT_LT(solution.relative_residual, 1e-12);
}

TEST(ContinuousAlgebraicRiccatiEquation, RejectsUndetectableImaginaryAxisMode) {
  // Undamped oscillator (eigenvalues ±i), Q = 0: Hamiltonian eigenvalues on the imaginary axis.
  Eigen::Matrix2d A;
  A << 0.0, 1.0, -1.0, 0.0;
  const Eigen::Vector2d B(0.0, 1.0);
  try {
    SolveContinuousAlgebraicRiccatiEquation(A, B, Eigen::Matrix2d::Zero(), Eigen::MatrixXd::Identity(1, 1));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("imaginary axis"), std::string::npos) << e.what();
  }
}

TEST(ContinuousAlgebraicRiccatiEquation, RejectsBadWeights) {
  Eigen::Matrix2d A;
  A << 0.0, 1.0, 0.0, 0.0;
  const Eigen::Vector2d B(0.0, 1.0);
  EXPECT_THROW(
      SolveContinuousAlgebraicRiccatiEquation(A, B, Eigen::Matrix2d::Identity(), -Eigen::MatrixXd::Identity(1, 1)),
      std::invalid_argument);
  EXPECT_THROW(
      SolveContinuousAlgebraicRiccatiEquation(A, B, -Eigen::Matrix2d::Identity(), Eigen::MatrixXd::Identity(1, 1)),
      std::invalid_argument);
  EXPECT_THROW(
      SolveContinuousAlgebraicRiccatiEquation(A, B, Eigen::Matrix3d::Identity(), Eigen::MatrixXd::Identity(1, 1)),
      std::invalid_argument);
}

}  // namespace
}  // namespace rome
