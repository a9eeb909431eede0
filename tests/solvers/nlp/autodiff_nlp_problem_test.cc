#include "solvers/nlp/autodiff_nlp_problem.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "solvers/nlp/derivative_checker.h"
#include "solvers/nlp/ipopt_solver.h"
#include "tests/solvers/nlp/hs071.h"

namespace rome {
namespace {

// HS071 written once on AutoDiff scalars.
std::unique_ptr<AutoDiffNlpProblem> MakeAutoDiffHs071() {
  auto problem = std::make_unique<AutoDiffNlpProblem>(
      "hs071_autodiff", 4, 2,
      [](const VectorXad& x) -> AutoDiffXd { return x(0) * x(3) * (x(0) + x(1) + x(2)) + x(2); },
      [](const VectorXad& x) -> VectorXad {
        VectorXad g(2);
        g(0) = x(0) * x(1) * x(2) * x(3);
        g(1) = x.squaredNorm();
        return g;
      });
  problem->SetVariableBounds(Eigen::Vector4d::Constant(1.0), Eigen::Vector4d::Constant(5.0));
  problem->SetConstraintBounds(Eigen::Vector2d(25.0, 40.0),
                               Eigen::Vector2d(std::numeric_limits<double>::infinity(), 40.0));
  return problem;
}

TEST(AutoDiffNlpProblem, JacobianMatchesFiniteDifferencesAndAnalytic) {
  auto problem = MakeAutoDiffHs071();
  test::Hs071 analytic;
  for (const Eigen::Vector4d& x : {Eigen::Vector4d(1.0, 5.0, 5.0, 1.0), Eigen::Vector4d(1.3, 2.2, 4.1, 3.7)}) {
    const DerivativeCheckResult check = CheckDerivatives(*problem, x);
    EXPECT_LT(check.max_gradient_error, 1e-8);
    EXPECT_LT(check.max_jacobian_error, 1e-8);
    EXPECT_EQ(check.max_missing_jacobian_entry, 0.0);
    // AutoDiff equals the hand-written derivatives to round-off.
    Eigen::VectorXd ga(4), gb(4), ja(8), jb(8);
    problem->EvalCostGradient(x, ga);
    analytic.EvalCostGradient(x, gb);
    problem->EvalConstraintJacobian(x, ja);
    analytic.EvalConstraintJacobian(x, jb);
    EXPECT_LT((ga - gb).cwiseAbs().maxCoeff(), 1e-13);
    // Dense pattern is column-major, the fixture's row-major: compare as matrices.
    Eigen::Map<Eigen::Matrix<double, 2, 4>> Ja(ja.data());
    Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>> Jb(jb.data());
    EXPECT_LT((Ja - Jb).cwiseAbs().maxCoeff(), 1e-13);
  }
}

TEST(AutoDiffNlpProblem, SolvesHs071WithLimitedMemoryHessian) {
  auto problem = MakeAutoDiffHs071();
  const NlpResult r = IpoptSolver().Solve(*problem, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0));
  ASSERT_TRUE(r.success()) << r.message;
  EXPECT_LT((r.x - test::Hs071Solution()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(r.cost, test::kHs071OptimalCost, 1e-6);
  std::printf("hs071 AutoDiff + L-BFGS: %d iterations, %.3f ms\n", r.iterations, 1e3 * r.wall_time);
}

TEST(AutoDiffNlpProblem, WrongConstraintSizeIsReported) {
  AutoDiffNlpProblem problem(
      "bad_size", 2, 2, [](const VectorXad& x) -> AutoDiffXd { return x.squaredNorm(); },
      [](const VectorXad& x) -> VectorXad { return x.head(1); });
  Eigen::VectorXd g(2);
  try {
    problem.EvalConstraints(Eigen::Vector2d(1.0, 2.0), g);
    FAIL();
  } catch (const std::runtime_error& e) { EXPECT_NE(std::string(e.what()).find("bad_size"), std::string::npos); }
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

// The inline-gradient scalar gives HS071's analytic constraint Jacobian, and refuses more derivatives than it holds.
TEST(AutoDiffMax, JacobianMatchesAnalyticAndCapacityIsChecked) {
  using AD = AutoDiffMax<6>;
  const Eigen::Vector4d v(1.0, 4.7, 3.8, 1.4);
  const Eigen::Matrix<AD, Eigen::Dynamic, 1> x = InitializeAutoDiff<AD>(v, 6, 1);  // columns 1-4 of 6
  Eigen::Matrix<AD, Eigen::Dynamic, 1> g(2);
  g(0) = x(0) * x(1) * x(2) * x(3);
  g(1) = x.squaredNorm();
  const Eigen::MatrixXd J = ExtractJacobian(g, 6);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(2, 6);
  expected.row(0).segment(1, 4) << v(1) * v(2) * v(3), v(0) * v(2) * v(3), v(0) * v(1) * v(3), v(0) * v(1) * v(2);
  expected.row(1).segment(1, 4) = 2.0 * v.transpose();
  EXPECT_LT((J - expected).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(ExtractValue(g)(0), v.prod(), 1e-14);
  EXPECT_THROW(InitializeAutoDiff<AD>(v, 7, 0), std::invalid_argument);
}

}  // namespace
}  // namespace rome
