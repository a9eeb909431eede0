#pragma once
// The NLP of a DirectCollocation problem (internal to rome_collocation; direct_collocation.h describes the
// transcription): the decision-vector layout of the phases and the NlpProblem that evaluates it.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "solvers/collocation/direct_collocation.h"

namespace rome::collocation_internal {

/// NodeConstraint::node of a path constraint (imposed at every node of its phase).
inline constexpr int kEveryNode = -2;

/// Where a phase's variables and defect rows sit in the NLP.
struct PhaseLayout {
  int nx = 0, nu = 0, N = 0;
  int x_offset = 0;  // first state variable
  int u_offset = 0;  // first input variable
  int T_index = -1;  // duration variable, −1 when fixed
  double fixed_T = 0.0;
  int defect_row = 0;  // first defect row
  int x(int k) const { return x_offset + k * nx; }
  int u(int k) const { return u_offset + k * nu; }
};

/// The layout of `phases` in order; `num_variables` receives the decision vector's size.
std::vector<PhaseLayout> MakeLayout(const std::vector<CollocationPhase>& phases, int* num_variables);

/// Evaluates y = F(x, u) and ∂y/∂[x; u] with AutoDiff; throws std::runtime_error naming `what` if y's size is not
/// `expected_size`.
void EvalWithJacobian(const StateInputFunction& F, int expected_size, const Eigen::VectorXd& x,
                      const Eigen::VectorXd& u, const std::string& what, Eigen::VectorXd* value,
                      Eigen::MatrixXd* jacobian);

/// The transcription as an NlpProblem (bounds not yet set). `z_probe` is evaluated once to find the Jacobian's
/// sparsity; `exact_hessian` declares the Lagrangian Hessian.
std::unique_ptr<NlpProblem> MakeCollocationNlp(
    const std::string& name, const std::vector<CollocationPhase>& phases, const std::vector<PhaseLayout>& layout,
    int num_variables, int num_constraints, const std::vector<DirectCollocation::NodeConstraint>& constraints,
    const std::vector<StateFunction>& transitions, const StateFunction& periodic_transition,
    const ScalarStateInputFunction& terminal_cost, const Eigen::VectorXd& z_probe, bool exact_hessian);

}  // namespace rome::collocation_internal
