// Tests of the hot start of rome::DenseQpSolver (kept factorization of the working set across solves with fixed
// matrices). Expected values always come from an independent cold solve (a fresh solver with warm_start off)
// and from the KKT residuals of the problem data, never from the hot path itself.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "solvers/qp/dense_qp_solver.h"
#include "tests/solvers/qp/qp_test_problems.h"

namespace rome {
namespace {

using qp_test::LoadInto;
using qp_test::QpProblem;

constexpr double kKktTolerance = 1e-9;
constexpr double kRelativeAgreement = 1e-9;

// Cold reference: a fresh solver without warm or hot start.
struct ColdSolution {
  QpStatus status;
  Eigen::VectorXd x, y_eq, y_ineq, y_bounds;
  double kkt;
};
ColdSolution SolveCold(const QpProblem& p) {
  QpSettings settings;
  settings.warm_start = false;
  DenseQpSolver cold(p.n(), p.n_eq(), p.n_ineq(), settings);
  LoadInto(p, &cold);
  ColdSolution s;
  s.status = cold.Solve();
  s.x = cold.x();
  s.y_eq = cold.y_eq();
  s.y_ineq = cold.y_ineq();
  s.y_bounds = cold.y_bounds();
  s.kkt = ComputeQpKktResiduals(cold).Max();
  return s;
}

double RelativeDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() == 0) return 0.0;
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

// Hot answers equal cold answers to 1e-9 relative and are KKT-certified on the problem data.
void ExpectMatchesCold(const DenseQpSolver& hot, const QpProblem& p, const std::string& what) {
  const ColdSolution cold = SolveCold(p);
  ASSERT_EQ(cold.status, QpStatus::kOptimal) << what;
  ASSERT_LT(cold.kkt, kKktTolerance) << what;
  EXPECT_LT(RelativeDifference(hot.x(), cold.x), kRelativeAgreement) << what;
  EXPECT_LT(RelativeDifference(hot.y_eq(), cold.y_eq), 1e3 * kRelativeAgreement) << what;
  EXPECT_LT(RelativeDifference(hot.y_ineq(), cold.y_ineq), 1e3 * kRelativeAgreement) << what;
  EXPECT_LT(RelativeDifference(hot.y_bounds(), cold.y_bounds), 1e3 * kRelativeAgreement) << what;
  const QpKktResiduals res = ComputeQpKktResiduals(hot);
  EXPECT_LT(res.Max(), kKktTolerance) << what << ": stationarity " << res.stationarity << ", primal "
                                      << res.primal_feasibility << ", dual " << res.dual_feasibility
                                      << ", complementarity " << res.complementarity;
}

// 200 condensed MPC problems along the MPC's closed loop, N = 20 and 40, both ways of knowing that the matrices
// are unchanged (declared and detected).
TEST(DenseQpHotStartTest, ClosedLoopCondensedMpcMatchesCold) {
  for (int horizon : {20, 40}) {
    const qp_test::CondensedMpcSequence sequence(horizon, 200);
    for (QpDataChange change : {QpDataChange::kVectorsOnly, QpDataChange::kUnknown}) {
      DenseQpSolver hot(horizon, 0, 2 * horizon);
      int hot_solves = 0, changed_working_sets = 0, max_active = 0;
      for (int k = 0; k < sequence.size(); ++k) {
        const QpProblem& p = sequence.Problem(k);
        LoadInto(p, &hot);
        ASSERT_EQ(hot.Solve(k == 0 ? QpDataChange::kUnknown : change), QpStatus::kOptimal) << hot.status_message();
        hot_solves += hot.hot_started();
        changed_working_sets += hot.hot_started() && hot.iterations() > 0;
        max_active = std::max(max_active, hot.active_set_size());
        ExpectMatchesCold(hot, p, "N = " + std::to_string(horizon) + " tick " + std::to_string(k));
      }
      // The hot path answers almost every tick (the first two build the kept factorization; a refresh is due
      // every 400 rank-one updates), and the sequence does move the working set.
      EXPECT_GE(hot_solves, 190) << "N = " << horizon;
      EXPECT_GT(changed_working_sets, 10) << "N = " << horizon;
      EXPECT_GT(max_active, 3) << "N = " << horizon;
    }
  }
}

// Sparse-form MPC (equalities: dynamics; only b_eq, g and bounds move) and the vertical-COM shape.
TEST(DenseQpHotStartTest, MpcWithEqualitiesMatchesCold) {
  qp_test::MpcQpFamily family(20);
  DenseQpSolver hot(1, 0, 0);
  int hot_solves = 0;
  for (int tick = 0; tick < 200; ++tick) {
    const QpProblem p = family.Sample(0.01 * tick);
    LoadInto(p, &hot);
    ASSERT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kOptimal) << hot.status_message();
    hot_solves += hot.hot_started();
    ExpectMatchesCold(hot, p, "family C tick " + std::to_string(tick));
  }
  EXPECT_GE(hot_solves, 190);
}

// A caller that changes a matrix while declaring it unchanged still gets the right answer (verified, then the
// full path), and the hot start resumes afterwards.
TEST(DenseQpHotStartTest, LyingCallerGetsTheRightAnswer) {
  const int horizon = 20;
  const qp_test::CondensedMpcSequence sequence(horizon, 120);
  DenseQpSolver hot(horizon, 0, 2 * horizon);
  int caught = 0;
  for (int k = 0; k < sequence.size(); ++k) {
    QpProblem p = sequence.Problem(k);
    const int lie = k % 10;
    if (lie == 3) p.H *= 1.5;                               // weights changed
    if (lie == 5) p.H(2, 2) += 1e-3;                        // a small change of H
    if (lie == 7) p.A.row(4) *= 2.0, p.u[4] *= 2.0, p.l[4] *= 2.0;  // the same set, rescaled row
    if (lie == 8) p.A(2 * horizon - 1, 0) += 0.5;           // a changed constraint row
    LoadInto(p, &hot);
    ASSERT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kOptimal) << "tick " << k << ": " << hot.status_message();
    if (k > 2 && (lie == 3 || lie == 5 || lie == 8)) caught += !hot.hot_started();
    ExpectMatchesCold(hot, p, "lie " + std::to_string(lie) + " tick " + std::to_string(k));
  }
  EXPECT_GT(caught, 20);  // the changes of H and A that move the solution are caught by the verification
  // A non-finite matrix entry behind a declaration: still reported as invalid input.
  hot.H(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kInvalidInput);
  EXPECT_NE(hot.status_message().find("H(1, 1)"), std::string::npos) << hot.status_message();
  // A non-symmetric H behind a declaration whose solution changes: reported.
  LoadInto(sequence.Problem(0), &hot);
  ASSERT_EQ(hot.Solve(), QpStatus::kOptimal);
  hot.H(0, 1) += 5.0;
  EXPECT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kInvalidInput);
  EXPECT_NE(hot.status_message().find("not symmetric"), std::string::npos) << hot.status_message();
}

// Every status from a hot state: infeasible (contradictory bounds and an infeasible combination of rows),
// invalid vectors, iteration limit, and back to optimal.
TEST(DenseQpHotStartTest, EveryStatusFromAHotState) {
  const int horizon = 20;
  const qp_test::CondensedMpcSequence sequence(horizon, 10);
  DenseQpSolver hot(horizon, 0, 2 * horizon);
  auto warm_up = [&]() {
    for (int k = 0; k < sequence.size(); ++k) {
      LoadInto(sequence.Problem(k), &hot);
      ASSERT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kOptimal);
    }
    ASSERT_TRUE(hot.hot_started());
  };
  warm_up();
  hot.lb[3] = 1.0;
  hot.ub[3] = 0.5;
  EXPECT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kInfeasible);
  EXPECT_EQ(hot.infeasible_constraints(), (std::vector<int>{2 * horizon + 3}));
  warm_up();
  // p_1 = dt^2/2 a_0 + p_1^free >= 0.99 (p_max = 1) cannot hold with a_0 <= 2 from rest far below.
  hot.l[0] = 0.5;
  EXPECT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kInfeasible) << hot.status_message();
  const std::vector<int>& certificate = hot.infeasible_constraints();
  EXPECT_NE(std::find(certificate.begin(), certificate.end(), 0), certificate.end()) << hot.status_message();
  warm_up();
  hot.g[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kInvalidInput);
  EXPECT_NE(hot.status_message().find("g[0]"), std::string::npos) << hot.status_message();
  warm_up();
  hot.g *= -3.0;  // a far-away optimum: many working-set changes
  hot.settings().max_iterations = 1;
  EXPECT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kMaxIterations);
  hot.settings().max_iterations = 1000;
  ASSERT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kOptimal);
  QpProblem p = sequence.Problem(sequence.size() - 1);
  p.g *= -3.0;
  ExpectMatchesCold(hot, p, "after the iteration limit");
  // A bound of the working set becoming infinite leaves the working set.
  warm_up();
  for (int j = 0; j < horizon; ++j) {
    hot.lb[j] = -std::numeric_limits<double>::infinity();
    hot.ub[j] = std::numeric_limits<double>::infinity();
  }
  ASSERT_EQ(hot.Solve(QpDataChange::kVectorsOnly), QpStatus::kOptimal);
  p = sequence.Problem(sequence.size() - 1);
  p.lb = hot.lb;
  p.ub = hot.ub;
  ExpectMatchesCold(hot, p, "bounds removed");
}

// Matrices that change every tick (CLF-QP, task-space shapes) never use the hot path and pay no copies for it.
TEST(DenseQpHotStartTest, ChangingMatricesNeverHotStart) {
  qp_test::ClfQpFamily family_a(5);
  qp_test::TaskSpaceQpFamily family_b(5);
  for (int family = 0; family < 2; ++family) {
    DenseQpSolver solver(1, 0, 0);
    for (int tick = 0; tick < 50; ++tick) {
      const QpProblem p = family == 0 ? family_a.Sample(1e-3 * tick) : family_b.Sample(1e-3 * tick);
      LoadInto(p, &solver);
      ASSERT_EQ(solver.Solve(), QpStatus::kOptimal);
      EXPECT_FALSE(solver.hot_started());
      ExpectMatchesCold(solver, p, "family " + std::to_string(family) + " tick " + std::to_string(tick));
    }
  }
}

}  // namespace
}  // namespace rome
