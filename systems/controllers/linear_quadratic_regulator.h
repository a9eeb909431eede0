#pragma once
// LinearQuadraticRegulator: the infinite-horizon LQR gain of ẋ = A x + B u (Drake's shape).
//
// Minimises J = ∫₀^∞ xᵀQx + uᵀRu + 2 xᵀN u dt over u = −K x. With Ā = A − B R⁻¹ Nᵀ and Q̄ = Q − N R⁻¹ Nᵀ,
// S = Sᵀ ⪰ 0 is the stabilising solution of the continuous-time algebraic Riccati equation (CARE)
//
//     Āᵀ S + S Ā − S B R⁻¹ Bᵀ S + Q̄ = 0,      K = R⁻¹ (Bᵀ S + Nᵀ),
//
// solved by solvers/riccati/continuous_algebraic_riccati_equation.h (sign function of the Hamiltonian with a
// Newton–Kleinman polish); J* = x₀ᵀ S x₀ and A − B K is Hurwitz.
//
// Errors (std::invalid_argument, one line starting "LinearQuadraticRegulator: "): sizes that do not match A and B,
// Q or R not symmetric, R not positive definite, Q̄ not positive semidefinite, (A, B) not stabilisable, and any other
// failure of the Riccati solver (its message follows).
#include <string>

#include <Eigen/Core>

#include "framework/linearize.h"
#include "framework/system.h"
#include "solvers/riccati/continuous_algebraic_riccati_equation.h"

namespace rome {

struct LinearQuadraticRegulatorResult {
  Eigen::MatrixXd K;  ///< m×n optimal gain, u = −K x
  Eigen::MatrixXd S;  ///< n×n cost-to-go matrix, J* = xᵀ S x
};

/// The LQR of (A, B) with weights Q (n×n), R (m×m) and cross weight N (n×m; empty means zero).
LinearQuadraticRegulatorResult LinearQuadraticRegulator(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                                        const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
                                                        const Eigen::MatrixXd& N = Eigen::MatrixXd(),
                                                        const ContinuousAlgebraicRiccatiOptions& riccati = {});

/// The LQR of `system` linearised (framework/linearize.h) about the operating point held by `context` (its state x0
/// and the value u0 fixed on `input_port`, usually an equilibrium). u = u0 − K (x − x0) then stabilises x0.
LinearQuadraticRegulatorResult LinearQuadraticRegulator(const System& system, Context& context,
                                                        const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
                                                        const std::string& input_port,
                                                        const Eigen::MatrixXd& N = Eigen::MatrixXd(),
                                                        const LinearizeParams& linearize = {},
                                                        const ContinuousAlgebraicRiccatiOptions& riccati = {});

}  // namespace rome
