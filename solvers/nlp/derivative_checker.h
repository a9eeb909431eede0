#pragma once
// Finite-difference reference for the derivatives of an NlpProblem (tests and debugging only;
// solvers always use the exact derivatives).
//
// Central differences with step h·max(1, |x_j|):
//   ∇f           vs (f(x + h e_j) − f(x − h e_j)) / 2h
//   ∂g/∂x        vs (g(x + h e_j) − g(x − h e_j)) / 2h   (also flags nonzeros missing from the
//                                                         declared sparsity pattern)
//   ∇²L (lower)  vs differences of ∇L = σ∇f + Jᵀλ, when the problem has an exact Hessian.
// Errors are |exact − fd| / max(1, |fd|).
#include "solvers/nlp/nlp_problem.h"

namespace rome {

struct DerivativeCheckOptions {
  double step = 1e-6;        // h, relative finite-difference step [-]
  double cost_factor = 1.0;  // σ used for the Hessian check [-]
};

struct DerivativeCheckResult {
  double max_gradient_error = 0.0;
  double max_jacobian_error = 0.0;  // includes entries missing from the pattern
  int worst_jacobian_row = -1;
  int worst_jacobian_col = -1;
  double max_hessian_error = 0.0;           // 0 when the problem has no exact Hessian
  double max_missing_jacobian_entry = 0.0;  // largest |fd| at a position outside the pattern
};

// `lambda` (size num_constraints) is used for the Hessian check; pass an empty vector to use
// ones.
DerivativeCheckResult CheckDerivatives(NlpProblem& problem, const Eigen::VectorXd& x,
                                       const Eigen::VectorXd& lambda = Eigen::VectorXd(),
                                       const DerivativeCheckOptions& options = {});

}  // namespace rome
