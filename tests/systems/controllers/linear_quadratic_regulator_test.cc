// LinearQuadraticRegulator: the gain against references that do not use ROME's Riccati solver (the Hamiltonian's
// stable invariant subspace from Eigen's eigensolver, the double integrator's closed form, the cost of a gain from a
// Lyapunov equation solved by Kronecker products), and the one-line errors.
#include "systems/controllers/linear_quadratic_regulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/Dense>

#include "tests/common/error_of.h"
#include "tests/systems/controllers/riccati_references.h"

namespace rome {
namespace {

// Cost matrix P of u = −K x for the cost xᵀQx + uᵀRu + 2xᵀNu: (A−BK)ᵀP + P(A−BK) + Q − NK − KᵀNᵀ + KᵀRK = 0, by
// vec(P) = −(I ⊗ Aclᵀ + Aclᵀ ⊗ I)⁻¹ vec(Q_K).
Eigen::MatrixXd CostOfGain(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                           const Eigen::MatrixXd& R, const Eigen::MatrixXd& N, const Eigen::MatrixXd& K) {
  const Eigen::Index n = A.rows();
  const Eigen::MatrixXd Acl_t = (A - B * K).transpose();
  const Eigen::MatrixXd Q_K = Q - N * K - K.transpose() * N.transpose() + K.transpose() * R * K;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd L(n * n, n * n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) L.block(i * n, j * n, n, n) = I(i, j) * Acl_t + Acl_t(i, j) * I;
  const Eigen::VectorXd p = L.fullPivLu().solve(-Eigen::Map<const Eigen::VectorXd>(Q_K.data(), n * n));
  return Eigen::Map<const Eigen::MatrixXd>(p.data(), n, n);
}

// Double integrator ẋ1 = x2, ẋ2 = u with Q = diag(q1, q2), R = r. Writing S = [a b; b c], the CARE's entries are
//   (1,1): q1 − b²/r = 0,  (1,2): a − b c / r = 0,  (2,2): q2 + 2 b − c²/r = 0,
// so b = √(q1 r), c = √(r (q2 + 2 √(q1 r))), a = b c / r and K = R⁻¹BᵀS = [√(q1/r), √((q2 + 2√(q1 r))/r)].
TEST(LinearQuadraticRegulator, DoubleIntegratorMatchesClosedForm) {
  const double q1 = 4.0, q2 = 1.0, r = 0.5;
  Eigen::Matrix2d A;
  A << 0, 1, 0, 0;
  const Eigen::MatrixXd B = Eigen::Vector2d(0, 1);
  const Eigen::MatrixXd Q = Eigen::Vector2d(q1, q2).asDiagonal();
  const Eigen::MatrixXd R = Eigen::MatrixXd::Constant(1, 1, r);
  const LinearQuadraticRegulatorResult lqr = LinearQuadraticRegulator(A, B, Q, R);
  const double b = std::sqrt(q1 * r), c = std::sqrt(r * (q2 + 2 * b)), a = b * c / r;
  Eigen::Matrix2d S;
  S << a, b, b, c;
  EXPECT_LT((lqr.S - S).cwiseAbs().maxCoeff(), 1e-12) << lqr.S;
  EXPECT_NEAR(lqr.K(0, 0), std::sqrt(q1 / r), 1e-12);
  EXPECT_NEAR(lqr.K(0, 1), std::sqrt((q2 + 2 * std::sqrt(q1 * r)) / r), 1e-12);
}

TEST(LinearQuadraticRegulator, MatchesHamiltonianStableSubspace) {
  // An unstable, coupled 4-state, 2-input system.
  Eigen::MatrixXd A(4, 4), B(4, 2);
  A << 0.5, 1.0, 0.0, -0.2, -1.0, 0.3, 2.0, 0.0, 0.0, 0.0, 0.1, 1.0, 0.4, 0.0, -3.0, -0.5;
  B << 1, 0, 0, 0, 0.5, 1, 0, 2;
  Eigen::MatrixXd M(4, 4);
  M << 1, 0.2, 0, 0, 0, 1, 0.3, 0, 0, 0, 2, 0.1, 0.4, 0, 0, 1;
  const Eigen::MatrixXd Q = M.transpose() * M;
  Eigen::MatrixXd R(2, 2);
  R << 2.0, 0.3, 0.3, 0.5;
  const LinearQuadraticRegulatorResult lqr = LinearQuadraticRegulator(A, B, Q, R);
  const Eigen::MatrixXd S_ref = HamiltonianStableSubspaceSolution(A, B, Q, R);
  EXPECT_LT((lqr.S - S_ref).norm() / S_ref.norm(), 1e-10);
  EXPECT_LT(RelativeCareResidual(A, B, Q, R, lqr.S), 1e-12);
  EXPECT_LT(RelativeCareResidual(A, B, Q, R, S_ref), 1e-9);
  EXPECT_LT((lqr.K - R.inverse() * B.transpose() * S_ref).norm() / lqr.K.norm(), 1e-10);
  EXPECT_LT(MaxRealEigenvalue(A - B * lqr.K), 0.0);
}

// With a cross weight N the gain is optimal among all stabilising gains: its cost matrix (a Lyapunov equation in the
// test) equals S, and any nearby gain costs more.
TEST(LinearQuadraticRegulator, CrossWeightGainIsOptimal) {
  Eigen::MatrixXd A(3, 3), B(3, 1), N(3, 1);
  A << 0, 1, 0, 0, 0, 1, 1, -2, 0.5;
  B << 0, 0, 1;
  N << 0.2, -0.1, 0.3;
  const Eigen::MatrixXd Q = Eigen::Vector3d(2, 1, 0.5).asDiagonal();
  const Eigen::MatrixXd R = Eigen::MatrixXd::Constant(1, 1, 1.5);
  const LinearQuadraticRegulatorResult lqr = LinearQuadraticRegulator(A, B, Q, R, N);
  const Eigen::MatrixXd P = CostOfGain(A, B, Q, R, N, lqr.K);
  EXPECT_LT((P - lqr.S).norm() / lqr.S.norm(), 1e-9);
  for (int i = 0; i < 3; ++i)
    for (double d : {-1e-2, 1e-2}) {
      Eigen::MatrixXd K = lqr.K;
      K(0, i) += d;
      EXPECT_GT(CostOfGain(A, B, Q, R, N, K).trace(), P.trace()) << "gain element " << i << " moved by " << d;
    }
}

using test::ErrorOf;

TEST(LinearQuadraticRegulator, ErrorsAreOneLineAndNameTheMatrix) {
  Eigen::Matrix2d A;
  A << 0, 1, 0, 0;
  const Eigen::MatrixXd B = Eigen::Vector2d(0, 1), Q = Eigen::Matrix2d::Identity(), R = Eigen::MatrixXd::Identity(1, 1);
  EXPECT_EQ(ErrorOf([&] { LinearQuadraticRegulator(A, B, Eigen::Matrix3d::Identity(), R); }),
            "LinearQuadraticRegulator: Q must be 2x2, got 3x3");
  EXPECT_EQ(ErrorOf([&] { LinearQuadraticRegulator(A, Eigen::MatrixXd::Ones(3, 1), Q, R); }),
            "LinearQuadraticRegulator: B must be 2x1, got 3x1");
  Eigen::Matrix2d Q_asym;
  Q_asym << 1, 0.5, 0, 1;
  EXPECT_EQ(ErrorOf([&] {
              LinearQuadraticRegulator(A, B, Q_asym, R);
            }).rfind("LinearQuadraticRegulator: Q must be symmetric", 0),
            0u);
  EXPECT_EQ(ErrorOf([&] { LinearQuadraticRegulator(A, B, Q, -R); }),
            "LinearQuadraticRegulator: R must be positive definite, its smallest eigenvalue is -1");
  EXPECT_EQ(ErrorOf([&] {
              LinearQuadraticRegulator(A, B, Q, R, Eigen::Vector2d(3, 0));
            }).rfind("LinearQuadraticRegulator: Q − N R⁻¹ Nᵀ must be positive semidefinite", 0),
            0u);
  // ẋ1 = x1 (unstable) is not reached by u.
  Eigen::Matrix2d A_unreachable;
  A_unreachable << 1, 0, 0, 0;
  const std::string unstabilisable = ErrorOf([&] { LinearQuadraticRegulator(A_unreachable, B, Q, R); });
  EXPECT_EQ(unstabilisable.rfind(
                "LinearQuadraticRegulator: SolveContinuousAlgebraicRiccatiEquation: (A, B) is not stabilizable", 0),
            0u)
      << unstabilisable;
  for (const std::string& e : {unstabilisable}) EXPECT_EQ(e.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace rome
