// Agreement of rome::DenseQpSolver with Ipopt (interior point, MUMPS) on the same QPs: random problems of
// assorted sizes and the three controller families of the benchmark. Ipopt 3.11 with MUMPS is not
// thread-safe, so every Ipopt solve holds one process-wide mutex.

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>
#include <gtest/gtest.h>

#include <mutex>

#include "solvers/nlp/ipopt_solver.h"  // rome::IpoptMutex(): the one process-wide Ipopt lock
#include <random>

#include "solvers/qp/dense_qp_solver.h"
#include "tests/solvers/qp/qp_test_problems.h"

namespace rome {
namespace {

using qp_test::QpProblem;

// The QP as an Ipopt NLP: constraints [A_eq; A] x with bounds [b_eq, b_eq; l, u], variable bounds lb, ub.
class QpTnlp : public Ipopt::TNLP {
 public:
  explicit QpTnlp(const QpProblem& p) : p_(p) {}
  Eigen::VectorXd x;

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = p_.n();
    m = p_.n_eq() + p_.n_ineq();
    nnz_jac = n * m;
    nnz_h = n * (n + 1) / 2;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override {
    for (int j = 0; j < n; ++j) {
      x_l[j] = std::isinf(p_.lb[j]) ? -2e19 : p_.lb[j];
      x_u[j] = std::isinf(p_.ub[j]) ? 2e19 : p_.ub[j];
    }
    for (int i = 0; i < p_.n_eq(); ++i) g_l[i] = g_u[i] = p_.b_eq[i];
    for (int i = 0; i < p_.n_ineq(); ++i) {
      g_l[p_.n_eq() + i] = std::isinf(p_.l[i]) ? -2e19 : p_.l[i];
      g_u[p_.n_eq() + i] = std::isinf(p_.u[i]) ? 2e19 : p_.u[i];
    }
    (void)m;
    return true;
  }
  bool get_starting_point(Ipopt::Index n, bool, Ipopt::Number* x0, bool, Ipopt::Number*, Ipopt::Number*,
                          Ipopt::Index, bool, Ipopt::Number*) override {
    for (int j = 0; j < n; ++j) x0[j] = 0.0;
    return true;
  }
  bool eval_f(Ipopt::Index n, const Ipopt::Number* xv, bool, Ipopt::Number& f) override {
    const Eigen::Map<const Eigen::VectorXd> xm(xv, n);
    f = 0.5 * xm.dot(p_.H * xm) + p_.g.dot(xm);
    return true;
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* xv, bool, Ipopt::Number* grad) override {
    const Eigen::Map<const Eigen::VectorXd> xm(xv, n);
    Eigen::Map<Eigen::VectorXd>(grad, n) = p_.H * xm + p_.g;
    return true;
  }
  bool eval_g(Ipopt::Index n, const Ipopt::Number* xv, bool, Ipopt::Index m, Ipopt::Number* gv) override {
    const Eigen::Map<const Eigen::VectorXd> xm(xv, n);
    Eigen::Map<Eigen::VectorXd> out(gv, m);
    out.head(p_.n_eq()) = p_.A_eq * xm;
    out.tail(p_.n_ineq()) = p_.A * xm;
    return true;
  }
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number*, bool, Ipopt::Index m, Ipopt::Index, Ipopt::Index* rows,
                  Ipopt::Index* cols, Ipopt::Number* values) override {
    int k = 0;
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < n; ++j, ++k) {
        if (values == nullptr) {
          rows[k] = i;
          cols[k] = j;
        } else {
          values[k] = i < p_.n_eq() ? p_.A_eq(i, j) : p_.A(i - p_.n_eq(), j);
        }
      }
    }
    return true;
  }
  bool eval_h(Ipopt::Index n, const Ipopt::Number*, bool, Ipopt::Number obj_factor, Ipopt::Index, const Ipopt::Number*,
              bool, Ipopt::Index, Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) override {
    int k = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j <= i; ++j, ++k) {
        if (values == nullptr) {
          rows[k] = i;
          cols[k] = j;
        } else {
          values[k] = obj_factor * p_.H(i, j);
        }
      }
    }
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* xv, const Ipopt::Number*,
                         const Ipopt::Number*, Ipopt::Index, const Ipopt::Number*, const Ipopt::Number*, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    x = Eigen::Map<const Eigen::VectorXd>(xv, n);
  }

 private:
  const QpProblem& p_;
};

Eigen::VectorXd SolveWithIpopt(const QpProblem& p) {
  std::lock_guard<std::mutex> lock(IpoptMutex());
  Ipopt::SmartPtr<QpTnlp> nlp = new QpTnlp(p);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", 1e-12);
  app->Options()->SetNumericValue("constr_viol_tol", 1e-12);
  app->Options()->SetStringValue("mehrotra_algorithm", "yes");
  app->Options()->SetStringValue("hessian_constant", "yes");
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  app->Options()->SetIntegerValue("max_iter", 500);
  app->Options()->SetNumericValue("bound_relax_factor", 0.0);  // Ipopt relaxes bounds by 1e-8 by default
  EXPECT_EQ(app->Initialize(), Ipopt::Solve_Succeeded);
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  EXPECT_TRUE(status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level)
      << "Ipopt status " << static_cast<int>(status);
  return nlp->x;
}

void ExpectAgreement(const QpProblem& p, const std::string& what, double* worst) {
  DenseQpSolver solver(p.n(), p.n_eq(), p.n_ineq());
  qp_test::LoadInto(p, &solver);
  ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << what << ": " << solver.status_message();
  const Eigen::VectorXd x_ipopt = SolveWithIpopt(p);
  ASSERT_EQ(x_ipopt.size(), p.n());
  const double dx = (solver.x() - x_ipopt).lpNorm<Eigen::Infinity>() / (1.0 + x_ipopt.lpNorm<Eigen::Infinity>());
  EXPECT_LT(dx, 1e-6) << what;
  *worst = std::max(*worst, dx);
  const double f_ipopt = 0.5 * x_ipopt.dot(p.H * x_ipopt) + p.g.dot(x_ipopt);
  EXPECT_NEAR(solver.objective(), f_ipopt, 1e-8 * (1.0 + std::abs(f_ipopt))) << what;
}

TEST(DenseQpSolverIpoptTest, RandomProblemsAgreeWithIpopt) {
  std::mt19937 rng(314159);
  double worst = 0.0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = std::uniform_int_distribution<int>(2, 25)(rng);
    const int n_eq = std::uniform_int_distribution<int>(0, n / 3)(rng);
    const int n_ineq = std::uniform_int_distribution<int>(0, 2 * n)(rng);
    ExpectAgreement(qp_test::RandomQp(rng, n, n_eq, n_ineq, trial % 2 == 0), "random " + std::to_string(trial),
                    &worst);
  }
  RecordProperty("worst_relative_dx", std::to_string(worst));
  std::printf("random problems: worst |x - x_ipopt|_inf / (1 + |x_ipopt|_inf) = %.3g\n", worst);
}

TEST(DenseQpSolverIpoptTest, ControllerFamiliesAgreeWithIpopt) {
  double worst = 0.0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    ExpectAgreement(qp_test::ClfQpFamily(seed).Sample(0.1 * seed), "CLF-QP", &worst);
    ExpectAgreement(qp_test::TaskSpaceQpFamily(seed).Sample(0.1 * seed), "task-space QP", &worst);
  }
  ExpectAgreement(qp_test::MpcQpFamily(20).Sample(0.4), "MPC N=20", &worst);
  ExpectAgreement(qp_test::MpcQpFamily(40).Sample(1.3), "MPC N=40", &worst);
  std::printf("controller families: worst |x - x_ipopt|_inf / (1 + |x_ipopt|_inf) = %.3g\n", worst);
}

}  // namespace
}  // namespace rome
