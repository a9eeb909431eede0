#include "solvers/nlp/nlp_problem.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace rome {
namespace {

class PatternProblem final : public NlpProblem {
 public:
  PatternProblem(SparsityPattern J, SparsityPattern H) : NlpProblem("pattern", 3, 2) {
    SetConstraintJacobianSparsity(std::move(J));
    SetLagrangianHessianSparsity(std::move(H));
  }
  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>&) override { return 0.0; }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}
};

TEST(NlpProblem, ValidatePatternsAndBounds) {
  SparsityPattern J, H;
  J.Add(1, 2);
  H.Add(2, 1);
  PatternProblem ok(J, H);
  EXPECT_NO_THROW(ok.Validate());
  EXPECT_EQ(ok.variable_lower_bounds().size(), 3);
  EXPECT_TRUE(std::isinf(ok.variable_upper_bounds()(0)));
  EXPECT_EQ(ok.constraint_upper_bounds(), Eigen::Vector2d::Zero());  // default: equalities

  SparsityPattern J_bad;
  J_bad.Add(2, 0);  // row out of range
  EXPECT_THROW(PatternProblem(J_bad, H).Validate(), std::invalid_argument);
  SparsityPattern H_upper;
  H_upper.Add(0, 1);  // above the diagonal
  try {
    PatternProblem(J, H_upper).Validate();
    FAIL();
  } catch (const std::invalid_argument& e) { EXPECT_NE(std::string(e.what()).find("'pattern'"), std::string::npos); }
  EXPECT_THROW(ok.SetVariableBounds(Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(ok.SetConstraintBounds(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), std::invalid_argument);
}

}  // namespace
}  // namespace rome
