// Tests of rome::DenseQpSolver: KKT conditions on random families, closed-form references (equality-only KKT
// solve, clipping for diagonal H), infeasibility certificates, degenerate vertices, PSD / non-convex H,
// warm start and input validation. Ipopt agreement and the no-allocation check live in their own binaries.

#include "solvers/qp/dense_qp_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/solvers/qp/qp_test_problems.h"

namespace rome {
namespace {

using qp_test::kInf;
using qp_test::LoadInto;
using qp_test::QpProblem;

constexpr double kKktTolerance = 1e-9;

void ExpectKkt(const DenseQpSolver& solver, const std::string& what) {
  const QpKktResiduals res = ComputeQpKktResiduals(solver);
  EXPECT_LT(res.Max(), kKktTolerance) << what << ": stationarity " << res.stationarity << ", primal "
                                      << res.primal_feasibility << ", dual " << res.dual_feasibility
                                      << ", complementarity " << res.complementarity;
}

TEST(DenseQpSolverTest, RandomProblemsSatisfyKkt) {
  std::mt19937 rng(20240611);
  double worst = 0.0;
  int total_active = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = std::uniform_int_distribution<int>(1, 30)(rng);
    const int n_eq = std::uniform_int_distribution<int>(0, n / 2)(rng);
    const int n_ineq = std::uniform_int_distribution<int>(0, 2 * n)(rng);
    const bool bounds = trial % 3 != 0;
    const QpProblem p = qp_test::RandomQp(rng, n, n_eq, n_ineq, bounds);
    DenseQpSolver solver(n, n_eq, n_ineq);
    LoadInto(p, &solver);
    ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << "trial " << trial << ": " << solver.status_message();
    ExpectKkt(solver, "random trial " + std::to_string(trial));
    worst = std::max(worst, ComputeQpKktResiduals(solver).Max());
    total_active += solver.active_set_size();
    // Objective reported consistently with x.
    EXPECT_NEAR(solver.objective(), 0.5 * solver.x().dot(p.H * solver.x()) + p.g.dot(solver.x()),
                1e-9 * (1.0 + std::abs(solver.objective())));
  }
  EXPECT_GT(total_active, 200);  // the family really exercises active constraints
  RecordProperty("worst_kkt", std::to_string(worst));
}

TEST(DenseQpSolverTest, ControllerFamiliesSatisfyKkt) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    qp_test::ClfQpFamily family_a(seed);
    qp_test::TaskSpaceQpFamily family_b(seed);
    for (double t : {0.0, 0.13, 0.61}) {
      for (const QpProblem& p : {family_a.Sample(t), family_b.Sample(t)}) {
        DenseQpSolver solver(p.n(), p.n_eq(), p.n_ineq());
        LoadInto(p, &solver);
        ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << solver.status_message();
        ExpectKkt(solver, "family seed " + std::to_string(seed));
        const int active_inequalities = solver.active_set_size() - p.n_eq();
        EXPECT_GE(active_inequalities, 2) << "family problems should have several active constraints";
      }
    }
  }
  for (int horizon : {20, 40}) {
    qp_test::MpcQpFamily family_c(horizon);
    for (double t : {0.0, 0.3, 1.1, 2.0}) {
      const QpProblem p = family_c.Sample(t);
      DenseQpSolver solver(p.n(), p.n_eq(), p.n_ineq());
      LoadInto(p, &solver);
      ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << solver.status_message();
      ExpectKkt(solver, "MPC horizon " + std::to_string(horizon));
      EXPECT_GE(solver.active_set_size() - p.n_eq(), 2);
    }
  }
}

TEST(DenseQpSolverTest, EqualityOnlyMatchesKktLinearSolve) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 3 + trial;
    const int n_eq = 1 + trial / 2;
    const QpProblem p = qp_test::RandomQp(rng, n, n_eq, 0, false);
    DenseQpSolver solver(n, n_eq, 0);
    LoadInto(p, &solver);
    ASSERT_EQ(solver.Solve(), QpStatus::kOptimal);
    // [H A^T; A 0] [x; y] = [-g; b] with y in the solver's sign convention (H x + g + A^T y = 0).
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + n_eq, n + n_eq);
    K.topLeftCorner(n, n) = p.H;
    K.topRightCorner(n, n_eq) = p.A_eq.transpose();
    K.bottomLeftCorner(n_eq, n) = p.A_eq;
    Eigen::VectorXd rhs(n + n_eq);
    rhs << -p.g, p.b_eq;
    const Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
    EXPECT_LT((solver.x() - sol.head(n)).lpNorm<Eigen::Infinity>(), 1e-10);
    EXPECT_LT((solver.y_eq() - sol.tail(n_eq)).lpNorm<Eigen::Infinity>(), 1e-9);
    EXPECT_EQ(solver.iterations(), 0);
  }
}

TEST(DenseQpSolverTest, BoundOnlyDiagonalHessianIsClipping) {
  std::mt19937 rng(11);
  const int n = 25;
  for (int trial = 0; trial < 20; ++trial) {
    DenseQpSolver solver(n, 0, 0);
    solver.H.setZero();
    Eigen::VectorXd expected(n);
    for (int j = 0; j < n; ++j) {
      const double h = qp_test::Uniform(rng, 0.1, 10.0);
      solver.H(j, j) = h;
      solver.g[j] = qp_test::Uniform(rng, -5.0, 5.0);
      solver.lb[j] = (j % 5 == 0) ? -kInf : qp_test::Uniform(rng, -1.0, 0.0);
      solver.ub[j] = (j % 7 == 0) ? kInf : qp_test::Uniform(rng, 0.0, 1.0);
      expected[j] = std::clamp(-solver.g[j] / h, solver.lb[j], solver.ub[j]);
    }
    ASSERT_EQ(solver.Solve(), QpStatus::kOptimal);
    EXPECT_LT((solver.x() - expected).lpNorm<Eigen::Infinity>(), 1e-12);
    ExpectKkt(solver, "bound-only");
    // Multiplier of an active bound is the gradient there: y = -(h x + g).
    for (int j = 0; j < n; ++j) {
      EXPECT_NEAR(solver.y_bounds()[j], -(solver.H(j, j) * expected[j] + solver.g[j]), 1e-12);
    }
  }
}

TEST(DenseQpSolverTest, ContradictoryBoundsAreInfeasibleWithIndex) {
  DenseQpSolver solver(3, 1, 2);
  solver.H.setIdentity();
  solver.A_eq << 1, 1, 1;
  solver.b_eq << 1;
  solver.A << 1, 0, 0, 0, 1, 0;
  solver.lb[2] = 1.0;
  solver.ub[2] = 0.5;
  EXPECT_EQ(solver.Solve(), QpStatus::kInfeasible);
  ASSERT_EQ(solver.infeasible_constraints().size(), 1u);
  EXPECT_EQ(solver.infeasible_constraints()[0], 1 + 2 + 2);  // bound on x[2]
  EXPECT_NE(solver.status_message().find("x[2]"), std::string::npos) << solver.status_message();

  solver.lb[2] = -kInf;
  solver.l[1] = 2.0;
  solver.u[1] = 1.0;
  EXPECT_EQ(solver.Solve(), QpStatus::kInfeasible);
  ASSERT_EQ(solver.infeasible_constraints().size(), 1u);
  EXPECT_EQ(solver.infeasible_constraints()[0], 1 + 1);  // inequality row 1
  EXPECT_NE(solver.status_message().find("row 1"), std::string::npos) << solver.status_message();
}

TEST(DenseQpSolverTest, InconsistentEqualitiesAreInfeasible) {
  DenseQpSolver solver(3, 3, 0);
  solver.H.setIdentity();
  solver.A_eq << 1, 1, 0,  //
      0, 1, 1,             //
      1, 2, 1;             // = row 0 + row 1, but right-hand side inconsistent
  solver.b_eq << 1, 1, 3;
  EXPECT_EQ(solver.Solve(), QpStatus::kInfeasible);
  std::vector<int> idx = solver.infeasible_constraints();
  std::sort(idx.begin(), idx.end());
  EXPECT_EQ(idx, (std::vector<int>{0, 1, 2}));
  // The same rows with a consistent right-hand side are redundant but solvable.
  solver.b_eq << 1, 1, 2;
  ASSERT_EQ(solver.Solve(), QpStatus::kOptimal);
  ExpectKkt(solver, "consistent redundant equalities");
}

TEST(DenseQpSolverTest, InfeasibleInequalitiesReportCertificate) {
  // x0 + x1 >= 3 with x0 <= 1, x1 <= 1: the row and both upper bounds are the infeasible subset; row 1 is not.
  DenseQpSolver solver(2, 0, 2);
  solver.H.setIdentity();
  solver.g << 1, -1;
  solver.A << 1, 1,  //
      1, -1;
  solver.l << 3, -5;
  solver.u << kInf, 5;
  solver.ub << 1, 1;
  EXPECT_EQ(solver.Solve(), QpStatus::kInfeasible) << solver.status_message();
  std::vector<int> idx = solver.infeasible_constraints();
  std::sort(idx.begin(), idx.end());
  EXPECT_EQ(idx, (std::vector<int>{0, 2, 3}));  // row 0, bounds on x0 and x1
  EXPECT_NE(solver.status_message().find("inequality row 0"), std::string::npos);
}

TEST(DenseQpSolverTest, LongInfeasibleSubsetKeepsTheMessageShort) {
  // Σ x_i = 0 with every x_i ≥ 1 (n = 10): no proper subset is infeasible, so all 11 constraints are reported by
  // infeasible_constraints(); the message names the first 6 and counts the other 5.
  const int n = 10;
  DenseQpSolver solver(n, 1, 0);
  solver.H.setIdentity();
  solver.g.setZero();
  solver.A_eq.setOnes();
  solver.b_eq << 0.0;
  solver.lb.setOnes();
  ASSERT_EQ(solver.Solve(), QpStatus::kInfeasible) << solver.status_message();
  EXPECT_EQ(solver.infeasible_constraints().size(), 11u);
  const std::string m = solver.status_message();
  EXPECT_NE(m.find("and 5 more (infeasible_constraints())"), std::string::npos) << m;
  EXPECT_LT(m.size(), 400u) << m;
}

TEST(DenseQpSolverTest, RandomInfeasibleCertificatesAreInfeasibleSubsets) {
  // Random problems made infeasible by one contradicting row; verify the reported subset alone is infeasible.
  std::mt19937 rng(99);
  int checked = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 6;
    QpProblem p = qp_test::RandomQp(rng, n, 2, 8, true);
    // Contradicting row: -(sum of two rows) bounded in a way impossible with the originals' bounds.
    p.A.row(7) = -(p.A.row(0) + p.A.row(1));
    if (!std::isfinite(p.u[0]) || !std::isfinite(p.u[1])) continue;
    p.u[7] = kInf;
    p.l[0] = p.u[0] - 0.1;
    p.l[1] = p.u[1] - 0.1;
    p.l[7] = -(p.l[0] + p.l[1]) + 0.5;  // A0x + A1x <= l0 + l1 - 0.5 contradicts A0x >= l0, A1x >= l1
    DenseQpSolver solver(n, 2, 8);
    LoadInto(p, &solver);
    ASSERT_EQ(solver.Solve(), QpStatus::kInfeasible) << solver.status_message();
    const std::vector<int> idx = solver.infeasible_constraints();
    ASSERT_FALSE(idx.empty());
    // Keep only the reported constraints and solve again: still infeasible.
    DenseQpSolver subset(n, 2, 8);
    LoadInto(p, &subset);
    std::vector<bool> keep(2 + 8 + n, false);
    for (int i : idx) keep[i] = true;
    for (int i = 0; i < 2; ++i) {
      if (!keep[i]) subset.A_eq.row(i).setZero(), subset.b_eq[i] = 0.0;
    }
    for (int i = 0; i < 8; ++i) {
      if (!keep[2 + i]) subset.l[i] = -kInf, subset.u[i] = kInf;
    }
    for (int j = 0; j < n; ++j) {
      if (!keep[10 + j]) subset.lb[j] = -kInf, subset.ub[j] = kInf;
    }
    EXPECT_EQ(subset.Solve(), QpStatus::kInfeasible) << "trial " << trial;
    ++checked;
  }
  EXPECT_GT(checked, 5);
}

TEST(DenseQpSolverTest, DegenerateVertexWithManyActiveConstraints) {
  // Minimum at the origin of the plane where 2 bounds and 4 rows (all through the origin) are active.
  DenseQpSolver solver(2, 0, 5);
  solver.H << 2, 0.5, 0.5, 1;
  solver.g << 3, 4;
  solver.A << 1, 1,  //
      1, 2,          //
      2, 1,          //
      1, 1,          // duplicate of row 0
      1, 3;
  solver.l.setZero();
  solver.lb.setZero();
  ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << solver.status_message();
  EXPECT_LT(solver.x().lpNorm<Eigen::Infinity>(), 1e-12);
  ExpectKkt(solver, "degenerate vertex");

  // Random degenerate problems: many constraints through the same point x_star, plus duplicated rows.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 8;
    const int m = 16;
    QpProblem p = qp_test::RandomQp(rng, n, 1, m, false);
    const Eigen::VectorXd x_star = qp_test::RandomMatrix(rng, n, 1);
    p.b_eq = p.A_eq * x_star;
    for (int i = 0; i < m; ++i) {
      if (i >= m / 2) p.A.row(i) = p.A.row(i - m / 2);  // duplicated rows
      p.l[i] = p.A.row(i).dot(x_star);
      p.u[i] = kInf;
    }
    DenseQpSolver solver2(n, 1, m);
    LoadInto(p, &solver2);
    ASSERT_EQ(solver2.Solve(), QpStatus::kOptimal) << solver2.status_message();
    ExpectKkt(solver2, "random degenerate " + std::to_string(trial));
    // Warm-started re-solves with a perturbed gradient agree with fresh solves.
    for (int k = 0; k < 3; ++k) {
      p.g += 0.05 * qp_test::RandomMatrix(rng, n, 1);
      solver2.g = p.g;
      DenseQpSolver fresh(n, 1, m);
      LoadInto(p, &fresh);
      ASSERT_EQ(solver2.Solve(), QpStatus::kOptimal) << solver2.status_message();
      ASSERT_EQ(fresh.Solve(), QpStatus::kOptimal) << fresh.status_message();
      EXPECT_LT((solver2.x() - fresh.x()).lpNorm<Eigen::Infinity>(), 1e-9);
      ExpectKkt(solver2, "warm degenerate " + std::to_string(trial));
    }
  }
}

TEST(DenseQpSolverTest, DuplicatedEqualityRowsStillSolve) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 10;
    const QpProblem p = qp_test::RandomQp(rng, n, 3, 12, true);
    DenseQpSolver reference(n, 3, 12);
    LoadInto(p, &reference);
    ASSERT_EQ(reference.Solve(), QpStatus::kOptimal);
    // Same problem with equality rows duplicated, scaled and combined.
    QpProblem q = p;
    q.A_eq.resize(6, n);
    q.b_eq.resize(6);
    q.A_eq << p.A_eq, p.A_eq.row(0), 2.0 * p.A_eq.row(1), p.A_eq.row(0) - p.A_eq.row(2);
    q.b_eq << p.b_eq, p.b_eq[0], 2.0 * p.b_eq[1], p.b_eq[0] - p.b_eq[2];
    DenseQpSolver solver(n, 6, 12);
    LoadInto(q, &solver);
    ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << solver.status_message();
    EXPECT_LT((solver.x() - reference.x()).lpNorm<Eigen::Infinity>(), 1e-9);
    ExpectKkt(solver, "duplicated equalities");
  }
}

TEST(DenseQpSolverTest, EdgeSizes) {
  DenseQpSolver empty(0, 0, 0);
  EXPECT_EQ(empty.Solve(), QpStatus::kOptimal) << empty.status_message();
  EXPECT_EQ(empty.objective(), 0.0);
  // More (consistent) equalities than variables: the unique point of the equalities.
  DenseQpSolver over(2, 4, 0);
  over.H.setIdentity();
  over.g << 3, -1;
  over.A_eq << 1, 0, 0, 1, 1, 1, 1, -1;
  over.b_eq << 0.5, -2, -1.5, 2.5;
  ASSERT_EQ(over.Solve(), QpStatus::kOptimal) << over.status_message();
  EXPECT_LT((over.x() - Eigen::Vector2d(0.5, -2)).lpNorm<Eigen::Infinity>(), 1e-14);
  ExpectKkt(over, "overdetermined equalities");
  over.g << -1, 4;  // warm-started second solve with n_eq > n
  ASSERT_EQ(over.Solve(), QpStatus::kOptimal) << over.status_message();
  EXPECT_LT((over.x() - Eigen::Vector2d(0.5, -2)).lpNorm<Eigen::Infinity>(), 1e-14);
  // A vertex fixed by n active inequalities, warm-started repeatedly (full-rank active set, q == n).
  DenseQpSolver vertex(2, 0, 2);
  vertex.H.setIdentity();
  vertex.A << 1, 1, 1, -1;
  vertex.l << 1, -kInf;
  vertex.u << kInf, 0;
  for (int k = 0; k < 3; ++k) {
    vertex.g << -0.1 * k, 2.0;
    ASSERT_EQ(vertex.Solve(), QpStatus::kOptimal) << vertex.status_message();
    EXPECT_LT((vertex.x() - Eigen::Vector2d(0.5, 0.5)).lpNorm<Eigen::Infinity>(), 1e-14);
    ExpectKkt(vertex, "vertex");
    if (k > 0) {
      EXPECT_EQ(vertex.iterations(), 0);  // previous active set is still optimal
    }
  }
}

TEST(DenseQpSolverTest, NonConvexHessianIsRejected) {
  DenseQpSolver solver(3, 0, 0);
  solver.H << 1, 0, 0, 0, -0.5, 0, 0, 0, 2;
  solver.lb.setConstant(-1);
  solver.ub.setConstant(1);
  EXPECT_EQ(solver.Solve(), QpStatus::kNonConvex);
  EXPECT_NE(solver.status_message().find("positive semidefinite"), std::string::npos);
  // Indefinite with a positive diagonal.
  solver.H << 1, 2, 0, 2, 1, 0, 0, 0, 1;
  EXPECT_EQ(solver.Solve(), QpStatus::kNonConvex);
}

TEST(DenseQpSolverTest, SemidefiniteHessianIsSolvedExactly) {
  // min 1/2 x0^2 + x0 - x1 (no curvature in x1) s.t. x0 + x1 <= 0.25, x1 <= 1.5.
  DenseQpSolver solver(2, 0, 1);
  solver.H << 1, 0, 0, 0;
  solver.g << 1, -1;
  solver.A << 1, 1;
  solver.u << 0.25;
  solver.ub[1] = 1.5;
  ASSERT_EQ(solver.Solve(), QpStatus::kOptimal) << solver.status_message();
  // KKT by hand: the row binds (x0 + x1 = 0.25), x1 at its bound 1.5 -> x0 = -1.25.
  EXPECT_NEAR(solver.x()[0], -1.25, 1e-10);
  EXPECT_NEAR(solver.x()[1], 1.5, 1e-10);
  ExpectKkt(solver, "PSD H");

  // Random PSD (rank-deficient) H with bounds everywhere: KKT of the original problem.
  std::mt19937 rng(17);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 8;
    QpProblem p = qp_test::RandomQp(rng, n, 2, 6, true);
    const Eigen::MatrixXd M = qp_test::RandomMatrix(rng, 3, n);
    p.H = M.transpose() * M;  // rank 3
    for (int j = 0; j < n; ++j) {
      if (!std::isfinite(p.lb[j])) p.lb[j] = -5.0;
      if (!std::isfinite(p.ub[j])) p.ub[j] = 5.0;
    }
    DenseQpSolver s(n, 2, 6);
    LoadInto(p, &s);
    ASSERT_EQ(s.Solve(), QpStatus::kOptimal) << "trial " << trial << ": " << s.status_message();
    ExpectKkt(s, "random PSD " + std::to_string(trial));
  }

  // An LP (H = 0) over a box: a vertex.
  DenseQpSolver lp(3, 0, 0);
  lp.g << 1, -2, 3;
  lp.lb.setConstant(-1);
  lp.ub.setConstant(2);
  ASSERT_EQ(lp.Solve(), QpStatus::kOptimal) << lp.status_message();
  EXPECT_LT((lp.x() - Eigen::Vector3d(-1, 2, -1)).lpNorm<Eigen::Infinity>(), 1e-10);
  ExpectKkt(lp, "LP");
}

TEST(DenseQpSolverTest, UnboundedSemidefiniteProblemIsReported) {
  DenseQpSolver solver(2, 0, 0);
  solver.H << 1, 0, 0, 0;
  solver.g << 0, -1;
  solver.lb[1] = 0.0;
  EXPECT_EQ(solver.Solve(), QpStatus::kUnbounded) << solver.status_message();
}

TEST(DenseQpSolverTest, WarmStartMatchesColdWithFewerIterations) {
  qp_test::ClfQpFamily family_a(42);
  qp_test::TaskSpaceQpFamily family_b(42);
  qp_test::MpcQpFamily family_c(30);
  for (int family = 0; family < 3; ++family) {
    DenseQpSolver warm(1, 0, 0), cold(1, 0, 0);
    int warm_iterations = 0, cold_iterations = 0;
    for (int tick = 0; tick < 200; ++tick) {
      const double t = 1e-3 * tick;
      const QpProblem p = family == 0 ? family_a.Sample(t) : family == 1 ? family_b.Sample(t) : family_c.Sample(t);
      LoadInto(p, &warm);
      LoadInto(p, &cold);
      cold.ResetWarmStart();
      ASSERT_EQ(warm.Solve(), QpStatus::kOptimal) << warm.status_message();
      ASSERT_EQ(cold.Solve(), QpStatus::kOptimal) << cold.status_message();
      EXPECT_LT((warm.x() - cold.x()).lpNorm<Eigen::Infinity>(), 1e-10) << "family " << family << " tick " << tick;
      ExpectKkt(warm, "warm");
      if (tick > 0) {
        warm_iterations += warm.iterations();
        cold_iterations += cold.iterations();
      }
    }
    EXPECT_LT(warm_iterations, cold_iterations / 2) << "family " << family;
  }
}

TEST(DenseQpSolverTest, CachedFactorizationsMatchFreshSolver) {
  // Constant H (MPC): the Cholesky factor and the equality part of the factorization are reused across
  // solves. Changing A_eq, H or b_eq between solves must give exactly what a fresh solver gives.
  qp_test::MpcQpFamily family(15);
  DenseQpSolver reused(1, 0, 0);
  std::mt19937 rng(8);
  for (int tick = 0; tick < 40; ++tick) {
    QpProblem p = family.Sample(0.01 * tick);
    if (tick % 10 == 5) p.A_eq(3, 4) += 0.01;  // dynamics change: equality cache invalid
    if (tick % 10 == 7) p.H(0, 0) += 0.5;      // weight change: factorization invalid
    if (tick % 10 == 8) p.A.row(2) *= 2.0;     // scaled inequality row (row norms recomputed)
    LoadInto(p, &reused);
    DenseQpSolver fresh(p.n(), p.n_eq(), p.n_ineq());
    LoadInto(p, &fresh);
    ASSERT_EQ(reused.Solve(), QpStatus::kOptimal) << reused.status_message();
    ASSERT_EQ(fresh.Solve(), QpStatus::kOptimal) << fresh.status_message();
    EXPECT_LT((reused.x() - fresh.x()).lpNorm<Eigen::Infinity>(), 1e-10) << "tick " << tick;
    EXPECT_LT((reused.y_eq() - fresh.y_eq()).lpNorm<Eigen::Infinity>(), 1e-8) << "tick " << tick;
    ExpectKkt(reused, "cached factorization tick " + std::to_string(tick));
  }
  // Constant H and A_eq with an inconsistent duplicated equality appearing: detected through the cache.
  QpProblem p = family.Sample(0.0);
  p.A_eq.row(1) = p.A_eq.row(0);
  p.b_eq[1] = p.b_eq[0];
  LoadInto(p, &reused);
  ASSERT_EQ(reused.Solve(), QpStatus::kOptimal) << reused.status_message();
  reused.b_eq[1] += 1.0;
  EXPECT_EQ(reused.Solve(), QpStatus::kInfeasible);
  std::vector<int> idx = reused.infeasible_constraints();
  std::sort(idx.begin(), idx.end());
  EXPECT_EQ(idx, (std::vector<int>{0, 1}));
}

TEST(DenseQpSolverTest, InvalidInputNamesTheField) {
  DenseQpSolver solver(4, 1, 2);
  solver.H.setIdentity();
  solver.g[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(solver.Solve(), QpStatus::kInvalidInput);
  EXPECT_NE(solver.status_message().find("g[3]"), std::string::npos) << solver.status_message();
  EXPECT_NE(solver.status_message().find("nan"), std::string::npos) << solver.status_message();
  solver.g[3] = 0.0;
  solver.A(1, 2) = kInf;
  EXPECT_EQ(solver.Solve(), QpStatus::kInvalidInput);
  EXPECT_NE(solver.status_message().find("A(1, 2)"), std::string::npos) << solver.status_message();
  solver.A(1, 2) = 0.0;
  solver.l[0] = kInf;
  EXPECT_EQ(solver.Solve(), QpStatus::kInvalidInput);
  EXPECT_NE(solver.status_message().find("l[0]"), std::string::npos) << solver.status_message();
  solver.l[0] = 0.0;
  solver.b_eq.resize(3);
  EXPECT_EQ(solver.Solve(), QpStatus::kInvalidInput);
  EXPECT_NE(solver.status_message().find("b_eq has size 3x1, expected 1x1"), std::string::npos)
      << solver.status_message();
  solver.b_eq.setZero(1);
  solver.H(0, 1) = 0.5;
  EXPECT_EQ(solver.Solve(), QpStatus::kInvalidInput);
  EXPECT_NE(solver.status_message().find("not symmetric"), std::string::npos) << solver.status_message();
  solver.H(0, 1) = 0.0;
  EXPECT_EQ(solver.Solve(), QpStatus::kOptimal) << solver.status_message();
  EXPECT_THROW(DenseQpSolver(-1, 0, 0), std::invalid_argument);
}

TEST(DenseQpSolverTest, IterationLimitIsReported) {
  qp_test::ClfQpFamily family(1);
  const QpProblem p = family.Sample(0.0);
  DenseQpSolver solver(p.n(), p.n_eq(), p.n_ineq());
  LoadInto(p, &solver);
  solver.settings().max_iterations = 1;
  EXPECT_EQ(solver.Solve(), QpStatus::kMaxIterations);
  EXPECT_NE(solver.status_message().find("max_iterations = 1"), std::string::npos) << solver.status_message();
  solver.settings().max_iterations = 1000;
  EXPECT_EQ(solver.Solve(), QpStatus::kOptimal);
}

TEST(DenseQpSolverTest, ToStringNamesEveryStatus) {
  EXPECT_EQ(to_string(QpStatus::kOptimal), "optimal");
  EXPECT_EQ(to_string(QpStatus::kInfeasible), "infeasible");
  EXPECT_EQ(to_string(QpStatus::kNonConvex), "non-convex");
  EXPECT_EQ(to_string(QpStatus::kUnbounded), "unbounded");
  EXPECT_EQ(to_string(QpStatus::kMaxIterations), "max-iterations");
  EXPECT_EQ(to_string(QpStatus::kInvalidInput), "invalid-input");
}

}  // namespace
}  // namespace rome
