// DenseQpSolver::Solve() performs no heap allocation once sized: global operator new (std::vector, strings) and,
// outside sanitizer builds, malloc/calloc/realloc (Eigen allocates with std::malloc) are replaced in this test
// binary and count allocations while Solve() runs, over cold, warm, hot (declared, detected, caught lie),
// infeasible, PSD (proximal) and invalid-input solves of every problem family.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "solvers/qp/dense_qp_solver.h"
#include "tests/solvers/qp/qp_test_problems.h"

#include "tests/common/allocation_counter.h"  // replaces operator new/malloc in this binary

namespace rome {
namespace {

long CountAllocationsDuringSolve(DenseQpSolver* solver, QpStatus* status) {
  g_allocations = 0;
  g_counting = true;
  *status = solver->Solve();
  g_counting = false;
  return g_allocations;
}

TEST(DenseQpSolverAllocationTest, CountingWorks) {
  // The counter must see an allocation made inside the counting window, or the test below proves nothing.
  static double* volatile sink = nullptr;  // volatile: the allocation cannot be elided
  EXPECT_EQ(rome::test::CountAllocations([] { sink = new double[16]; }), 1);
  delete[] sink;
#if ROME_COUNT_MALLOC
  // Eigen allocates through malloc; that must be seen too.
  static Eigen::VectorXd* volatile eigen_sink = nullptr;
  eigen_sink = new Eigen::VectorXd(64);
  g_allocations = 0;
  g_counting = true;
  eigen_sink->resize(128);
  g_counting = false;
  delete eigen_sink;
  EXPECT_EQ(g_allocations, 1);
#endif
}

TEST(DenseQpSolverAllocationTest, SolveDoesNotAllocate) {
  std::vector<qp_test::QpProblem> problems;
  qp_test::ClfQpFamily a(3);
  qp_test::TaskSpaceQpFamily b(3);
  qp_test::MpcQpFamily c(20);
  std::mt19937 rng(1);
  for (const auto& family_sample : {a.Sample(0.0), b.Sample(0.0), c.Sample(0.0)}) {
    DenseQpSolver solver(family_sample.n(), family_sample.n_eq(), family_sample.n_ineq());
    for (int tick = 0; tick < 50; ++tick) {
      const double t = 1e-3 * tick;
      const qp_test::QpProblem p = family_sample.n() == 12 ? a.Sample(t) : family_sample.n() == 22 ? b.Sample(t) : c.Sample(t);
      qp_test::LoadInto(p, &solver);
      if (tick % 5 == 0) solver.ResetWarmStart();
      QpStatus status;
      EXPECT_EQ(CountAllocationsDuringSolve(&solver, &status), 0) << "tick " << tick;
      EXPECT_EQ(status, QpStatus::kOptimal);
    }
    // Infeasible: contradictory bound, then an infeasible combination of rows.
    solver.lb[0] = 1.0;
    solver.ub[0] = 0.0;
    QpStatus status;
    EXPECT_EQ(CountAllocationsDuringSolve(&solver, &status), 0);
    EXPECT_EQ(status, QpStatus::kInfeasible);
    solver.lb[0] = 5.0;
    solver.ub[0] = 6.0;
    solver.lb[1] = -6.0;
    solver.ub[1] = -5.0;
    solver.A.row(0).setZero();
    solver.A(0, 0) = 1.0;
    solver.A(0, 1) = 1.0;
    solver.l[0] = 2.0;
    solver.u[0] = 3.0;
    EXPECT_EQ(CountAllocationsDuringSolve(&solver, &status), 0);
    EXPECT_EQ(status, QpStatus::kInfeasible);
    // Invalid input.
    solver.g[0] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(CountAllocationsDuringSolve(&solver, &status), 0);
    EXPECT_EQ(status, QpStatus::kInvalidInput);
  }
  // Hot start on the condensed MPC (declared and detected unchanged matrices), including a caller that changes H
  // behind a declaration (verification fails, full path) and an infeasible tick.
  {
    const qp_test::CondensedMpcSequence sequence(20, 60);
    DenseQpSolver solver(20, 0, 40);
    int hot = 0;
    for (int k = 0; k < sequence.size(); ++k) {
      qp_test::LoadInto(sequence.Problem(k), &solver);
      if (k % 20 == 13) solver.H(0, 0) += 1.0;
      if (k % 20 == 17) solver.ub[0] = solver.lb[0] - 1.0;
      QpStatus status;
      const QpDataChange change = k % 2 == 0 ? QpDataChange::kVectorsOnly : QpDataChange::kUnknown;
      g_allocations = 0;
      g_counting = true;
      status = solver.Solve(change);
      g_counting = false;
      EXPECT_EQ(g_allocations, 0) << "tick " << k;
      EXPECT_EQ(status, k % 20 == 17 ? QpStatus::kInfeasible : QpStatus::kOptimal) << "tick " << k;
      hot += solver.hot_started();
    }
    EXPECT_GT(hot, 40);
  }
  // PSD H (proximal iterations) and random problems with inconsistent equalities.
  for (int trial = 0; trial < 10; ++trial) {
    qp_test::QpProblem p = qp_test::RandomQp(rng, 8, 2, 6, true);
    const Eigen::MatrixXd M = qp_test::RandomMatrix(rng, 3, 8);
    p.H = M.transpose() * M;
    p.lb.setConstant(-3.0);
    p.ub.setConstant(3.0);
    DenseQpSolver solver(8, 2, 6);
    qp_test::LoadInto(p, &solver);
    QpStatus status;
    EXPECT_EQ(CountAllocationsDuringSolve(&solver, &status), 0);
    EXPECT_EQ(status, QpStatus::kOptimal) << solver.status_message();
    solver.A_eq.row(1) = solver.A_eq.row(0);
    solver.b_eq[1] = solver.b_eq[0] + 1.0;
    EXPECT_EQ(CountAllocationsDuringSolve(&solver, &status), 0);
    EXPECT_EQ(status, QpStatus::kInfeasible);
  }
}

}  // namespace
}  // namespace rome
