#pragma once
// AutoDiffNlpProblem: an NlpProblem from two functions written once on AutoDiff scalars,
//     cost(x) -> AutoDiffXd,   constraints(x) -> VectorXad (size num_constraints),
// with exact gradient and a DENSE constraint Jacobian (every entry in the pattern) from forward
// AutoDiff. No exact Hessian: Ipopt uses its limited-memory approximation.
// Meant for small problems (tens of variables); large sparse problems should derive from
// NlpProblem directly (see solvers/collocation for a structured example).
#include <functional>
#include <string>

#include "solvers/nlp/autodiff.h"
#include "solvers/nlp/nlp_problem.h"

namespace rome {

class AutoDiffNlpProblem final : public NlpProblem {
 public:
  using CostFunction = std::function<AutoDiffXd(const VectorXad& x)>;
  using ConstraintFunction = std::function<VectorXad(const VectorXad& x)>;

  // `constraints` may be empty when num_constraints == 0.
  AutoDiffNlpProblem(std::string name, int num_variables, int num_constraints, CostFunction cost,
                     ConstraintFunction constraints);

  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override;
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> gradient) override;
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override;
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> values) override;

 private:
  void Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x);
  VectorXad CheckedConstraints(const VectorXad& x) const;

  CostFunction cost_;
  ConstraintFunction constraints_;
  // Cache of the last evaluation point (Ipopt asks for f, ∇f, g, ∂g at the same x).
  Eigen::VectorXd cached_x_;
  double cost_value_ = 0.0;
  Eigen::VectorXd cost_gradient_;
  Eigen::VectorXd g_value_;
  Eigen::MatrixXd g_jacobian_;
};

}  // namespace rome
