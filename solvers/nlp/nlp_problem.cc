#include "solvers/nlp/nlp_problem.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rome {
namespace {

void CheckBounds(const std::string& problem, const char* what, int expected, const Eigen::VectorXd& lower,
                 const Eigen::VectorXd& upper) {
  std::ostringstream msg;
  if (lower.size() != expected || upper.size() != expected) {
    msg << "NLP '" << problem << "': " << what << " bounds must have size " << expected << ", got lower "
        << lower.size() << " and upper " << upper.size();
    throw std::invalid_argument(msg.str());
  }
  for (int i = 0; i < expected; ++i) {
    if (std::isnan(lower(i)) || std::isnan(upper(i)) || lower(i) > upper(i)) {
      msg << "NLP '" << problem << "': " << what << " bound " << i << " has lower " << lower(i) << " > upper "
          << upper(i) << " (or NaN)";
      throw std::invalid_argument(msg.str());
    }
  }
}

}  // namespace

NlpProblem::NlpProblem(std::string name, int num_variables, int num_constraints)
    : name_(std::move(name)), num_variables_(num_variables), num_constraints_(num_constraints) {
  if (num_variables <= 0 || num_constraints < 0) {
    std::ostringstream msg;
    msg << "NLP '" << name_ << "': needs num_variables > 0 and num_constraints ≥ 0, got " << num_variables << " and "
        << num_constraints;
    throw std::invalid_argument(msg.str());
  }
  const double inf = std::numeric_limits<double>::infinity();
  x_lower_ = Eigen::VectorXd::Constant(num_variables, -inf);
  x_upper_ = Eigen::VectorXd::Constant(num_variables, inf);
  g_lower_ = Eigen::VectorXd::Zero(num_constraints);
  g_upper_ = Eigen::VectorXd::Zero(num_constraints);
}

void NlpProblem::SetVariableBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  CheckBounds(name_, "variable", num_variables_, lower, upper);
  x_lower_ = lower;
  x_upper_ = upper;
}

void NlpProblem::SetConstraintBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  CheckBounds(name_, "constraint", num_constraints_, lower, upper);
  g_lower_ = lower;
  g_upper_ = upper;
}

void NlpProblem::SetConstraintJacobianSparsity(SparsityPattern pattern) { jacobian_sparsity_ = std::move(pattern); }

void NlpProblem::SetLagrangianHessianSparsity(SparsityPattern pattern) {
  hessian_sparsity_ = std::move(pattern);
  has_hessian_ = true;
}

void NlpProblem::EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>&, double,
                                       const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) {
  throw std::logic_error("NLP '" + name_ + "': EvalLagrangianHessian called but not implemented");
}

void NlpProblem::Validate() const {
  const auto& J = jacobian_sparsity_;
  std::ostringstream msg;
  if (J.rows.size() != J.cols.size()) {
    msg << "NLP '" << name_ << "': Jacobian pattern has " << J.rows.size() << " rows but " << J.cols.size() << " cols";
    throw std::invalid_argument(msg.str());
  }
  for (int k = 0; k < J.nnz(); ++k) {
    if (J.rows[k] < 0 || J.rows[k] >= num_constraints_ || J.cols[k] < 0 || J.cols[k] >= num_variables_) {
      msg << "NLP '" << name_ << "': Jacobian entry " << k << " at (" << J.rows[k] << ", " << J.cols[k]
          << ") is outside " << num_constraints_ << "x" << num_variables_;
      throw std::invalid_argument(msg.str());
    }
  }
  const auto& H = hessian_sparsity_;
  if (H.rows.size() != H.cols.size()) {
    msg << "NLP '" << name_ << "': Hessian pattern has mismatched rows/cols";
    throw std::invalid_argument(msg.str());
  }
  for (int k = 0; k < H.nnz(); ++k) {
    if (H.rows[k] < 0 || H.rows[k] >= num_variables_ || H.cols[k] < 0 || H.cols[k] > H.rows[k]) {
      msg << "NLP '" << name_ << "': Hessian entry " << k << " at (" << H.rows[k] << ", " << H.cols[k]
          << ") is not in the lower triangle of " << num_variables_ << "x" << num_variables_;
      throw std::invalid_argument(msg.str());
    }
  }
}

}  // namespace rome
