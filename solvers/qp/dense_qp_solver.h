#pragma once
// Dense convex QP solver for ROME's controllers (CLF-QP, task-space QP, H-LIP / MPC transitions).
//
// Problem (all data dense, sizes n variables, n_eq equality rows, n_ineq two-sided inequality rows):
//
//   minimize    1/2 x^T H x + g^T x
//   subject to  A_eq x  = b_eq                    (n_eq rows)
//               l    <= A x <= u                  (n_ineq rows, either side may be +-infinity)
//               lb   <= x   <= ub                 (n bounds,    either side may be +-infinity)
//
// Method: Goldfarb-Idnani dual active-set method (Goldfarb & Idnani, Math. Programming 27, 1983).
//   H = L L^T (Cholesky). The active constraint normals N (n x q) are kept through the factorization
//   L^{-1} N = Q [R; 0], stored as J = L^{-T} Q (n x n) and the upper triangular R (q x q); a constraint is
//   added with one Householder reflection and removed with Givens rotations (O(n^2) each). The method starts from a
//   dual feasible point (the unconstrained minimum, or the previous active set when warm-starting), adds the most
//   violated constraint at each iteration and keeps all multipliers dual feasible, so the first primal feasible iterate
//   is optimal. The active set of the last optimal solve is reused by the next Solve() (warm start).
//
// Warm start (1 kHz control loops, where the active set rarely changes between ticks):
//   1. Range-space check: the equality-constrained QP on the previous active set W is solved directly,
//      (M^T M) u = b_W + M^T L^{-1} g with M = L^{-1} N_W, x = L^{-T} (M u - L^{-1} g). If u >= 0 on every
//      inequality side, no other constraint is violated and every active row holds to
//      0.01 * feasibility_tolerance / max(1, |u|) (the normal equations lose accuracy as cond(M)^2), this is
//      the optimum (KKT conditions hold) and Solve() returns with iterations() == 0.
//   2. Otherwise the GI factorization is rebuilt with W installed, constraints with negative multipliers are
//      dropped until the start is dual feasible, and the GI iterations continue from there.
// Caches (exact, invalidated by any change of the data they depend on, compared bit for bit):
//   - the Cholesky factor and L^{-T} are reused while H is unchanged;
//   - J and R after adding the equalities are reused while H and A_eq are unchanged (e.g. MPC with fixed
//     dynamics, where only b_eq = initial state changes); then step 2 replaces step 1.
//
// Hot start (MPC and other parametric sequences: H, A_eq and A fixed, g, b_eq, l, u, lb, ub move):
//   The GI factorization J, R of the final working set of the last solve is kept across solves, together with
//   the working set itself. The next Solve() on the same matrices starts from it:
//   1. x and the multipliers u are recomputed on the kept working set for the new g and right-hand sides
//      (x = J1 R^{-T} b_W - J2 J2^T g, u = R^{-1} (R^{-T} b_W + J1^T g): two triangular solves and two
//      matrix-vector products, O(n^2)). If every inequality multiplier is >= 0 and no constraint is violated,
//      this is the optimum: the working set is unchanged, the step is feasible and Solve() returns after this
//      single O(n^2 + n m) pass (iterations() == 0), with no re-factorization and no further verification.
//   2. Otherwise working-set sides whose bound became infinite, then those with negative multipliers (the most
//      negative first, x and u recomputed after each) are dropped with Givens rotations, which restores dual
//      feasibility, and the ordinary GI iterations continue: each constraint that enters costs one Householder
//      reflection, each that leaves a sequence of Givens rotations (rank-one changes of the factorization,
//      O(n^2) each), never a re-factorization.
//   This is the dual counterpart of qpOASES's online active-set strategy: instead of following the homotopy
//   from the old to the new parameter with primal feasibility kept along the way, it keeps dual feasibility
//   and the factorization and lets the dual method repair primal feasibility from the old working set; in a
//   control loop the working set changes by a few constraints per tick, so a hot solve costs a few O(n^2)
//   updates. The factorization is kept after a solve whose H equals the previous one (so problems whose H
//   changes every tick pay nothing); it is rebuilt by the warm-start path above after 400 rank-one updates
//   (round-off of the orthogonal updates), when the matrices changed, and when the hot solve does not end
//   optimal (infeasible, iteration limit: the full path then decides and reports).
//   "The matrices are unchanged" is known in one of two ways (Solve(QpDataChange)):
//   - kUnknown (default): H, A_eq and A are compared bit for bit with the solver's copies (memcmp, O(n^2));
//   - kVectorsOnly: the caller declares them unchanged. Nothing is compared and the matrices are not
//     re-validated; instead the hot answer is verified on the data as stored now (stationarity
//     H x + g + A_eq^T y_eq + A^T y_ineq + y_bounds = 0 to 1e-11 relative to max(1, |g|, |H x|), every row and
//     bound feasible, every working-set side held, multipliers of the right sign; O(n^2 + n m)). If the
//     caller changed a matrix anyway, the check fails and Solve() falls back to the full path, which validates
//     the matrices, detects the change and re-factorizes: the answer is correct either way.
//   hot_started() tells whether the last Solve() was answered this way. QpSettings::hot_start = false or
//   warm_start = false disables it; ResetWarmStart() makes the next solve cold.
//
// Multiplier sign convention (same as OSQP), so that users can check the KKT conditions:
//   H x + g + A_eq^T y_eq + A^T y_ineq + y_bounds = 0,
//   y_ineq[i] > 0 only if row i is at its upper side u[i], y_ineq[i] < 0 only if it is at its lower side l[i];
//   y_bounds[j] > 0 only if x[j] = ub[j], y_bounds[j] < 0 only if x[j] = lb[j].
//
// Constraint indices (infeasible_constraints(), status_message()) use one flat numbering:
//   [0, n_eq)                          equality row i            -> i
//   [n_eq, n_eq + n_ineq)              inequality row i          -> n_eq + i
//   [n_eq + n_ineq, n_eq + n_ineq + n) bound on variable x[j]    -> n_eq + n_ineq + j
//
// Positive semidefinite H: if the Cholesky factorization of H fails (a pivot <= 1e-8 * max_j H_jj, i.e. H is
// singular or has a condition number above ~1e8, too large for KKT residuals of 1e-9), H + rho I
// (rho = QpSettings::regularization) is factorized instead. If that also fails, H has a negative eigenvalue
// below -rho and Solve() returns kNonConvex. Otherwise the bias of rho is removed by proximal-point iterations
//   x_{k+1} = argmin 1/2 x^T (H + rho I) x + (g - rho x_k)^T x  s.t. constraints,
// each warm-started from the previous active set and refined by one step of iterative refinement (cond(H + rho I)
// ~ 1/rho amplifies round-off), until rho * ||x_{k+1} - x_k||_inf <= proximal_tolerance
// (this quantity is exactly the stationarity residual of the original problem). If the iterates move along a
// fixed ray (objective unbounded below on the feasible set) Solve() returns kUnbounded.
//
// Memory: Resize() (or the constructor) allocates everything; Solve() performs no heap allocation.
// Cost: O(n^3) for a new H, O(n^2) per GI iteration; see tests/benchmarks/qp/qp_benchmark.cpp for latencies.
// On x86-64 with GCC the hot loops are compiled for AVX2/FMA and baseline x86-64 and chosen at load time.
//
// Files (one idea each): dense_qp_solver.cc, the method (factorizations, GI iterations, warm and hot start);
// dense_qp_kernels.h, the linear-algebra kernels and the CPU dispatch; dense_qp_diagnostics.cc, input
// validation, status text and KKT residuals.

#include <Eigen/Dense>

#include <string>
#include <string_view>
#include <vector>

namespace rome {

// Every tolerance and limit of the QP solver. Units are those of the problem data.
struct QpSettings {
  // Maximum number of Goldfarb-Idnani iterations (constraint additions + removals chosen by the pricing loop)
  // per Solve(), including all proximal iterations. Exceeding it returns kMaxIterations.
  int max_iterations = 1000;
  // A constraint row is violated when it is off by more than this absolute amount, in the row's own units
  // (e.g. l[i] - a_i^T x > feasibility_tolerance). The returned solution violates no row by more than this.
  double feasibility_tolerance = 1e-9;
  // A new constraint normal n is linearly dependent on the active ones when the part of L^{-1} n outside
  // the span of the active set has norm <= linear_dependence_tolerance * ||L^{-1} n|| (dimensionless).
  // Dependent equalities that are consistent are skipped; inconsistent ones make the problem infeasible.
  double linear_dependence_tolerance = 1e-10;
  // rho, added to the diagonal of H (units of H) only when H is not numerically positive definite.
  double regularization = 1e-6;
  // Stop the proximal iterations for PSD H when rho * ||x_{k+1} - x_k||_inf <= proximal_tolerance
  // (units of g; this is the stationarity residual with respect to the original H).
  double proximal_tolerance = 1e-11;
  // Maximum proximal iterations for PSD H; exceeding it returns kMaxIterations.
  int max_proximal_iterations = 200;
  // Bounds with |value| >= infinity are treated as absent (std::numeric_limits<double>::infinity() also works).
  double infinity = 1e20;
  // Start Solve() from the active set of the previous optimal solve when the sizes did not change.
  bool warm_start = true;
  // Keep the factorization of the working set across solves with unchanged H, A_eq and A and start from it
  // (hot start, see the header comment). Requires warm_start.
  bool hot_start = true;
};

// What the caller changed in the problem data since the last Solve().
enum class QpDataChange {
  kUnknown,      // anything: the matrices are compared with the solver's copies (bit for bit)
  kVectorsOnly,  // declared: H, A_eq and A are unchanged, only g, b_eq, l, u, lb, ub moved (verified, see above)
};

enum class QpStatus {
  kOptimal,        // KKT conditions hold within the tolerances.
  kInfeasible,     // No x satisfies the constraints; infeasible_constraints() lists an infeasible subset.
  kNonConvex,      // H has an eigenvalue below -regularization.
  kUnbounded,      // H is PSD and the objective decreases without bound on the feasible set.
  kMaxIterations,  // Iteration limit reached; x() is the last (dual feasible, primal infeasible) iterate.
  kInvalidInput,   // NaN / inf / size mismatch in the problem data; status_message() names the field.
};

std::string_view to_string(QpStatus status);

class DenseQpSolver {
 public:
  // Allocates the problem data (H = 0, g = 0, A_eq = 0, b_eq = 0, A = 0, l = lb = -inf, u = ub = +inf)
  // and the whole workspace. Throws std::invalid_argument for negative sizes.
  DenseQpSolver(int n, int n_eq, int n_ineq, QpSettings settings = {});

  // Reallocates the data (reset as in the constructor) and the workspace; clears the warm start.
  void Resize(int n, int n_eq, int n_ineq);

  // Problem data: public and preallocated; overwrite in place each control tick (do not resize them).
  Eigen::MatrixXd H;       // n x n, symmetric, positive (semi)definite
  Eigen::VectorXd g;       // n
  Eigen::MatrixXd A_eq;    // n_eq x n
  Eigen::VectorXd b_eq;    // n_eq
  Eigen::MatrixXd A;       // n_ineq x n
  Eigen::VectorXd l, u;    // n_ineq each, l <= A x <= u
  Eigen::VectorXd lb, ub;  // n each, lb <= x <= ub

  // Solves the problem currently stored in the data members. Never allocates, never throws.
  // `change` may declare that only the vectors changed (hot start without comparing the matrices; safe, see the
  // header comment).
  QpStatus Solve(QpDataChange change = QpDataChange::kUnknown);
  // The next Solve() starts from the unconstrained minimum (cold start).
  void ResetWarmStart();

  QpSettings& settings() { return settings_; }
  const QpSettings& settings() const { return settings_; }
  int num_variables() const { return n_; }
  int num_equalities() const { return n_eq_; }
  int num_inequalities() const { return n_ineq_; }

  QpStatus status() const { return status_; }
  const Eigen::VectorXd& x() const { return x_; }
  const Eigen::VectorXd& y_eq() const { return y_eq_; }
  const Eigen::VectorXd& y_ineq() const { return y_ineq_; }
  const Eigen::VectorXd& y_bounds() const { return y_bounds_; }
  // Goldfarb-Idnani iterations of the last Solve() (pricing-loop additions + removals; the installation of a
  // warm-start active set and of the equalities is not counted).
  int iterations() const { return iterations_; }
  // True if the last Solve() was answered by the hot start (kept factorization of the previous working set).
  bool hot_started() const { return hot_started_; }
  // Number of constraints (equalities, active inequality sides, active bounds) in the final active set.
  int active_set_size() const { return q_; }
  double objective() const { return objective_; }
  // Flat indices (see the header comment) of an infeasible subset of constraints when status() is kInfeasible.
  const std::vector<int>& infeasible_constraints() const { return infeasible_flat_; }
  // Human-readable explanation of status(), naming the offending data field / constraints and values.
  std::string status_message() const;

 private:
  enum class InputError { kNone, kSize, kNotFinite, kNotSymmetric, kWrongInfinity, kContradictoryBounds };

  // Constraint ids used internally: each inequality row and each bound has a lower and an upper side, written
  // as n^T x >= b (upper side: -a^T x >= -u). id layout: [eq rows][ineq row i: 2i lower, 2i+1 upper][bounds].
  int EqId(int i) const { return i; }
  int IneqId(int i, int side) const { return n_eq_ + 2 * i + side; }
  int BoundId(int j, int side) const { return n_eq_ + 2 * n_ineq_ + 2 * j + side; }
  int FlatIndex(int id) const;
  double Rhs(int id) const;
  double NormalDot(int id, const Eigen::VectorXd& v) const;
  bool SideIsFinite(int id) const;

  bool ValidateInput(bool matrices);  // sizes, finiteness, bounds; finiteness / symmetry of H, A_eq, A if matrices
  bool MatricesMatchHotCache() const;
  // Solve's stages (dense_qp_solve.cc).
  bool FindContradictoryBounds();  // records the first row or bound with lower > upper; true if there is one
  bool FactorizeH();               // H, else H + regularization I, factorized and cached; false if neither is PD
  void ComputeInverseRowNorms();
  QpStatus SolveGoldfarbIdnani(bool warm, bool keep_factorization);
  QpStatus SolveProximal(bool warm);
  QpStatus HotSolve(bool verify);
  bool VerifyHotSolution();
  QpStatus Iterate(const Eigen::VectorXd& g_eff, bool x_current);  // GI pricing loop from a dual feasible start
  bool Factorize(double shift);  // L_ = chol(H + shift I); false if not numerically PD
  void ComputeJ0();              // J0_ = L^{-T}
  QpStatus SolveFromFactor(const Eigen::VectorXd& g_eff, bool use_warm_start);
  bool TryWarmActiveSet();  // optimal solution on the previous active set, if it is still optimal
  void ComputeD(int id);    // d_ = J^T n_id
  bool DIsDependent() const;
  void AddConstraint(int id, double multiplier);
  void DropConstraint(int position);
  void ComputeActiveSetSolution(const Eigen::VectorXd& g_eff);  // x_, u_active_ from J, R
  // Drops the working set's inequality sides with negative multipliers, the most negative first, re-solving after each,
  // until none is left (the dual method must start dual feasible); returns how many it dropped.
  int DropNegativeMultipliers(const Eigen::VectorXd& g_eff);
  void RefineActiveSetSolution(const Eigen::VectorXd& g_eff, double shift);
  void ComputeNormal(int id, double* out) const;
  int FindMostViolated(double* slack);
  void SolveR(int q);  // r_ = R^{-1} d_.head(q)
  void RecordInfeasible(int id, int num_certificate);
  void SaveWarmStart();
  void FillOutputs();

  int n_ = 0, n_eq_ = 0, n_ineq_ = 0, n_ids_ = 0;
  QpSettings settings_;

  // Workspace.
  Eigen::MatrixXd L_, J0_, J_, R_, H_cached_, M_, G_, T_;
  bool factor_cached_ = false;
  // State of the GI factorization after adding the equalities (valid for H_cached_ and A_eq_cached_).
  Eigen::MatrixXd J_eq_, R_eq_, A_eq_cached_;
  std::vector<int> active_eq_cached_, dependent_eq_cached_;
  int q_eq_cached_ = 0, num_dependent_cached_ = 0;
  bool eq_cache_valid_ = false, use_eq_cache_ = false, store_eq_cache_ = false;
  bool j0_valid_ = false;
  bool factor_regularized_ = false;
  Eigen::VectorXd inv_diag_, t_col_, g_eff_refine_, b_refine_, d_, row_, z_, r_, v_, w_, Ax_, inv_row_norm_, g_eff_,
      x_prev_, dx_prev_, u_active_;
  std::vector<int> active_;               // constraint id at each active position
  std::vector<unsigned char> is_active_;  // per constraint id
  std::vector<int> dependent_eq_;
  int q_ = 0, q_eq_ = 0;
  std::vector<int> warm_active_;
  int warm_count_ = 0;
  bool warm_valid_ = false;
  // Hot start: J_, R_, active_, q_, q_eq_ and is_active_ are the factorization of the working set of the last
  // optimal solve, for the matrices H_cached_, A_eq_hot_, A_hot_.
  Eigen::MatrixXd A_eq_hot_, A_hot_;
  bool hot_valid_ = false, hot_started_ = false;
  int hot_updates_ = 0;    // rank-one updates of the kept factorization since it was built
  int num_dependent_ = 0;  // dependent equalities skipped by the last SolveFromFactor()

  // Results.
  QpStatus status_ = QpStatus::kInvalidInput;
  Eigen::VectorXd x_, y_eq_, y_ineq_, y_bounds_;
  int iterations_ = 0;
  double objective_ = 0.0;
  std::vector<int> infeasible_flat_, infeasible_ids_;
  int proximal_iterations_ = 0;

  // Details for status_message().
  InputError input_error_ = InputError::kNone;
  const char* bad_field_ = "";
  int bad_row_ = 0, bad_col_ = 0, bad_rows_expected_ = 0, bad_cols_expected_ = 0;
  double bad_value_ = 0.0, bad_value2_ = 0.0;
};

// KKT residuals of a QP solution (infinity norms, absolute, in the units of the respective rows).
struct QpKktResiduals {
  double stationarity = 0.0;        // ||H x + g + A_eq^T y_eq + A^T y_ineq + y_bounds||_inf
  double primal_feasibility = 0.0;  // max violation of equalities, inequality rows and bounds
  double dual_feasibility = 0.0;    // max multiplier of the wrong sign (or on an infinite side)
  double complementarity = 0.0;     // max |y_i| * distance of row i to the side its multiplier's sign selects
  double Max() const;
};

// Residuals of (x, y_eq, y_ineq, y_bounds) for the problem stored in `qp` (sign convention of DenseQpSolver).
QpKktResiduals ComputeQpKktResiduals(const DenseQpSolver& qp, const Eigen::VectorXd& x, const Eigen::VectorXd& y_eq,
                                     const Eigen::VectorXd& y_ineq, const Eigen::VectorXd& y_bounds);
// Residuals of the solver's own solution.
QpKktResiduals ComputeQpKktResiduals(const DenseQpSolver& qp);

}  // namespace rome
