#pragma once
// References for CARE solutions that do not use ROME's Riccati solver (shared by the LQR tests;
// compiled once in riccati_references.cc: the complex eigensolver is the costliest code to compile in the suite).
#include <Eigen/Dense>

namespace rome {

// Stabilising CARE solution from the stable invariant subspace of H = [A −BR⁻¹Bᵀ; −Q −Aᵀ]: with the eigenvectors
// [U1; U2] of the n eigenvalues of H with negative real part, S = U2 U1⁻¹ (real up to round-off). Records a GoogleTest
// failure when H does not have n stable eigenvalues or S is not real.
Eigen::MatrixXd HamiltonianStableSubspaceSolution(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                                  const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

// ‖AᵀS + SA − SBR⁻¹BᵀS + Q‖_F / ‖Q‖_F, written out here.
double RelativeCareResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                            const Eigen::MatrixXd& R, const Eigen::MatrixXd& S);

// max Re λ(M) for a square M (the slowest closed-loop mode when M = A − BK).
double MaxRealEigenvalue(const Eigen::MatrixXd& M);

}  // namespace rome
