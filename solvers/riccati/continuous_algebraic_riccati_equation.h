#pragma once
// Continuous-time algebraic Riccati equation (CARE)
//
//     Aᵀ P + P A − P B R⁻¹ Bᵀ P + Q = 0,                     (footnote 3 of the hopping paper)
//
// returning the unique stabilizing solution P = Pᵀ ⪰ 0 (A − B K Hurwitz, K = R⁻¹ Bᵀ P).
//
// Method: matrix sign function of the Hamiltonian
//     H = [ A  −B R⁻¹ Bᵀ ;  −Q  −Aᵀ ],
// by the Newton iteration Z ← (c Z + (c Z)⁻¹)/2 with determinant scaling c = |det Z|^(−1/2n)
// (Roberts 1971, Byers 1987). With W = sign(H), the stable invariant subspace [I; P] satisfies
// (W + I)[I; P] = 0, so P is the least-squares solution of
//     [W12; W22 + I] P = −[W11 + I; W21].
// P is then polished by Newton–Kleinman steps (each a Lyapunov solve with the closed-loop
// matrix A − B R⁻¹ Bᵀ P, see continuous_lyapunov_equation.h) until the residual stops falling.
// We chose the sign function over a reordered real Schur form because Eigen has no Schur
// reordering; the Newton polish recovers full accuracy.
//
// Errors (std::invalid_argument): wrong sizes, R not symmetric positive definite, Q not
// symmetric positive semidefinite, (A, B) not stabilizable (the uncontrollable eigenvalue is
// named), Hamiltonian eigenvalue on the imaginary axis ((Q, A) not detectable on the axis).
#include <Eigen/Dense>

namespace rome {

struct ContinuousAlgebraicRiccatiOptions {
  // Sign iteration stops when ‖Z_{k+1} − Z_k‖₁ ≤ sign_tolerance · ‖Z_k‖₁. [-]
  double sign_tolerance = 1e-13;
  // Iteration cap of the sign function (quadratic convergence needs ~10–30). [-]
  int max_sign_iterations = 100;
  // Maximum number of Newton–Kleinman polishing steps. [-]
  int max_newton_refinements = 8;
  // An eigenvalue λ is "on the imaginary axis / unstable" when Re λ ≥ −axis_tolerance·max(1,‖H‖). [-]
  double axis_tolerance = 1e-9;
  // Rank tolerance of the PBH stabilizability test, relative to max(1, ‖[A B]‖). [-]
  double rank_tolerance = 1e-9;
  // Symmetry tolerance on Q and R, relative to max(1, ‖·‖_F). [-]
  double symmetry_tolerance = 1e-10;
};

struct ContinuousAlgebraicRiccatiSolution {
  Eigen::MatrixXd P;           // stabilizing solution, symmetric
  Eigen::MatrixXd K;           // optimal gain R⁻¹ Bᵀ P (u = −K x)
  double relative_residual{};  // see ContinuousAlgebraicRiccatiRelativeResidual
  int sign_iterations{};       // Newton iterations of the sign function
  int newton_refinements{};    // Newton–Kleinman polishing steps taken
};

ContinuousAlgebraicRiccatiSolution SolveContinuousAlgebraicRiccatiEquationWithDetails(
    const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B,
    const Eigen::Ref<const Eigen::MatrixXd>& Q, const Eigen::Ref<const Eigen::MatrixXd>& R,
    const ContinuousAlgebraicRiccatiOptions& options = {});

// Convenience: returns only P.
Eigen::MatrixXd SolveContinuousAlgebraicRiccatiEquation(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                        const Eigen::Ref<const Eigen::MatrixXd>& B,
                                                        const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                                        const Eigen::Ref<const Eigen::MatrixXd>& R,
                                                        const ContinuousAlgebraicRiccatiOptions& options = {});

// ‖Aᵀ P + P A − P B R⁻¹ Bᵀ P + Q‖_F divided by the sum of the Frobenius norms of the four terms.
double ContinuousAlgebraicRiccatiRelativeResidual(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& B,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& R,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& P);

}  // namespace rome
