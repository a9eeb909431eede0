#include "solvers/nlp/derivative_checker.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rome {
namespace {

Eigen::MatrixXd DenseJacobian(NlpProblem& problem, const Eigen::VectorXd& x) {
  const auto& pattern = problem.constraint_jacobian_sparsity();
  Eigen::VectorXd values(pattern.nnz());
  problem.EvalConstraintJacobian(x, values);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(problem.num_constraints(), problem.num_variables());
  for (int k = 0; k < pattern.nnz(); ++k) J(pattern.rows[k], pattern.cols[k]) += values(k);
  return J;
}

Eigen::VectorXd LagrangianGradient(NlpProblem& problem, const Eigen::VectorXd& x, double sigma,
                                   const Eigen::VectorXd& lambda) {
  Eigen::VectorXd grad(problem.num_variables());
  problem.EvalCostGradient(x, grad);
  return sigma * grad + DenseJacobian(problem, x).transpose() * lambda;
}

}  // namespace

DerivativeCheckResult CheckDerivatives(NlpProblem& problem, const Eigen::VectorXd& x, const Eigen::VectorXd& lambda_in,
                                       const DerivativeCheckOptions& options) {
  const int n = problem.num_variables();
  const int m = problem.num_constraints();
  if (x.size() != n) {
    std::ostringstream msg;
    msg << "CheckDerivatives: NLP '" << problem.name() << "' has " << n << " variables, x has size " << x.size();
    throw std::invalid_argument(msg.str());
  }
  problem.Validate();
  const Eigen::VectorXd lambda = lambda_in.size() == m ? lambda_in : Eigen::VectorXd::Ones(m);
  DerivativeCheckResult result;

  Eigen::VectorXd grad(n);
  problem.EvalCostGradient(x, grad);
  const Eigen::MatrixXd J = DenseJacobian(problem, x);
  Eigen::MatrixXi in_pattern = Eigen::MatrixXi::Zero(m, n);
  const auto& pattern = problem.constraint_jacobian_sparsity();
  for (int k = 0; k < pattern.nnz(); ++k) in_pattern(pattern.rows[k], pattern.cols[k]) = 1;

  Eigen::MatrixXd H_fd(n, n);
  Eigen::VectorXd g_plus(m), g_minus(m);
  for (int j = 0; j < n; ++j) {
    const double h = options.step * std::max(1.0, std::abs(x(j)));
    Eigen::VectorXd xp = x, xm = x;
    xp(j) += h;
    xm(j) -= h;
    const double fd_grad = (problem.EvalCost(xp) - problem.EvalCost(xm)) / (2.0 * h);
    result.max_gradient_error =
        std::max(result.max_gradient_error, std::abs(grad(j) - fd_grad) / std::max(1.0, std::abs(fd_grad)));
    problem.EvalConstraints(xp, g_plus);
    problem.EvalConstraints(xm, g_minus);
    for (int i = 0; i < m; ++i) {
      const double fd = (g_plus(i) - g_minus(i)) / (2.0 * h);
      const double err = std::abs(J(i, j) - fd) / std::max(1.0, std::abs(fd));
      if (!in_pattern(i, j)) {
        result.max_missing_jacobian_entry = std::max(result.max_missing_jacobian_entry, std::abs(fd));
      }
      if (err > result.max_jacobian_error) {
        result.max_jacobian_error = err;
        result.worst_jacobian_row = i;
        result.worst_jacobian_col = j;
      }
    }
    if (problem.has_lagrangian_hessian()) {
      H_fd.col(j) = (LagrangianGradient(problem, xp, options.cost_factor, lambda) -
                     LagrangianGradient(problem, xm, options.cost_factor, lambda)) /
                    (2.0 * h);
    }
  }
  if (problem.has_lagrangian_hessian()) {
    const auto& hp = problem.lagrangian_hessian_sparsity();
    Eigen::VectorXd values(hp.nnz());
    problem.EvalLagrangianHessian(x, options.cost_factor, lambda, values);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    for (int k = 0; k < hp.nnz(); ++k) H(hp.rows[k], hp.cols[k]) += values(k);
    const Eigen::MatrixXd H_fd_sym = 0.5 * (H_fd + H_fd.transpose());
    for (int j = 0; j < n; ++j) {
      for (int i = j; i < n; ++i) {
        result.max_hessian_error = std::max(
            result.max_hessian_error, std::abs(H(i, j) - H_fd_sym(i, j)) / std::max(1.0, std::abs(H_fd_sym(i, j))));
      }
    }
  }
  return result;
}

}  // namespace rome
