#pragma once
// NlpProblem: a sparse nonlinear program
//
//     minimize    f(x)
//     subject to  x_lower ≤ x ≤ x_upper,   g_lower ≤ g(x) ≤ g_upper,
//
// with exact first derivatives: ∇f, and the constraint Jacobian ∂g/∂x given by a fixed sparsity
// pattern (row, column triplets) plus a value array in the same order. Optionally the Hessian of
// the Lagrangian  σ ∇²f + Σ λ_i ∇²g_i  (lower triangle, fixed pattern); without it, solvers use a
// limited-memory quasi-Newton approximation.
//
// A derived class declares sizes, bounds and patterns in its constructor and implements the Eval*
// hooks. Eval* methods are non-const so a problem may cache work between calls at the same x.
// Infinite bounds (±std::numeric_limits<double>::infinity()) mean "unbounded".
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace rome {

// Triplet sparsity pattern; entry k is at (rows[k], cols[k]). Duplicates are summed by solvers.
struct SparsityPattern {
  std::vector<int> rows;
  std::vector<int> cols;
  int nnz() const { return static_cast<int>(rows.size()); }
  void Add(int row, int col) {
    rows.push_back(row);
    cols.push_back(col);
  }
};

class NlpProblem {
 public:
  // `name` is used in every message about this problem (errors, solver status).
  NlpProblem(std::string name, int num_variables, int num_constraints);
  virtual ~NlpProblem() = default;
  NlpProblem(const NlpProblem&) = delete;
  NlpProblem& operator=(const NlpProblem&) = delete;

  const std::string& name() const { return name_; }
  int num_variables() const { return num_variables_; }
  int num_constraints() const { return num_constraints_; }

  const Eigen::VectorXd& variable_lower_bounds() const { return x_lower_; }
  const Eigen::VectorXd& variable_upper_bounds() const { return x_upper_; }
  const Eigen::VectorXd& constraint_lower_bounds() const { return g_lower_; }
  const Eigen::VectorXd& constraint_upper_bounds() const { return g_upper_; }
  const SparsityPattern& constraint_jacobian_sparsity() const { return jacobian_sparsity_; }
  const SparsityPattern& lagrangian_hessian_sparsity() const { return hessian_sparsity_; }
  bool has_lagrangian_hessian() const { return has_hessian_; }

  // Bounds setters validate sizes and lower ≤ upper (std::invalid_argument naming the problem).
  void SetVariableBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);
  void SetConstraintBounds(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);

  // f(x).
  virtual double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) = 0;
  // ∇f(x), size num_variables.
  virtual void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> gradient) = 0;
  // g(x), size num_constraints.
  virtual void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) = 0;
  // Values of ∂g/∂x in the order of constraint_jacobian_sparsity().
  virtual void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x,
                                      Eigen::Ref<Eigen::VectorXd> values) = 0;
  // Values of σ∇²f + Σλ_i∇²g_i in the order of lagrangian_hessian_sparsity() (lower triangle).
  // Only called when has_lagrangian_hessian(); default throws std::logic_error.
  virtual void EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>& x, double cost_factor,
                                     const Eigen::Ref<const Eigen::VectorXd>& lambda,
                                     Eigen::Ref<Eigen::VectorXd> values);

  // Throws std::invalid_argument if a pattern entry is out of range or a Hessian entry is above
  // the diagonal (message names the problem and the entry). Called by solvers before solving.
  void Validate() const;

 protected:
  void SetConstraintJacobianSparsity(SparsityPattern pattern);
  // Declares an exact Hessian with this lower-triangular pattern.
  void SetLagrangianHessianSparsity(SparsityPattern pattern);

 private:
  std::string name_;
  int num_variables_;
  int num_constraints_;
  Eigen::VectorXd x_lower_, x_upper_, g_lower_, g_upper_;
  SparsityPattern jacobian_sparsity_;
  SparsityPattern hessian_sparsity_;
  bool has_hessian_ = false;
};

}  // namespace rome
