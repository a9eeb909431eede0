#include "solvers/nlp/autodiff_nlp_problem.h"

#include <sstream>
#include <stdexcept>

namespace rome {

AutoDiffNlpProblem::AutoDiffNlpProblem(std::string name, int num_variables, int num_constraints, CostFunction cost,
                                       ConstraintFunction constraints)
    : NlpProblem(std::move(name), num_variables, num_constraints),
      cost_(std::move(cost)),
      constraints_(std::move(constraints)) {
  if (!cost_) throw std::invalid_argument("NLP '" + this->name() + "': cost function is empty");
  if (num_constraints > 0 && !constraints_) {
    throw std::invalid_argument("NLP '" + this->name() + "': constraint function is empty");
  }
  SparsityPattern pattern;
  for (int j = 0; j < num_variables; ++j) {
    for (int i = 0; i < num_constraints; ++i) pattern.Add(i, j);  // column-major, like MatrixXd
  }
  SetConstraintJacobianSparsity(std::move(pattern));
}

VectorXad AutoDiffNlpProblem::CheckedConstraints(const VectorXad& x) const {
  if (num_constraints() == 0) return VectorXad(0);
  VectorXad g = constraints_(x);
  if (g.size() != num_constraints()) {
    std::ostringstream msg;
    msg << "NLP '" << name() << "': constraint function returned size " << g.size() << ", expected "
        << num_constraints();
    throw std::runtime_error(msg.str());
  }
  return g;
}

void AutoDiffNlpProblem::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (cached_x_.size() == x.size() && cached_x_ == x) return;
  const VectorXad xa = InitializeAutoDiff(x);
  const AutoDiffXd f = cost_(xa);
  cost_value_ = f.value();
  cost_gradient_ =
      f.derivatives().size() == x.size() ? Eigen::VectorXd(f.derivatives()) : Eigen::VectorXd::Zero(x.size());
  const VectorXad g = CheckedConstraints(xa);
  g_value_ = ExtractValue(g);
  g_jacobian_ = ExtractJacobian(g, static_cast<int>(x.size()));
  cached_x_ = x;
}

double AutoDiffNlpProblem::EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Evaluate(x);
  return cost_value_;
}

void AutoDiffNlpProblem::EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                                          Eigen::Ref<Eigen::VectorXd> gradient) {
  Evaluate(x);
  gradient = cost_gradient_;
}

void AutoDiffNlpProblem::EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) {
  Evaluate(x);
  g = g_value_;
}

void AutoDiffNlpProblem::EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x,
                                                Eigen::Ref<Eigen::VectorXd> values) {
  Evaluate(x);
  values = Eigen::Map<const Eigen::VectorXd>(g_jacobian_.data(), g_jacobian_.size());
}

}  // namespace rome
