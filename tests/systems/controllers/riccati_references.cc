#include "tests/systems/controllers/riccati_references.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

namespace rome {

Eigen::MatrixXd HamiltonianStableSubspaceSolution(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                                  const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd H(2 * n, 2 * n);
  H << A, -B * R.inverse() * B.transpose(), -Q, -A.transpose();
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(H);
  Eigen::MatrixXcd U(2 * n, n);
  Eigen::Index k = 0;
  for (Eigen::Index i = 0; i < 2 * n; ++i)
    if (eig.eigenvalues()[i].real() < 0 && k < n) U.col(k++) = eig.eigenvectors().col(i);
  EXPECT_EQ(k, n) << "H must have n stable eigenvalues";
  EXPECT_LT(eig.eigenvalues().real().minCoeff(), 0.0);
  const Eigen::MatrixXcd S = U.bottomRows(n) * U.topRows(n).inverse();
  EXPECT_LT(S.imag().cwiseAbs().maxCoeff(), 1e-9);
  return S.real();
}

double RelativeCareResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                            const Eigen::MatrixXd& R, const Eigen::MatrixXd& S) {
  return (A.transpose() * S + S * A - S * B * R.inverse() * B.transpose() * S + Q).norm() / Q.norm();
}

double MaxRealEigenvalue(const Eigen::MatrixXd& M) { return M.eigenvalues().real().maxCoeff(); }

}  // namespace rome
