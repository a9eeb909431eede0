#pragma once
// References for CARE solutions that do not use ROME's Riccati solver (shared by the LQR tests).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

namespace rome {

// Stabilising CARE solution from the stable invariant subspace of H = [A −BR⁻¹Bᵀ; −Q −Aᵀ]: with the eigenvectors
// [U1; U2] of the n eigenvalues of H with negative real part, S = U2 U1⁻¹ (real up to round-off).
inline Eigen::MatrixXd HamiltonianStableSubspaceSolution(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
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

// ‖AᵀS + SA − SBR⁻¹BᵀS + Q‖_F / ‖Q‖_F, written out here.
inline double RelativeCareResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                                   const Eigen::MatrixXd& R, const Eigen::MatrixXd& S) {
  return (A.transpose() * S + S * A - S * B * R.inverse() * B.transpose() * S + Q).norm() / Q.norm();
}

}  // namespace rome
