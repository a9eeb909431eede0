// DenseQpSolver's construction and sizes, and the Solve driver: input checks, reuse of the factorization, and the
// choice among hot start, the warm active set, Goldfarb-Idnani and proximal iterations (dense_qp_solver.h describes
// the method; the iterations are in dense_qp_solver.cc).

#include "solvers/qp/dense_qp_solver.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "solvers/qp/dense_qp_kernels.h"

namespace rome {

using namespace qp_kernels;  // NOLINT: the kernels are the solver's vocabulary

DenseQpSolver::DenseQpSolver(int n, int n_eq, int n_ineq, QpSettings settings) : settings_(settings) {
  Resize(n, n_eq, n_ineq);
}

void DenseQpSolver::Resize(int n, int n_eq, int n_ineq) {
  if (n < 0 || n_eq < 0 || n_ineq < 0) {
    throw std::invalid_argument("DenseQpSolver::Resize: sizes must be non-negative, got n=" + std::to_string(n) +
                                ", n_eq=" + std::to_string(n_eq) + ", n_ineq=" + std::to_string(n_ineq));
  }
  n_ = n;
  n_eq_ = n_eq;
  n_ineq_ = n_ineq;
  n_ids_ = n_eq + 2 * n_ineq + 2 * n;

  H = Eigen::MatrixXd::Zero(n, n);
  g = Eigen::VectorXd::Zero(n);
  A_eq = Eigen::MatrixXd::Zero(n_eq, n);
  b_eq = Eigen::VectorXd::Zero(n_eq);
  A = Eigen::MatrixXd::Zero(n_ineq, n);
  l = Eigen::VectorXd::Constant(n_ineq, -kInf);
  u = Eigen::VectorXd::Constant(n_ineq, kInf);
  lb = Eigen::VectorXd::Constant(n, -kInf);
  ub = Eigen::VectorXd::Constant(n, kInf);

  L_.setZero(n, n);
  inv_diag_.setZero(n);
  J0_.setZero(n, n);
  J_.setZero(n, n);
  R_.setZero(n, n);
  J_eq_.setZero(n, n);
  R_eq_.setZero(n, n);
  A_eq_cached_.setZero(n_eq, n);
  active_eq_cached_.assign(n_eq, 0);
  dependent_eq_cached_.assign(n_eq, 0);
  q_eq_cached_ = 0;
  num_dependent_cached_ = 0;
  eq_cache_valid_ = false;
  use_eq_cache_ = false;
  store_eq_cache_ = false;
  M_.setZero(n, n + 1);
  T_.setZero(n + 2, n);
  t_col_.setZero(n + 2);
  G_.setZero(n, n);
  j0_valid_ = false;
  H_cached_.setZero(n, n);
  factor_cached_ = false;
  factor_regularized_ = false;
  d_.setZero(n);
  row_.setZero(n);
  z_.setZero(n);
  r_.setZero(n);
  v_.setZero(n);
  w_.setZero(n);
  Ax_.setZero(n_ineq);
  inv_row_norm_.setZero(n_ineq);
  g_eff_.setZero(n);
  g_eff_refine_.setZero(n);
  b_refine_.setZero(n + 1);
  x_prev_.setZero(n);
  dx_prev_.setZero(n);
  u_active_.setZero(n + 1);
  active_.assign(n + 1, -1);
  is_active_.assign(n_ids_, 0);
  dependent_eq_.assign(n_eq, -1);
  warm_active_.assign(n + 1, -1);
  warm_count_ = 0;
  warm_valid_ = false;
  A_eq_hot_.setZero(n_eq, n);
  A_hot_.setZero(n_ineq, n);
  hot_valid_ = false;
  hot_started_ = false;
  hot_updates_ = 0;
  q_ = 0;
  q_eq_ = 0;

  status_ = QpStatus::kInvalidInput;
  input_error_ = InputError::kNone;
  x_.setZero(n);
  y_eq_.setZero(n_eq);
  y_ineq_.setZero(n_ineq);
  y_bounds_.setZero(n);
  iterations_ = 0;
  objective_ = 0.0;
  infeasible_flat_.clear();
  infeasible_ids_.clear();
  infeasible_flat_.reserve(n + 2);
  infeasible_ids_.reserve(n + 2);
}

void DenseQpSolver::ResetWarmStart() {
  warm_valid_ = false;
  warm_count_ = 0;
  hot_valid_ = false;
}

QpStatus DenseQpSolver::Solve(QpDataChange change) {
  iterations_ = 0;
  proximal_iterations_ = 0;
  infeasible_flat_.clear();
  infeasible_ids_.clear();
  input_error_ = InputError::kNone;
  objective_ = std::numeric_limits<double>::quiet_NaN();
  hot_started_ = false;
  // Hot start when the matrices are those of the kept factorization: declared by the caller (then verified),
  // or compared bit for bit. Then only the vectors need validating (the cached matrices were validated).
  const bool declared = change == QpDataChange::kVectorsOnly;
  bool hot = hot_valid_ && settings_.hot_start && settings_.warm_start;
  if (hot && !declared) hot = MatricesMatchHotCache();
  if (!ValidateInput(/*matrices=*/!hot)) {
    if (!hot) factor_cached_ = false;
    return status_ = QpStatus::kInvalidInput;
  }
  if (FindContradictoryBounds()) return status_ = QpStatus::kInfeasible;  // no iterations needed
  if (hot) {
    const QpStatus status = HotSolve(/*verify=*/declared);
    if (status == QpStatus::kOptimal) {
      hot_started_ = true;
      SaveWarmStart();
      return status_ = status;
    }
    // Not answered hot (refresh due, infeasible, iteration limit, or a declaration that did not hold): the
    // full path below validates, compares, re-factorizes if needed and reports.
    iterations_ = 0;
    infeasible_flat_.clear();
    infeasible_ids_.clear();
    if (declared && !ValidateInput(/*matrices=*/true)) {
      hot_valid_ = false;
      factor_cached_ = false;
      return status_ = QpStatus::kInvalidInput;
    }
  }
  hot_valid_ = false;  // J_ and R_ are rebuilt below

  // Factorization of H, reused when H did not change since the last solve.
  const bool factor_reused = factor_cached_ && H == H_cached_;
  if (!factor_reused && !FactorizeH()) return status_ = QpStatus::kNonConvex;
  ComputeInverseRowNorms();

  // Equality part of the factorization: reused when H and A_eq are unchanged; stored only when H was
  // unchanged (a constant-H problem such as MPC), so problems with a new H every tick pay no copy.
  use_eq_cache_ = factor_reused && eq_cache_valid_ && A_eq == A_eq_cached_;
  store_eq_cache_ = !use_eq_cache_ && (factor_reused || factor_regularized_);

  const bool warm = settings_.warm_start && warm_valid_;
  QpStatus status;
  // With the equality part cached, re-adding the warm inequalities in the GI factorization is cheaper than the
  // range-space solve (which is O(n^2 (n_eq + n_active))).
  // With a repeated H and hot starts enabled, the GI path is taken so that its factorization can be kept.
  const bool keep_factorization = settings_.hot_start && settings_.warm_start && factor_reused;
  if (!factor_regularized_ && warm && !use_eq_cache_ && !keep_factorization && TryWarmActiveSet()) {
    status = QpStatus::kOptimal;
  } else if (!factor_regularized_) {
    status = SolveGoldfarbIdnani(warm, keep_factorization);
  } else {
    status = SolveProximal(warm);
  }
  if (status != QpStatus::kOptimal) warm_valid_ = false;
  if (status != QpStatus::kInfeasible) FillOutputs();
  return status_ = status;
}

bool DenseQpSolver::FindContradictoryBounds() {
  const double tol = settings_.feasibility_tolerance;
  for (int i = 0; i < n_ineq_; ++i) {
    if (l[i] - u[i] > tol) {
      input_error_ = InputError::kContradictoryBounds;
      infeasible_ids_.push_back(IneqId(i, 0));
      infeasible_flat_.push_back(n_eq_ + i);
      bad_value_ = l[i];
      bad_value2_ = u[i];
      return true;
    }
  }
  for (int j = 0; j < n_; ++j) {
    if (lb[j] - ub[j] > tol) {
      input_error_ = InputError::kContradictoryBounds;
      infeasible_ids_.push_back(BoundId(j, 0));
      infeasible_flat_.push_back(n_eq_ + n_ineq_ + j);
      bad_value_ = lb[j];
      bad_value2_ = ub[j];
      return true;
    }
  }
  return false;
}

bool DenseQpSolver::FactorizeH() {
  factor_cached_ = false;
  eq_cache_valid_ = false;
  if (Factorize(0.0)) {
    factor_regularized_ = false;
  } else if (Factorize(settings_.regularization)) {
    factor_regularized_ = true;
  } else {
    return false;
  }
  H_cached_ = H;
  factor_cached_ = true;
  j0_valid_ = false;
  return true;
}

void DenseQpSolver::ComputeInverseRowNorms() {
  if (n_ineq_ == 0) return;
  double* __restrict rn = inv_row_norm_.data();
  for (int i = 0; i < n_ineq_; ++i) rn[i] = 0.0;
  for (int j = 0; j < n_; ++j) {
    const double* __restrict aj = A.col(j).data();
    for (int i = 0; i < n_ineq_; ++i) rn[i] += aj[i] * aj[i];
  }
  for (int i = 0; i < n_ineq_; ++i) {
    inv_row_norm_[i] = inv_row_norm_[i] > 0.0 ? 1.0 / std::sqrt(inv_row_norm_[i]) : 0.0;
  }
}

QpStatus DenseQpSolver::SolveGoldfarbIdnani(bool warm, bool keep_factorization) {
  if (!j0_valid_) ComputeJ0();
  j0_valid_ = true;
  const QpStatus status = SolveFromFactor(g, warm);
  if (status == QpStatus::kOptimal) {
    SaveWarmStart();
    // Keep the factorization for hot starts. Only when H repeated (a parametric sequence), so that problems
    // whose H changes every tick (CLF-QP, task-space QP) pay no copies.
    if (keep_factorization && num_dependent_ == 0) {
      A_eq_hot_ = A_eq;
      A_hot_ = A;
      hot_valid_ = true;
      hot_updates_ = 0;
    }
  }
  return status;
}

QpStatus DenseQpSolver::SolveProximal(bool warm) {
  if (!j0_valid_) ComputeJ0();
  j0_valid_ = true;
  // Proximal-point iterations on H + rho I (see header).
  const double rho = settings_.regularization;
  if (!warm) x_.setZero();
  x_prev_ = x_;
  QpStatus status = QpStatus::kMaxIterations;
  bool use_warm = warm;
  double previous_step = kInf;
  int previous_q = -1;
  for (int k = 0; k < settings_.max_proximal_iterations; ++k) {
    ++proximal_iterations_;
    g_eff_ = g;
    g_eff_.noalias() -= rho * x_prev_;
    const QpStatus inner = SolveFromFactor(g_eff_, use_warm);
    if (inner != QpStatus::kOptimal) {
      status = inner;
      break;
    }
    // cond(H + rho I) ~ 1/rho amplifies round-off: refine the inner KKT solution once.
    RefineActiveSetSolution(g_eff_, rho);
    SaveWarmStart();
    use_warm = true;
    // Stationarity residual of the original problem: H x + g + N^T y = rho (x_prev - x).
    z_ = x_ - x_prev_;
    const double step = z_.lpNorm<Eigen::Infinity>();
    if (rho * step <= settings_.proximal_tolerance) {
      status = QpStatus::kOptimal;
      break;
    }
    // Iterates moving along a fixed ray at constant speed: unbounded objective.
    if (k > 2 && q_ == previous_q && (z_ - dx_prev_).lpNorm<Eigen::Infinity>() <= 1e-9 * step &&
        step >= 0.999 * previous_step) {
      status = QpStatus::kUnbounded;
      break;
    }
    previous_step = step;
    previous_q = q_;
    dx_prev_ = z_;
    x_prev_ = x_;
  }
  return status;
}

bool DenseQpSolver::MatricesMatchHotCache() const {
  // Bit-for-bit comparison with the matrices of the kept factorization (memcmp: no NaN can match, the copies
  // were validated).
  auto same = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
    return a.size() == 0 || std::memcmp(a.data(), b.data(), static_cast<size_t>(a.size()) * sizeof(double)) == 0;
  };
  return same(H, H_cached_) && same(A_eq, A_eq_hot_) && same(A, A_hot_);
}

void DenseQpSolver::SaveWarmStart() {
  warm_count_ = 0;
  for (int j = q_eq_; j < q_; ++j) warm_active_[warm_count_++] = active_[j];
  warm_valid_ = true;
}

}  // namespace rome
