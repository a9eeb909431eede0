#include "solvers/nlp/ipopt_solver.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "solvers/nlp/derivative_checker.h"
#include "tests/solvers/nlp/hs071.h"

namespace rome {
namespace {

// Rosenbrock f = (1 − x0)² + 100 (x1 − x0²)², unconstrained, analytic Hessian.
class Rosenbrock final : public NlpProblem {
 public:
  Rosenbrock() : NlpProblem("rosenbrock", 2, 0) {
    SparsityPattern H;
    H.Add(0, 0);
    H.Add(1, 0);
    H.Add(1, 1);
    SetLagrangianHessianSparsity(H);
  }
  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override {
    return std::pow(1.0 - x(0), 2) + 100.0 * std::pow(x(1) - x(0) * x(0), 2);
  }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    g(0) = -2.0 * (1.0 - x(0)) - 400.0 * x(0) * (x(1) - x(0) * x(0));
    g(1) = 200.0 * (x(1) - x(0) * x(0));
  }
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}
  void EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>& x, double s,
                             const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd> v) override {
    v(0) = s * (2.0 - 400.0 * x(1) + 1200.0 * x(0) * x(0));
    v(1) = s * (-400.0 * x(0));
    v(2) = s * 200.0;
  }
};

// Unit disc x0² + x1² ≤ 1 together with x0 + x1 ≥ 3: no feasible point.
class InfeasibleDisc final : public NlpProblem {
 public:
  InfeasibleDisc() : NlpProblem("infeasible_disc", 2, 2) {
    const double inf = std::numeric_limits<double>::infinity();
    SetConstraintBounds(Eigen::Vector2d(-inf, 3.0), Eigen::Vector2d(1.0, inf));
    SparsityPattern J;
    J.Add(0, 0);
    J.Add(0, 1);
    J.Add(1, 0);
    J.Add(1, 1);
    SetConstraintJacobianSparsity(J);
  }
  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override { return x.squaredNorm(); }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    g = 2.0 * x;
  }
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    g(0) = x.squaredNorm();
    g(1) = x(0) + x(1);
  }
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> v) override {
    v << 2.0 * x(0), 2.0 * x(1), 1.0, 1.0;
  }
};

// Throws from its cost after a few evaluations.
class ThrowingProblem final : public NlpProblem {
 public:
  ThrowingProblem() : NlpProblem("throwing", 1, 0) {}
  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override {
    if (++calls_ > 3) throw std::runtime_error("model 'throwing' evaluated out of its domain");
    return x(0) * x(0);
  }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    g(0) = 2.0 * x(0);
  }
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>&, Eigen::Ref<Eigen::VectorXd>) override {}

 private:
  int calls_ = 0;
};

// KKT stationarity ∇f + Jᵀλ − z_L + z_U with Ipopt's sign convention.
double StationarityError(NlpProblem& problem, const NlpResult& r) {
  Eigen::VectorXd grad(problem.num_variables());
  problem.EvalCostGradient(r.x, grad);
  const auto& p = problem.constraint_jacobian_sparsity();
  Eigen::VectorXd values(p.nnz());
  problem.EvalConstraintJacobian(r.x, values);
  Eigen::VectorXd kkt = grad - r.multipliers.lower_bounds + r.multipliers.upper_bounds;
  for (int k = 0; k < p.nnz(); ++k) kkt(p.cols[k]) += values(k) * r.multipliers.constraints(p.rows[k]);
  return kkt.cwiseAbs().maxCoeff();
}

TEST(IpoptSolver, Hs071ExactHessianMatchesKnownSolution) {
  test::Hs071 problem;
  const Eigen::Vector4d x0(1.0, 5.0, 5.0, 1.0);
  // The fixture's analytic derivatives agree with finite differences.
  const DerivativeCheckResult check = CheckDerivatives(problem, x0, Eigen::Vector2d(0.7, -0.3));
  EXPECT_LT(check.max_gradient_error, 1e-7);
  EXPECT_LT(check.max_jacobian_error, 1e-7);
  EXPECT_LT(check.max_hessian_error, 1e-6);

  IpoptSolver solver;
  const NlpResult r = solver.Solve(problem, x0);
  ASSERT_EQ(r.status, NlpStatus::kSolved) << r.message;
  EXPECT_LT((r.x - test::Hs071Solution()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(r.cost, test::kHs071OptimalCost, 1e-6);
  EXPECT_NEAR(r.constraints(1), 40.0, 1e-8);
  EXPECT_LT(StationarityError(problem, r), 1e-7);
  EXPECT_NE(r.message.find("hs071"), std::string::npos);
  std::printf("hs071 exact Hessian: %d iterations, %.3f ms, |x − x*|∞ = %.2e\n", r.iterations, 1e3 * r.wall_time,
              (r.x - test::Hs071Solution()).cwiseAbs().maxCoeff());

  // Warm start from the solution with its multipliers converges in fewer iterations.
  const NlpResult warm = solver.Solve(problem, r.x, &r.multipliers);
  ASSERT_TRUE(warm.success()) << warm.message;
  EXPECT_LT(warm.iterations, r.iterations);
  EXPECT_LT((warm.x - r.x).cwiseAbs().maxCoeff(), 1e-7);
  std::printf("hs071 warm start: %d iterations\n", warm.iterations);
}

TEST(IpoptSolver, Hs071LimitedMemoryHessian) {
  test::Hs071 problem;
  IpoptSolverOptions options;
  options.use_limited_memory_hessian = true;
  const NlpResult r = IpoptSolver(options).Solve(problem, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0));
  ASSERT_TRUE(r.success()) << r.message;
  EXPECT_LT((r.x - test::Hs071Solution()).cwiseAbs().maxCoeff(), 1e-6);
  std::printf("hs071 L-BFGS: %d iterations, %.3f ms\n", r.iterations, 1e3 * r.wall_time);
}

TEST(IpoptSolver, RosenbrockReachesGlobalMinimum) {
  Rosenbrock problem;
  const NlpResult r = IpoptSolver().Solve(problem, Eigen::Vector2d(-1.2, 1.0));
  ASSERT_EQ(r.status, NlpStatus::kSolved) << r.message;
  EXPECT_LT((r.x - Eigen::Vector2d(1.0, 1.0)).norm(), 1e-7);
  EXPECT_LT(r.cost, 1e-14);
  std::printf("rosenbrock: %d iterations, %.3f ms\n", r.iterations, 1e3 * r.wall_time);
}

TEST(IpoptSolver, InfeasibleProblemIsReported) {
  InfeasibleDisc problem;
  const NlpResult r = IpoptSolver().Solve(problem, Eigen::Vector2d(0.1, 0.2));
  EXPECT_EQ(r.status, NlpStatus::kInfeasible) << r.message;
  EXPECT_FALSE(r.success());
  EXPECT_NE(r.message.find("infeasible_disc"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("infeasible"), std::string::npos) << r.message;
  // Ipopt minimizes the violation: closest approach is x0 = x1 = 1/√2 (disc) vs line x0+x1 = 3,
  // so the returned point minimizes the violation there: x0 + x1 = √2, violation 3 − √2.
  EXPECT_NEAR(r.constraints(1), std::sqrt(2.0), 1e-3);
  EXPECT_LT(r.constraints(0), 1.0 + 1e-6);
  std::printf("%s\n", r.message.c_str());
}

TEST(IpoptSolver, IterationLimitIsReported) {
  Rosenbrock problem;
  IpoptSolverOptions options;
  options.max_iterations = 3;
  const NlpResult r = IpoptSolver(options).Solve(problem, Eigen::Vector2d(-1.2, 1.0));
  EXPECT_EQ(r.status, NlpStatus::kMaxIterations) << r.message;
}

TEST(IpoptSolver, CallbackExceptionIsRethrown) {
  ThrowingProblem problem;
  try {
    IpoptSolver().Solve(problem, Eigen::VectorXd::Constant(1, 3.0));
    FAIL() << "expected the model's exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("out of its domain"), std::string::npos);
  }
}

TEST(IpoptSolver, RejectedOptionValueIsNamed) {
  test::Hs071 problem;
  IpoptSolverOptions options;
  options.mu_strategy = "fast";
  try {
    IpoptSolver(options).Solve(problem, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu_strategy = 'fast'"), std::string::npos) << e.what();
  }
  options = IpoptSolverOptions();
  options.mu_init = -1e-9;  // Ipopt requires mu_init > 0
  try {
    IpoptSolver(options).Solve(problem, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mu_init = -1e-09"), std::string::npos) << e.what();
  }
  // The mutex is released: a valid solve still runs.
  EXPECT_TRUE(IpoptSolver().Solve(problem, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0)).success());
}

// Both bound-multiplier initialisations reach HS071's published optimum (Hock & Schittkowski, test::Hs071Solution).
TEST(IpoptSolver, MuBasedBoundMultipliersReachTheSameOptimum) {
  for (const char* method : {"constant", "mu-based"}) {
    test::Hs071 problem;
    IpoptSolverOptions options;
    options.bound_mult_init_method = method;
    options.mu_init = 0.01;
    const NlpResult r = IpoptSolver(options).Solve(problem, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0));
    ASSERT_TRUE(r.success()) << method << ": " << r.message;
    EXPECT_LT((r.x - test::Hs071Solution()).cwiseAbs().maxCoeff(), 1e-6) << method;
  }
}

TEST(IpoptSolver, RejectsWrongInitialGuessSize) {
  test::Hs071 problem;
  EXPECT_THROW(IpoptSolver().Solve(problem, Eigen::Vector3d::Ones()), std::invalid_argument);
}

TEST(IpoptSolver, ConcurrentSolvesAreSerializedAndCorrect) {
  // Ipopt/MUMPS is not thread-safe; the process-wide mutex must make this safe.
  Eigen::Vector4d x_a, x_b;
  std::thread a([&] {
    test::Hs071 p;
    x_a = IpoptSolver().Solve(p, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0)).x;
  });
  std::thread b([&] {
    test::Hs071 p;
    x_b = IpoptSolver().Solve(p, Eigen::Vector4d(1.0, 5.0, 5.0, 1.0)).x;
  });
  a.join();
  b.join();
  EXPECT_LT((x_a - test::Hs071Solution()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((x_b - test::Hs071Solution()).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace rome
