#include "solvers/nlp/derivative_checker.h"

#include <gtest/gtest.h>

#include "tests/solvers/nlp/hs071.h"

namespace rome {
namespace {

// HS071 with a deliberate bug: ∂g0/∂x2 off by 10 %, and ∂g1/∂x3 missing from the pattern.
class BuggyHs071 final : public NlpProblem {
 public:
  BuggyHs071() : NlpProblem("buggy", 4, 2) {
    SparsityPattern J;
    for (int j = 0; j < 4; ++j) J.Add(0, j);
    for (int j = 0; j < 3; ++j) J.Add(1, j);
    SetConstraintJacobianSparsity(J);
  }
  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override { return inner_.EvalCost(x); }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    inner_.EvalCostGradient(x, g);
  }
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    inner_.EvalConstraints(x, g);
  }
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> v) override {
    Eigen::VectorXd full(8);
    inner_.EvalConstraintJacobian(x, full);
    v = full.head(7);
    v(2) *= 1.1;
  }

 private:
  test::Hs071 inner_;
};

TEST(DerivativeChecker, FindsWrongAndMissingEntries) {
  BuggyHs071 problem;
  const Eigen::Vector4d x(1.3, 2.2, 4.1, 3.7);
  const DerivativeCheckResult r = CheckDerivatives(problem, x);
  EXPECT_LT(r.max_gradient_error, 1e-8);
  // Missing ∂g1/∂x3 = 2 x3 = 7.4 dominates the 10 % error on ∂g0/∂x2 (= 1.3·2.2·3.7·0.1 ≈ 1.06).
  EXPECT_NEAR(r.max_missing_jacobian_entry, 7.4, 1e-6);
  EXPECT_EQ(r.worst_jacobian_row, 1);
  EXPECT_EQ(r.worst_jacobian_col, 3);
  EXPECT_GT(r.max_jacobian_error, 0.9);
}

TEST(DerivativeChecker, CorrectProblemPasses) {
  test::Hs071 problem;
  const DerivativeCheckResult r =
      CheckDerivatives(problem, Eigen::Vector4d(1.3, 2.2, 4.1, 3.7), Eigen::Vector2d(0.5, 2.0));
  EXPECT_LT(r.max_gradient_error, 1e-8);
  EXPECT_LT(r.max_jacobian_error, 1e-8);
  EXPECT_LT(r.max_hessian_error, 1e-6);
}

}  // namespace
}  // namespace rome
