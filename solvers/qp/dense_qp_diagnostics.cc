#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "solvers/qp/dense_qp_kernels.h"
#include "solvers/qp/dense_qp_solver.h"  // IWYU pragma: associated

// Diagnostics of rome::DenseQpSolver: input validation (which field, row and value is wrong), the status text,
// and the KKT residuals used by tests and benchmarks to certify solutions.

namespace rome {
namespace {

using namespace qp_kernels;  // NOLINT

// Relative symmetry tolerance for H.
constexpr double kSymmetryTolerance = 1e-10;

}  // namespace

std::string_view to_string(QpStatus status) {
  switch (status) {
    case QpStatus::kOptimal: return "optimal";
    case QpStatus::kInfeasible: return "infeasible";
    case QpStatus::kNonConvex: return "non-convex";
    case QpStatus::kUnbounded: return "unbounded";
    case QpStatus::kMaxIterations: return "max-iterations";
    case QpStatus::kInvalidInput: return "invalid-input";
  }
  return "unknown";
}

// ---------------------------------------------------------------------------------------------------------
// Input validation.

ROME_QP_HOT bool DenseQpSolver::ValidateInput(bool matrices) {
  input_error_ = InputError::kNone;
  auto size_error = [this](const char* field, Eigen::Index rows, Eigen::Index cols, int er, int ec) {
    if (rows == er && cols == ec) return false;
    input_error_ = InputError::kSize;
    bad_field_ = field;
    bad_row_ = static_cast<int>(rows);
    bad_col_ = static_cast<int>(cols);
    bad_rows_expected_ = er;
    bad_cols_expected_ = ec;
    return true;
  };
  if (size_error("H", H.rows(), H.cols(), n_, n_) || size_error("g", g.rows(), g.cols(), n_, 1) ||
      size_error("A_eq", A_eq.rows(), A_eq.cols(), n_eq_, n_) ||
      size_error("b_eq", b_eq.rows(), b_eq.cols(), n_eq_, 1) || size_error("A", A.rows(), A.cols(), n_ineq_, n_) ||
      size_error("l", l.rows(), l.cols(), n_ineq_, 1) || size_error("u", u.rows(), u.cols(), n_ineq_, 1) ||
      size_error("lb", lb.rows(), lb.cols(), n_, 1) || size_error("ub", ub.rows(), ub.cols(), n_, 1)) {
    return false;
  }
  // (m * 0).sum() is 0 exactly when every entry is finite (inf * 0 and NaN give NaN); vectorized by Eigen.
  auto finite_error = [this](const char* field, const Eigen::MatrixXd& m) {
    if (AllFinite(m.data(), m.size())) return false;
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      for (Eigen::Index r = 0; r < m.rows(); ++r) {
        if (!std::isfinite(m(r, c))) {
          input_error_ = InputError::kNotFinite;
          bad_field_ = field;
          bad_row_ = static_cast<int>(r);
          bad_col_ = static_cast<int>(c);
          bad_value_ = m(r, c);
          return true;
        }
      }
    }
    return false;
  };
  auto finite_vec_error = [this](const char* field, const Eigen::VectorXd& v) {
    if (AllFinite(v.data(), v.size())) return false;
    for (Eigen::Index r = 0; r < v.size(); ++r) {
      if (!std::isfinite(v[r])) {
        input_error_ = InputError::kNotFinite;
        bad_field_ = field;
        bad_row_ = static_cast<int>(r);
        bad_col_ = -1;
        bad_value_ = v[r];
        return true;
      }
    }
    return false;
  };
  if ((matrices && finite_error("H", H)) || finite_vec_error("g", g) || (matrices && finite_error("A_eq", A_eq)) ||
      finite_vec_error("b_eq", b_eq) || (matrices && finite_error("A", A))) {
    return false;
  }
  // Bounds: NaN is invalid, and so is an infinity on the wrong side (l = +inf, u = -inf, ...).
  auto bound_error = [this](const char* field, const Eigen::VectorXd& v, double forbidden_sign) {
    // Vectorized check first: no NaN (v != v) and no infinity of the forbidden sign.
    // (NaN compares false.)
    if (BoundsValid(v.data(), v.size(), forbidden_sign)) return false;
    for (Eigen::Index r = 0; r < v.size(); ++r) {
      const double value = v[r];
      if (std::isnan(value) || (std::isinf(value) && (value > 0) == (forbidden_sign > 0))) {
        input_error_ = InputError::kWrongInfinity;
        bad_field_ = field;
        bad_row_ = static_cast<int>(r);
        bad_col_ = -1;
        bad_value_ = value;
        return true;
      }
    }
    return false;
  };
  if (bound_error("l", l, +1.0) || bound_error("u", u, -1.0) || bound_error("lb", lb, +1.0) ||
      bound_error("ub", ub, -1.0)) {
    return false;
  }
  if (!matrices) return true;
  // Symmetry of H.
  double scale = 0.0;
  for (int j = 0; j < n_; ++j) scale = std::max(scale, std::abs(H(j, j)));
  const double sym_tol = kSymmetryTolerance * std::max(scale, 1.0);
  for (int j = 0; j < n_; ++j) {
    for (int i = j + 1; i < n_; ++i) {
      if (std::abs(H(i, j) - H(j, i)) > sym_tol) {
        input_error_ = InputError::kNotSymmetric;
        bad_field_ = "H";
        bad_row_ = i;
        bad_col_ = j;
        bad_value_ = H(i, j);
        bad_value2_ = H(j, i);
        return false;
      }
    }
  }
  return true;
}

// ---------------------------------------------------------------------------------------------------------

std::string DenseQpSolver::status_message() const {
  auto describe = [this](int id) {
    char buf[160];
    if (id < n_eq_) {
      std::snprintf(buf, sizeof(buf), "equality row %d (A_eq.row(%d) x = b_eq[%d] = %g)", id, id, id, b_eq[id]);
    } else if (id < n_eq_ + 2 * n_ineq_) {
      const int k = id - n_eq_;
      const int i = k >> 1;
      if (k & 1) {
        std::snprintf(buf, sizeof(buf), "inequality row %d upper side (A.row(%d) x <= u[%d] = %g)", i, i, i, u[i]);
      } else {
        std::snprintf(buf, sizeof(buf), "inequality row %d lower side (A.row(%d) x >= l[%d] = %g)", i, i, i, l[i]);
      }
    } else {
      const int k = id - n_eq_ - 2 * n_ineq_;
      const int j = k >> 1;
      if (k & 1) {
        std::snprintf(buf, sizeof(buf), "upper bound on x[%d] (ub[%d] = %g)", j, j, ub[j]);
      } else {
        std::snprintf(buf, sizeof(buf), "lower bound on x[%d] (lb[%d] = %g)", j, j, lb[j]);
      }
    }
    return std::string(buf);
  };
  char buf[256];
  switch (status_) {
    case QpStatus::kOptimal:
      std::snprintf(buf, sizeof(buf),
                    "DenseQpSolver: optimal after %d iterations, objective %.17g, %d active constraints", iterations_,
                    objective_, q_);
      return buf;
    case QpStatus::kNonConvex:
      std::snprintf(buf, sizeof(buf),
                    "DenseQpSolver: H (%dx%d) is not positive semidefinite: Cholesky of H + %g I failed "
                    "(QpSettings::regularization)",
                    n_, n_, settings_.regularization);
      return buf;
    case QpStatus::kUnbounded:
      return "DenseQpSolver: H is only positive semidefinite and the objective is unbounded below on the "
             "feasible set";
    case QpStatus::kMaxIterations:
      std::snprintf(buf, sizeof(buf),
                    "DenseQpSolver: iteration limit reached (%d iterations, %d proximal iterations; "
                    "QpSettings::max_iterations = %d, max_proximal_iterations = %d)",
                    iterations_, proximal_iterations_, settings_.max_iterations, settings_.max_proximal_iterations);
      return buf;
    case QpStatus::kInfeasible: {
      std::string msg;
      if (input_error_ == InputError::kContradictoryBounds && !infeasible_ids_.empty()) {
        const int id = infeasible_ids_[0];
        if (id < n_eq_ + 2 * n_ineq_) {
          std::snprintf(buf, sizeof(buf), "DenseQpSolver: infeasible: inequality row %d has l[%d] = %g > u[%d] = %g",
                        infeasible_flat_[0] - n_eq_, infeasible_flat_[0] - n_eq_, bad_value_,
                        infeasible_flat_[0] - n_eq_, bad_value2_);
        } else {
          const int j = infeasible_flat_[0] - n_eq_ - n_ineq_;
          std::snprintf(buf, sizeof(buf), "DenseQpSolver: infeasible: bound on x[%d] has lb[%d] = %g > ub[%d] = %g", j,
                        j, bad_value_, j, bad_value2_);
        }
        return buf;
      }
      // The first few of the subset keep the message one readable line; infeasible_constraints() has them all.
      constexpr size_t kListed = 6;
      msg = "DenseQpSolver: infeasible; these constraints cannot hold together: ";
      for (size_t k = 0; k < infeasible_ids_.size() && k < kListed; ++k) {
        if (k > 0) msg += ", ";
        msg += describe(infeasible_ids_[k]);
      }
      if (infeasible_ids_.size() > kListed) {
        msg += " and " + std::to_string(infeasible_ids_.size() - kListed) + " more (infeasible_constraints())";
      }
      return msg;
    }
    case QpStatus::kInvalidInput:
      switch (input_error_) {
        case InputError::kSize:
          std::snprintf(buf, sizeof(buf),
                        "DenseQpSolver: invalid input: %s has size %dx%d, expected %dx%d (n=%d, n_eq=%d, n_ineq=%d; "
                        "use Resize to change sizes)",
                        bad_field_, bad_row_, bad_col_, bad_rows_expected_, bad_cols_expected_, n_, n_eq_, n_ineq_);
          return buf;
        case InputError::kNotFinite:
          if (bad_col_ >= 0) {
            std::snprintf(buf, sizeof(buf), "DenseQpSolver: invalid input: %s(%d, %d) = %g is not finite", bad_field_,
                          bad_row_, bad_col_, bad_value_);
          } else {
            std::snprintf(buf, sizeof(buf), "DenseQpSolver: invalid input: %s[%d] = %g is not finite", bad_field_,
                          bad_row_, bad_value_);
          }
          return buf;
        case InputError::kWrongInfinity:
          std::snprintf(buf, sizeof(buf),
                        "DenseQpSolver: invalid input: %s[%d] = %g (NaN, or an infinity of the wrong sign)", bad_field_,
                        bad_row_, bad_value_);
          return buf;
        case InputError::kNotSymmetric:
          std::snprintf(buf, sizeof(buf),
                        "DenseQpSolver: invalid input: H is not symmetric: H(%d, %d) = %.17g but H(%d, %d) = %.17g",
                        bad_row_, bad_col_, bad_value_, bad_col_, bad_row_, bad_value2_);
          return buf;
        default: return "DenseQpSolver: Solve() has not been called";
      }
  }
  return "DenseQpSolver: unknown status";
}

// ---------------------------------------------------------------------------------------------------------

double QpKktResiduals::Max() const {
  return std::max(std::max(stationarity, primal_feasibility), std::max(dual_feasibility, complementarity));
}

QpKktResiduals ComputeQpKktResiduals(const DenseQpSolver& qp, const Eigen::VectorXd& x, const Eigen::VectorXd& y_eq,
                                     const Eigen::VectorXd& y_ineq, const Eigen::VectorXd& y_bounds) {
  QpKktResiduals res;
  Eigen::VectorXd grad = qp.H * x + qp.g + qp.A_eq.transpose() * y_eq + qp.A.transpose() * y_ineq + y_bounds;
  res.stationarity = grad.size() > 0 ? grad.lpNorm<Eigen::Infinity>() : 0.0;
  auto side_residuals = [&res](double value, double lo, double hi, double y) {
    res.primal_feasibility = std::max(res.primal_feasibility, std::max(lo - value, value - hi));
    if (y > 0.0) {
      if (std::isinf(hi)) {
        res.dual_feasibility = std::max(res.dual_feasibility, y);
      } else {
        res.complementarity = std::max(res.complementarity, y * std::abs(hi - value));
      }
    } else if (y < 0.0) {
      if (std::isinf(lo)) {
        res.dual_feasibility = std::max(res.dual_feasibility, -y);
      } else {
        res.complementarity = std::max(res.complementarity, -y * std::abs(value - lo));
      }
    }
  };
  for (Eigen::Index i = 0; i < qp.A_eq.rows(); ++i) {
    res.primal_feasibility = std::max(res.primal_feasibility, std::abs(qp.A_eq.row(i).dot(x) - qp.b_eq[i]));
  }
  for (Eigen::Index i = 0; i < qp.A.rows(); ++i) side_residuals(qp.A.row(i).dot(x), qp.l[i], qp.u[i], y_ineq[i]);
  for (Eigen::Index j = 0; j < x.size(); ++j) side_residuals(x[j], qp.lb[j], qp.ub[j], y_bounds[j]);
  return res;
}

QpKktResiduals ComputeQpKktResiduals(const DenseQpSolver& qp) {
  return ComputeQpKktResiduals(qp, qp.x(), qp.y_eq(), qp.y_ineq(), qp.y_bounds());
}

}  // namespace rome
