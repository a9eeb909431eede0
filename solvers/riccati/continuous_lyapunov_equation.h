#pragma once
// Continuous-time Lyapunov equation (CTLE)
//
//     Aᵀ P + P A + Q = 0,                                   (footnote 4 of the hopping paper)
//
// solved by the Bartels–Stewart method on the complex Schur form A = U T Uᴴ:
// with Y = Uᴴ P U and C = −Uᴴ Q U the equation becomes Tᴴ Y + Y T = C, which is
// solved entry by entry because T is upper triangular:
//
//     (conj(T_ii) + T_jj) Y_ij = C_ij − Σ_{k<i} conj(T_ki) Y_kj − Σ_{k<j} Y_ik T_kj.
//
// Cost O(n³); intended for the small systems of ROME (n ≲ 50).
#include <Eigen/Dense>

namespace rome {

struct ContinuousLyapunovOptions {
  // A is accepted as Hurwitz when max Re λ(A) < −hurwitz_margin · max(1, ‖A‖_F). [-]
  double hurwitz_margin = 1e-12;
  // Symmetry tolerance on Q, relative to max(1, ‖Q‖_F). [-]
  double symmetry_tolerance = 1e-10;
};

// Returns the symmetric P solving Aᵀ P + P A + Q = 0.
// Throws std::invalid_argument when A is not square, Q has the wrong size or is not
// symmetric, or A is not Hurwitz (the message gives the offending eigenvalue).
Eigen::MatrixXd SolveContinuousLyapunovEquation(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                                const ContinuousLyapunovOptions& options = {});

// Same equation, without the Hurwitz requirement: only needs λ_i(A) + conj(λ_j(A)) ≠ 0
// for all i, j (unique solution). Used by the Newton refinement of the Riccati solver.
// Throws std::invalid_argument when the equation is singular.
Eigen::MatrixXd SolveContinuousLyapunovEquationUnchecked(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                         const Eigen::Ref<const Eigen::MatrixXd>& Q);

// ‖Aᵀ P + P A + Q‖_F / max(‖Aᵀ P‖_F + ‖P A‖_F + ‖Q‖_F, tiny): relative residual.
double ContinuousLyapunovRelativeResidual(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                          const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                          const Eigen::Ref<const Eigen::MatrixXd>& P);

}  // namespace rome
