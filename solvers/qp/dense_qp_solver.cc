#include "solvers/qp/dense_qp_solver.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "solvers/qp/dense_qp_kernels.h"

// The method (Goldfarb-Idnani dual active set, warm and hot start) is described in dense_qp_solver.h. This file:
// constraint helpers, the factorization, active-set updates, the Goldfarb-Idnani iterations, warm and hot start.
// Construction and the Solve driver are in dense_qp_solve.cc; input validation, status text and KKT residuals in
// dense_qp_diagnostics.cc; the linear-algebra kernels and the CPU dispatch of the ROME_QP_HOT functions in
// dense_qp_kernels.h.

namespace rome {
namespace {

using namespace qp_kernels;  // NOLINT: the kernels are this file's vocabulary

// Relative Cholesky pivot threshold below which H is treated as singular (see header): beyond a condition
// number of ~1e8 the direct solve could not deliver KKT residuals of 1e-9, the proximal iterations can.
constexpr double kPivotTolerance = 1e-8;
// Coefficients of the dependence certificate below this fraction of the largest one are treated as zero.
constexpr double kCertificateTolerance = 1e-9;

// Rank-one updates (constraint additions and removals) after which a kept factorization is rebuilt.
constexpr int kHotRefreshUpdates = 400;
// Stationarity residual accepted by the hot-start verification, relative to max(1, |g|, |H x|).
constexpr double kHotStationarityTolerance = 1e-11;

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Constraint helpers.

int DenseQpSolver::FlatIndex(int id) const {
  if (id < n_eq_) return id;
  if (id < n_eq_ + 2 * n_ineq_) return n_eq_ + (id - n_eq_) / 2;
  return n_eq_ + n_ineq_ + (id - n_eq_ - 2 * n_ineq_) / 2;
}

// Rhs, NormalDot and SideIsFinite are always inlined: called from the AVX2 clones of the hot loops, an
// out-of-line baseline (SSE) body runs with the upper YMM state dirty (see dense_qp_kernels.h).
[[gnu::always_inline]] inline double DenseQpSolver::Rhs(int id) const {
  if (id < n_eq_) return b_eq[id];
  if (id < n_eq_ + 2 * n_ineq_) {
    const int k = id - n_eq_;
    return (k & 1) ? -u[k >> 1] : l[k >> 1];
  }
  const int k = id - n_eq_ - 2 * n_ineq_;
  return (k & 1) ? -ub[k >> 1] : lb[k >> 1];
}

[[gnu::always_inline]] inline double DenseQpSolver::NormalDot(int id, const Eigen::VectorXd& v) const {
  if (id < n_eq_) return A_eq.row(id).dot(v);
  if (id < n_eq_ + 2 * n_ineq_) {
    const int k = id - n_eq_;
    const double a = A.row(k >> 1).dot(v);
    return (k & 1) ? -a : a;
  }
  const int k = id - n_eq_ - 2 * n_ineq_;
  return (k & 1) ? -v[k >> 1] : v[k >> 1];
}

[[gnu::always_inline]] inline bool DenseQpSolver::SideIsFinite(int id) const {
  if (id < n_eq_) return true;
  return std::abs(Rhs(id)) < settings_.infinity;
}

ROME_QP_HOT void DenseQpSolver::ComputeD(int id) {
  // d = J^T n_id (rows of A / A_eq are strided: copied to a contiguous buffer first).
  const int n = n_;
  double* d = d_.data();
  if (id < n_eq_ + 2 * n_ineq_) {
    double* row = row_.data();
    double sign = 1.0;
    if (id < n_eq_) {
      for (int i = 0; i < n; ++i) row[i] = A_eq(id, i);
    } else {
      const int k = id - n_eq_;
      for (int i = 0; i < n; ++i) row[i] = A(k >> 1, i);
      if (k & 1) sign = -1.0;
    }
    GemvTransposed(J_.data(), n, n, n, row, d);
    if (sign < 0.0) {
      for (int i = 0; i < n; ++i) d[i] = -d[i];
    }
  } else {
    const int k = id - n_eq_ - 2 * n_ineq_;
    const double sign = (k & 1) ? -1.0 : 1.0;
    const double* jrow = J_.data() + (k >> 1);
    for (int i = 0; i < n; ++i) d[i] = sign * jrow[static_cast<Eigen::Index>(i) * n];
  }
}

bool DenseQpSolver::DIsDependent() const {
  const double d2 = SquaredNorm(d_.data() + q_, n_ - q_);
  const double tol = settings_.linear_dependence_tolerance;
  return d2 <= tol * tol * (d2 + SquaredNorm(d_.data(), q_));
}

// ---------------------------------------------------------------------------------------------------------
// Factorization.

ROME_QP_HOT bool DenseQpSolver::Factorize(double shift) {
  // Left-looking Cholesky of H + shift I (lower triangle of H): column j is
  //   L(j:n, j) = (H(j:n, j) - L(j:n, 0:j) L(j, 0:j)^T) / L(j, j),
  // one unrolled gemv per column with the row L(j, 0:j) gathered into a contiguous buffer.
  const int n = n_;
  double max_diag = 0.0;
  for (int j = 0; j < n; ++j) max_diag = std::max(max_diag, std::abs(H(j, j)));
  const double pivot_min = kPivotTolerance * (max_diag + shift);
  double* lrow = row_.data();
  double* tmp = z_.data();
  for (int j = 0; j < n; ++j) {
    double* __restrict lj = L_.col(j).data();
    const double* __restrict hj = H.col(j).data();
    const int rows = n - j;
    if (j > 0) {
      for (int k = 0; k < j; ++k) lrow[k] = L_(j, k);
      Gemv(L_.data() + j, n, rows, j, lrow, tmp);
    } else {
      for (int i = 0; i < rows; ++i) tmp[i] = 0.0;
    }
    const double pivot = hj[j] + shift - tmp[0];
    if (!(pivot > pivot_min)) return false;
    const double ljj = std::sqrt(pivot);
    const double inv = 1.0 / ljj;
    lj[j] = ljj;
    inv_diag_[j] = inv;
    for (int i = 1; i < rows; ++i) lj[j + i] = (hj[j + i] - tmp[i]) * inv;
  }
  return true;
}

ROME_QP_HOT void DenseQpSolver::ComputeJ0() {
  // J0 = L^{-T} (upper triangular). Row j of L^{-1} is (e_j - L(j, 0:j) L^{-1}(0:j, :)) / L(j, j); transposed,
  // column j of J0 is (e_j - J0(0:j, 0:j) L(j, 0:j)^T) / L(j, j): one unrolled gemv per column.
  const int n = n_;
  J0_.setZero();
  double* lrow = row_.data();
  for (int j = 0; j < n; ++j) {
    double* __restrict cj = J0_.col(j).data();
    const double inv = inv_diag_[j];
    if (j > 0) {
      for (int k = 0; k < j; ++k) lrow[k] = L_(j, k);
      Gemv(J0_.data(), n, j, j, lrow, cj);
      for (int i = 0; i < j; ++i) cj[i] *= -inv;
    }
    cj[j] = inv;
  }
}

// ---------------------------------------------------------------------------------------------------------
// Active-set updates (Givens rotations keep J^T N = [R; 0]).

ROME_QP_HOT void DenseQpSolver::AddConstraint(int id, double multiplier) {
  // d_ holds J^T n_id. One Householder reflection P (symmetric, orthogonal) maps d[q..n) onto alpha e_q;
  // applying it to J's trailing columns (J2 <- J2 P) keeps J^T H J = I and makes J^T N = [R; 0] again.
  const int n = n_;
  const int q = q_;
  const int m = n - q;
  double* d2 = d_.data() + q;
  double tail = 0.0;
  for (int i = 1; i < m; ++i) tail += d2[i] * d2[i];
  if (tail > 0.0) {
    const double norm = std::sqrt(d2[0] * d2[0] + tail);
    const double alpha = d2[0] > 0.0 ? -norm : norm;
    d2[0] -= alpha;  // v = d2 - alpha e_0 (stored in place)
    const double beta = 2.0 / (d2[0] * d2[0] + tail);
    // w = J2 v, then J2 -= beta w v^T.
    double* __restrict w = z_.data();
    Gemv(J_.col(q).data(), n, n, m, d2, w);
    for (int k = 0; k < m; ++k) {
      const double s = beta * d2[k];
      double* __restrict jk = J_.col(q + k).data();
      for (int i = 0; i < n; ++i) jk[i] -= s * w[i];
    }
    d2[0] = alpha;
    for (int i = 1; i < m; ++i) d2[i] = 0.0;
  }
  double* rq = R_.col(q).data();
  for (int i = 0; i <= q; ++i) rq[i] = d_[i];
  active_[q] = id;
  u_active_[q] = multiplier;
  is_active_[id] = 1;
  ++q_;
}

ROME_QP_HOT void DenseQpSolver::DropConstraint(int position) {
  const int n = n_;
  const int q = q_;
  is_active_[active_[position]] = 0;
  for (int j = position; j < q - 1; ++j) {
    double* dst = R_.col(j).data();
    const double* src = R_.col(j + 1).data();
    for (int i = 0; i <= j + 1; ++i) dst[i] = src[i];
    active_[j] = active_[j + 1];
    u_active_[j] = u_active_[j + 1];
  }
  // Columns position..q-2 are now upper Hessenberg: zero R(j+1, j) with row rotations (= J column rotations).
  for (int j = position; j < q - 1; ++j) {
    const double b = R_(j + 1, j);
    if (b == 0.0) continue;
    const double a = R_(j, j);
    const double h = std::sqrt(a * a + b * b);
    const double inv_h = 1.0 / h;
    const double c = a * inv_h;
    const double s = b * inv_h;
    R_(j, j) = h;
    R_(j + 1, j) = 0.0;
    for (int col = j + 1; col < q - 1; ++col) {
      const double t1 = R_(j, col);
      const double t2 = R_(j + 1, col);
      R_(j, col) = c * t1 + s * t2;
      R_(j + 1, col) = c * t2 - s * t1;
    }
    RotateColumns(J_.col(j).data(), J_.col(j + 1).data(), n, c, s);
  }
  --q_;
}

ROME_QP_HOT void DenseQpSolver::SolveR(int q) {
  // r = R^{-1} d[0..q), column-oriented back substitution on the upper triangular R (contiguous axpys).
  double* r = r_.data();
  const double* d = d_.data();
  for (int i = 0; i < q; ++i) r[i] = d[i];
  for (int j = q - 1; j >= 0; --j) {
    const double* rj = R_.col(j).data();
    const double xj = r[j] / rj[j];
    r[j] = xj;
    for (int i = 0; i < j; ++i) r[i] -= xj * rj[i];
  }
}

ROME_QP_HOT void DenseQpSolver::ComputeActiveSetSolution(const Eigen::VectorXd& g_eff) {
  // With x = J w: w1 = R^{-T} b_A, w2 = -J2^T g, u = R^{-1} (w1 + J1^T g) (derivation in the header).
  const int n = n_;
  const int q = q_;
  for (int i = 0; i < q; ++i) {
    double s = Rhs(active_[i]);
    const double* ri = R_.col(i).data();
    for (int j = 0; j < i; ++j) s -= ri[j] * w_[j];
    w_[i] = s / ri[i];
  }
  GemvTransposed(J_.data(), n, n, n, g_eff.data(), v_.data());
  // x = J1 w1 - J2 v2: flip the sign of v2 in place and use one product with [w1; -v2].
  for (int i = 0; i < q; ++i) z_[i] = w_[i];
  for (int i = q; i < n; ++i) z_[i] = -v_[i];
  Gemv(J_.data(), n, n, n, z_.data(), x_.data());
  for (int i = q - 1; i >= 0; --i) {
    double s = w_[i] + v_[i];
    for (int j = i + 1; j < q; ++j) s -= R_(i, j) * u_active_[j];
    u_active_[i] = s / R_(i, i);
  }
}

int DenseQpSolver::DropNegativeMultipliers(const Eigen::VectorXd& g_eff) {
  ComputeActiveSetSolution(g_eff);
  for (int dropped = 0;; ++dropped) {
    int worst = -1;
    double worst_u = 0.0;
    for (int j = q_eq_; j < q_; ++j) {
      if (u_active_[j] < worst_u) {
        worst_u = u_active_[j];
        worst = j;
      }
    }
    if (worst < 0) return dropped;
    DropConstraint(worst);
    ComputeActiveSetSolution(g_eff);
  }
}

void DenseQpSolver::RefineActiveSetSolution(const Eigen::VectorXd& g_eff, double shift) {
  // One step of iterative refinement of the active-set KKT system (H + shift I) x + g = N u, N^T x = b_A with
  // the current factors: residuals r_d = (H + shift I) x + g - N u, r_p = b_A - N^T x; the correction solves the
  // same system with g = r_d, b_A = r_p (same formulas as ComputeActiveSetSolution).
  const int n = n_;
  const int q = q_;
  double* rd = g_eff_refine_.data();
  Gemv(H.data(), n, n, n, x_.data(), rd);
  for (int i = 0; i < n; ++i) rd[i] += shift * x_[i] + g_eff[i];
  for (int c = 0; c < q; ++c) {
    const int id = active_[c];
    ComputeNormal(id, row_.data());
    const double uc = u_active_[c];
    for (int i = 0; i < n; ++i) rd[i] -= uc * row_[i];
    b_refine_[c] = Rhs(id) - NormalDot(id, x_);
  }
  // w1 = R^{-T} r_p, v = J^T r_d, dx = J1 w1 - J2 v2, du = R^{-1} (w1 + v1).
  for (int i = 0; i < q; ++i) {
    double sum = b_refine_[i];
    const double* ri = R_.col(i).data();
    for (int j = 0; j < i; ++j) sum -= ri[j] * w_[j];
    w_[i] = sum / ri[i];
  }
  GemvTransposed(J_.data(), n, n, n, rd, v_.data());
  for (int i = 0; i < q; ++i) z_[i] = w_[i];
  for (int i = q; i < n; ++i) z_[i] = -v_[i];
  Gemv(J_.data(), n, n, n, z_.data(), d_.data());
  for (int i = 0; i < n; ++i) x_[i] += d_[i];
  for (int i = q - 1; i >= 0; --i) {
    double sum = w_[i] + v_[i];
    for (int j = i + 1; j < q; ++j) sum -= R_(i, j) * r_[j];
    r_[i] = sum / R_(i, i);
  }
  for (int i = 0; i < q; ++i) u_active_[i] += r_[i];
}

void DenseQpSolver::ComputeNormal(int id, double* out) const {
  const int n = n_;
  if (id < n_eq_) {
    for (int i = 0; i < n; ++i) out[i] = A_eq(id, i);
  } else if (id < n_eq_ + 2 * n_ineq_) {
    const int k = id - n_eq_;
    const double sign = (k & 1) ? -1.0 : 1.0;
    for (int i = 0; i < n; ++i) out[i] = sign * A(k >> 1, i);
  } else {
    const int k = id - n_eq_ - 2 * n_ineq_;
    for (int i = 0; i < n; ++i) out[i] = 0.0;
    out[k >> 1] = (k & 1) ? -1.0 : 1.0;
  }
}

ROME_QP_HOT int DenseQpSolver::FindMostViolated(double* slack) {
  // Most violated inactive constraint, scored by violation / ||row|| (distance to the constraint plane).
  // Active constraints hold to rounding error, far below the tolerance, so they are practically never
  // candidates; the is_active_ test only guards that assumption (a skipped candidate triggers a rescan).
  const double tol = settings_.feasibility_tolerance;
  const int m = n_ineq_;
  const int n = n_;
  if (m > 0) Gemv(A.data(), m, m, n, x_.data(), Ax_.data());
  const double* __restrict ax = Ax_.data();
  const double* __restrict inv = inv_row_norm_.data();
  const double* __restrict xv = x_.data();
  int best_k = -1;
  double best_score = 0.0;
  for (int i = 0; i < m; ++i) {
    const double v = std::max(l[i] - ax[i], ax[i] - u[i]);
    if (v > tol && v * inv[i] > best_score) {
      best_score = v * inv[i];
      best_k = i;
    }
  }
  for (int j = 0; j < n; ++j) {
    const double v = std::max(lb[j] - xv[j], xv[j] - ub[j]);
    if (v > tol && v > best_score) {
      best_score = v;
      best_k = m + j;
    }
  }
  if (best_k < 0) return -1;
  int id;
  if (best_k < m) {
    const bool lower = ax[best_k] < l[best_k];
    id = IneqId(best_k, lower ? 0 : 1);
    *slack = lower ? ax[best_k] - l[best_k] : u[best_k] - ax[best_k];
  } else {
    const int j = best_k - m;
    const bool lower = xv[j] < lb[j];
    id = BoundId(j, lower ? 0 : 1);
    *slack = lower ? xv[j] - lb[j] : ub[j] - xv[j];
  }
  if (!is_active_[id]) return id;
  // Rare: the best candidate is already active (rounding). Full scan that skips active constraints.
  int best = -1;
  best_score = 0.0;
  for (int i = 0; i < m; ++i) {
    const bool lower = ax[i] < l[i];
    const double v = lower ? l[i] - ax[i] : ax[i] - u[i];
    const int cand = IneqId(i, lower ? 0 : 1);
    if (v > tol && v * inv[i] > best_score && !is_active_[cand]) {
      best_score = v * inv[i];
      best = cand;
      *slack = -v;
    }
  }
  for (int j = 0; j < n; ++j) {
    const bool lower = xv[j] < lb[j];
    const double v = lower ? lb[j] - xv[j] : xv[j] - ub[j];
    const int cand = BoundId(j, lower ? 0 : 1);
    if (v > tol && v > best_score && !is_active_[cand]) {
      best_score = v;
      best = cand;
      *slack = -v;
    }
  }
  return best;
}

void DenseQpSolver::RecordInfeasible(int id, int num_certificate) {
  // The violated constraint `id` plus the active constraints with nonzero coefficients r_ (n_id = N r).
  infeasible_ids_.clear();
  infeasible_ids_.push_back(id);
  double r_max = 0.0;
  for (int j = 0; j < num_certificate; ++j) r_max = std::max(r_max, std::abs(r_[j]));
  for (int j = 0; j < num_certificate; ++j) {
    if (std::abs(r_[j]) > kCertificateTolerance * r_max) infeasible_ids_.push_back(active_[j]);
  }
  infeasible_flat_.clear();
  for (int i : infeasible_ids_) infeasible_flat_.push_back(FlatIndex(i));
}

// ---------------------------------------------------------------------------------------------------------
// Goldfarb-Idnani iterations for one factorization of H and one linear term g_eff.

ROME_QP_HOT QpStatus DenseQpSolver::SolveFromFactor(const Eigen::VectorXd& g_eff, bool use_warm_start) {
  const int n = n_;
  for (int i = 0; i < q_; ++i) is_active_[active_[i]] = 0;
  q_ = 0;

  // Equalities are always active. Dependent ones are checked for consistency after x is known.
  // J and R after the equalities depend only on H and A_eq: reused when both are unchanged (MPC).
  int num_dependent = 0;
  if (use_eq_cache_) {
    J_ = J_eq_;
    q_ = q_eq_cached_;
    R_.topLeftCorner(q_, q_) = R_eq_.topLeftCorner(q_, q_);
    for (int i = 0; i < q_; ++i) {
      active_[i] = EqId(active_eq_cached_[i]);
      u_active_[i] = 0.0;
      is_active_[active_[i]] = 1;
    }
    num_dependent = num_dependent_cached_;
    for (int k = 0; k < num_dependent; ++k) dependent_eq_[k] = dependent_eq_cached_[k];
  } else {
    J_ = J0_;
    for (int i = 0; i < n_eq_; ++i) {
      ComputeD(EqId(i));
      if (DIsDependent()) {
        dependent_eq_[num_dependent++] = i;
      } else {
        AddConstraint(EqId(i), 0.0);
      }
    }
    if (store_eq_cache_) {
      J_eq_ = J_;
      R_eq_.topLeftCorner(q_, q_) = R_.topLeftCorner(q_, q_);
      for (int i = 0; i < q_; ++i) active_eq_cached_[i] = active_[i];
      for (int k = 0; k < num_dependent; ++k) dependent_eq_cached_[k] = dependent_eq_[k];
      q_eq_cached_ = q_;
      num_dependent_cached_ = num_dependent;
      A_eq_cached_ = A_eq;
      eq_cache_valid_ = true;
      use_eq_cache_ = true;  // later proximal iterations of this Solve() reuse it
    }
  }
  q_eq_ = q_;
  num_dependent_ = num_dependent;
  bool x_current = false;  // x_ and u_active_ correspond to the current active set
  if (num_dependent > 0 || !(use_warm_start && warm_count_ > 0)) {
    ComputeActiveSetSolution(g_eff);
    x_current = true;
  }
  for (int k = 0; k < num_dependent; ++k) {
    const int i = dependent_eq_[k];
    const double residual = A_eq.row(i).dot(x_) - b_eq[i];
    if (std::abs(residual) > settings_.feasibility_tolerance) {
      ComputeD(EqId(i));
      SolveR(q_);
      RecordInfeasible(EqId(i), q_);
      return QpStatus::kInfeasible;
    }
  }

  // Warm start: install the previous active inequality sides, then drop negative multipliers until the
  // active set is dual feasible (a valid starting point of the dual method).
  if (use_warm_start && warm_count_ > 0) {
    for (int k = 0; k < warm_count_ && q_ < n; ++k) {
      const int id = warm_active_[k];
      if (!SideIsFinite(id) || is_active_[id]) continue;
      ComputeD(id);
      if (DIsDependent()) continue;
      AddConstraint(id, 0.0);
    }
    DropNegativeMultipliers(g_eff);
    x_current = true;
  }

  return Iterate(g_eff, x_current);
}

ROME_QP_HOT QpStatus DenseQpSolver::Iterate(const Eigen::VectorXd& g_eff, bool x_current) {
  // GI pricing loop from a dual feasible working set (x_current: x_ and u_active_ are its solution).
  const int n = n_;
  while (true) {
    double s_p = 0.0;
    const int p = FindMostViolated(&s_p);
    if (p < 0) break;
    double u_p = 0.0;
    x_current = false;
    while (true) {
      if (iterations_ >= settings_.max_iterations) return QpStatus::kMaxIterations;
      ++iterations_;
      ComputeD(p);
      const int q = q_;
      SolveR(q);
      // Partial (dual) step length: first active inequality whose multiplier reaches zero.
      int k_drop = -1;
      double t1 = kInf;
      for (int j = q_eq_; j < q; ++j) {
        if (r_[j] > 0.0) {
          const double t = u_active_[j] / r_[j];
          if (t < t1) {
            t1 = t;
            k_drop = j;
          }
        }
      }
      const bool dependent = DIsDependent();
      if (dependent) {
        if (k_drop < 0) {
          RecordInfeasible(p, q);
          return QpStatus::kInfeasible;
        }
        // Step in the dual space only, then remove the blocking constraint.
        for (int j = 0; j < q; ++j) u_active_[j] -= t1 * r_[j];
        u_p += t1;
        DropConstraint(k_drop);
        continue;
      }
      const double zn = SquaredNorm(d_.data() + q, n - q);  // z^T n_p with z = J2 J2^T n_p
      const double t2 = -s_p / zn;
      const double t = std::min(t1, t2);
      Gemv(J_.data() + static_cast<Eigen::Index>(q) * n, n, n, n - q, d_.data() + q, z_.data());
      for (int i = 0; i < n; ++i) x_[i] += t * z_[i];
      for (int j = 0; j < q; ++j) u_active_[j] -= t * r_[j];
      u_p += t;
      if (t2 <= t1) {
        AddConstraint(p, u_p);
        break;
      }
      DropConstraint(k_drop);
      s_p = NormalDot(p, x_) - Rhs(p);
    }
  }
  // Recompute x and the multipliers from the final factorization (removes drift of the incremental updates).
  if (!x_current) ComputeActiveSetSolution(g_eff);
  return QpStatus::kOptimal;
}

ROME_QP_HOT bool DenseQpSolver::TryWarmActiveSet() {
  // Range-space solve of the equality-constrained QP on the previous active set W (all equalities plus the
  // warm inequality sides): with H = L L^T, M = L^{-1} N_W, h = L^{-1} g,
  //   (M^T M) u = b_W + M^T h,   x = L^{-T} (M u - h),   so that H x + g = N_W u.
  // Accepted only if it is the optimum: u >= 0 on inequality sides, every other constraint satisfied and the
  // active rows reproduced to the feasibility tolerance (guards against an ill-conditioned M^T M).
  const int n = n_;
  int q = 0;
  for (int i = 0; i < q_; ++i) is_active_[active_[i]] = 0;
  q_ = 0;
  // At most n independent constraints (active_ holds n + 1; M_ holds h in column q <= n).
  if (n_eq_ + warm_count_ > n) return false;
  for (int i = 0; i < n_eq_; ++i) active_[q++] = EqId(i);
  for (int k = 0; k < warm_count_; ++k) {
    if (!SideIsFinite(warm_active_[k])) return false;
    active_[q++] = warm_active_[k];
  }
  // T = [N_W g]^T (row c of T = constraint normal c, row q = g); column j of T holds the j-th components of all
  // q + 1 vectors contiguously, so the forward substitution L [M h] = [N_W g] becomes T.col(j) =
  // (T.col(j) - T(:, 0:j) L(j, 0:j)^T) / L(j, j): unrolled gemv passes of length q + 1.
  const int ld = static_cast<int>(T_.rows());
  const int q1 = q + 1;
  double* t = T_.data();
  for (int c = 0; c < q; ++c) {
    const int id = active_[c];
    if (id < n_eq_) {
      for (int j = 0; j < n; ++j) t[c + j * ld] = A_eq(id, j);
    } else if (id < n_eq_ + 2 * n_ineq_) {
      const int k = id - n_eq_;
      const double sign = (k & 1) ? -1.0 : 1.0;
      for (int j = 0; j < n; ++j) t[c + j * ld] = sign * A(k >> 1, j);
    } else {
      const int k = id - n_eq_ - 2 * n_ineq_;
      for (int j = 0; j < n; ++j) t[c + j * ld] = 0.0;
      t[c + (k >> 1) * ld] = (k & 1) ? -1.0 : 1.0;
    }
  }
  for (int j = 0; j < n; ++j) t[q + j * ld] = g[j];
  double* lrow = row_.data();
  double* tmp = t_col_.data();  // q + 1 <= n + 1 entries
  for (int j = 0; j < n; ++j) {
    double* tj = t + j * ld;
    if (j > 0) {
      for (int k = 0; k < j; ++k) lrow[k] = L_(j, k);
      Gemv(t, ld, q1, j, lrow, tmp);
      for (int i = 0; i < q1; ++i) tj[i] -= tmp[i];
    }
    const double inv = inv_diag_[j];
    for (int i = 0; i < q1; ++i) tj[i] *= inv;
  }
  // Back to columns: M_ = T(0:q, :)^T, h = T(q, :)^T.
  for (int c = 0; c < q1; ++c) {
    double* m = M_.col(c).data();
    for (int j = 0; j < n; ++j) m[j] = t[c + j * ld];
  }
  const double* h = M_.col(q).data();
  // G = M^T M (lower triangle, dot products of contiguous columns) and its Cholesky factor, in place.
  for (int j = 0; j < q; ++j) GemvTransposed(M_.col(j).data(), n, n, q - j, M_.col(j).data(), G_.col(j).data() + j);
  double g_max = 0.0;
  for (int j = 0; j < q; ++j) g_max = std::max(g_max, G_(j, j));
  const double tol = settings_.linear_dependence_tolerance;
  for (int j = 0; j < q; ++j) {
    double* __restrict gj = G_.col(j).data();
    for (int k = 0; k < j; ++k) {
      const double* __restrict gk = G_.col(k).data();
      const double gjk = gk[j];
      for (int i = j; i < q; ++i) gj[i] -= gjk * gk[i];
    }
    if (!(gj[j] > tol * tol * g_max)) return false;  // (nearly) dependent active set: use the GI path
    const double gjj = std::sqrt(gj[j]);
    gj[j] = gjj;
    const double inv = 1.0 / gjj;
    for (int i = j + 1; i < q; ++i) gj[i] *= inv;
  }
  // u = G^{-1} (b_W + M^T h).
  double* uu = u_active_.data();
  GemvTransposed(M_.data(), n, n, q, h, uu);
  for (int c = 0; c < q; ++c) uu[c] += Rhs(active_[c]);
  for (int j = 0; j < q; ++j) {  // forward: G_L w = rhs
    const double* __restrict gj = G_.col(j).data();
    const double wj = uu[j] / gj[j];
    uu[j] = wj;
    for (int i = j + 1; i < q; ++i) uu[i] -= wj * gj[i];
  }
  for (int i = q - 1; i >= 0; --i) {  // backward: G_L^T u = w
    const double* gi = G_.col(i).data();
    double sum = uu[i];
    for (int j = i + 1; j < q; ++j) sum -= gi[j] * uu[j];
    uu[i] = sum / gi[i];
  }
  for (int c = n_eq_; c < q; ++c) {
    if (uu[c] < 0.0) return false;
  }
  // y = M u - h, x = L^{-T} y (dot products with the contiguous columns of L).
  double* y = z_.data();
  Gemv(M_.data(), n, n, q, uu, y);
  for (int i = 0; i < n; ++i) y[i] -= h[i];
  double* x = x_.data();
  for (int i = n - 1; i >= 0; --i) {
    double sum = 0.0;
    GemvTransposed(L_.col(i).data() + i + 1, n, n - i - 1, 1, x + i + 1, &sum);
    x[i] = (y[i] - sum) * inv_diag_[i];
  }
  q_ = q;
  q_eq_ = n_eq_;
  for (int c = 0; c < q; ++c) is_active_[active_[c]] = 1;
  double slack = 0.0;
  if (FindMostViolated(&slack) >= 0) return false;  // also computes Ax_
  // Active rows must be reproduced (accuracy check of the normal equations, whose error grows with
  // cond(M)^2): residual * max(1, |u|) (the complementarity error it causes) well below the tolerance.
  // Otherwise the QR-based GI path, accurate to rounding, takes over.
  const double feas_tol = 0.01 * settings_.feasibility_tolerance;
  for (int c = 0; c < q; ++c) {
    const int id = active_[c];
    double value;
    if (id < n_eq_) {
      value = A_eq.row(id).dot(x_);
    } else if (id < n_eq_ + 2 * n_ineq_) {
      const int k = id - n_eq_;
      value = (k & 1) ? -Ax_[k >> 1] : Ax_[k >> 1];
    } else {
      const int k = id - n_eq_ - 2 * n_ineq_;
      value = (k & 1) ? -x[k >> 1] : x[k >> 1];
    }
    if (std::abs(value - Rhs(id)) * std::max(1.0, std::abs(u_active_[c])) > feas_tol) return false;
  }
  return true;
}

ROME_QP_HOT void DenseQpSolver::FillOutputs() {
  // Convert GI multipliers (H x + g = N u, u >= 0 on inequality sides) to the OSQP convention.
  y_eq_.setZero();
  y_ineq_.setZero();
  y_bounds_.setZero();
  for (int j = 0; j < q_; ++j) {
    const int id = active_[j];
    const double uj = u_active_[j];
    if (id < n_eq_) {
      y_eq_[id] = -uj;
    } else if (id < n_eq_ + 2 * n_ineq_) {
      const int k = id - n_eq_;
      y_ineq_[k >> 1] = (k & 1) ? uj : -uj;
    } else {
      const int k = id - n_eq_ - 2 * n_ineq_;
      y_bounds_[k >> 1] = (k & 1) ? uj : -uj;
    }
  }
  Gemv(H.data(), n_, n_, n_, x_.data(), v_.data());
  objective_ = 0.5 * x_.dot(v_) + g.dot(x_);
}

// ---------------------------------------------------------------------------------------------------------
// Hot start (see the header comment).

ROME_QP_HOT QpStatus DenseQpSolver::HotSolve(bool verify) {
  // J_, R_ and the working set active_[0, q_) are those of the last optimal solve for the same matrices.
  if (hot_updates_ >= kHotRefreshUpdates) return QpStatus::kMaxIterations;  // rebuild the factorization
  // Working-set sides whose bound became infinite leave first (from the top: lower positions stay valid).
  for (int j = q_ - 1; j >= q_eq_; --j) {
    if (!SideIsFinite(active_[j])) {
      DropConstraint(j);
      ++hot_updates_;
    }
  }
  // Solution on the kept working set for the new g and right-hand sides. Sides with negative multipliers leave,
  // the most negative first, until none is left: the start of the dual method must be dual feasible.
  hot_updates_ += DropNegativeMultipliers(g);
  // Unchanged working set with a feasible step: Iterate() finds no violated constraint and returns at once.
  const QpStatus status = Iterate(g, /*x_current=*/true);
  hot_updates_ += iterations_;
  if (status != QpStatus::kOptimal) return status;
  FillOutputs();
  if (verify && !VerifyHotSolution()) return QpStatus::kInvalidInput;  // matrices changed after all
  return QpStatus::kOptimal;
}

ROME_QP_HOT bool DenseQpSolver::VerifyHotSolution() {
  // KKT conditions on the data as stored now (the caller declared the matrices unchanged; this checks it where
  // it matters). Comparisons are written so that NaN fails them.
  const int n = n_;
  const double tol = settings_.feasibility_tolerance;
  // Stationarity: H x + g + A_eq^T y_eq + A^T y_ineq + y_bounds = 0 (H x is in v_ from FillOutputs).
  double* __restrict r = g_eff_refine_.data();
  double* __restrict t = z_.data();
  double scale = 1.0;
  for (int i = 0; i < n; ++i) {
    r[i] = v_[i] + g[i] + y_bounds_[i];
    scale = std::max(scale, std::max(std::abs(g[i]), std::abs(v_[i])));
  }
  if (n_eq_ > 0) {
    GemvTransposed(A_eq.data(), n_eq_, n_eq_, n, y_eq_.data(), t);
    for (int i = 0; i < n; ++i) r[i] += t[i];
  }
  if (n_ineq_ > 0) {
    GemvTransposed(A.data(), n_ineq_, n_ineq_, n, y_ineq_.data(), t);
    for (int i = 0; i < n; ++i) r[i] += t[i];
  }
  const double limit = kHotStationarityTolerance * scale;
  for (int i = 0; i < n; ++i) {
    if (!(std::abs(r[i]) <= limit)) return false;
  }
  // Primal feasibility of every row and bound (equalities are independent here, so n_eq <= n).
  if (n_eq_ > 0) {
    double* ax = b_refine_.data();
    Gemv(A_eq.data(), n_eq_, n_eq_, n, x_.data(), ax);
    for (int i = 0; i < n_eq_; ++i) {
      if (!(std::abs(ax[i] - b_eq[i]) <= tol)) return false;
    }
  }
  if (n_ineq_ > 0) Gemv(A.data(), n_ineq_, n_ineq_, n, x_.data(), Ax_.data());
  for (int i = 0; i < n_ineq_; ++i) {
    if (!(Ax_[i] >= l[i] - tol && Ax_[i] <= u[i] + tol)) return false;
  }
  for (int j = 0; j < n; ++j) {
    if (!(x_[j] >= lb[j] - tol && x_[j] <= ub[j] + tol)) return false;
  }
  // Complementarity and dual feasibility: every working-set side holds, with a multiplier of the right sign.
  for (int c = q_eq_; c < q_; ++c) {
    const int id = active_[c];
    double value;
    if (id < n_eq_ + 2 * n_ineq_) {
      const int k = id - n_eq_;
      value = (k & 1) ? -Ax_[k >> 1] : Ax_[k >> 1];
    } else {
      const int k = id - n_eq_ - 2 * n_ineq_;
      value = (k & 1) ? -x_[k >> 1] : x_[k >> 1];
    }
    if (!(std::abs(value - Rhs(id)) <= tol) || !(u_active_[c] >= -tol)) return false;
  }
  return true;
}

}  // namespace rome
