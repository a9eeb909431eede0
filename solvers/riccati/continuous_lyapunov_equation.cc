#include "solvers/riccati/continuous_lyapunov_equation.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace rome {
namespace {

void CheckSizes(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& Q,
                double symmetry_tolerance) {
  if (A.rows() != A.cols() || A.rows() == 0) {
    std::ostringstream msg;
    msg << "SolveContinuousLyapunovEquation: A must be square and non-empty, got " << A.rows() << "x" << A.cols();
    throw std::invalid_argument(msg.str());
  }
  if (Q.rows() != A.rows() || Q.cols() != A.cols()) {
    std::ostringstream msg;
    msg << "SolveContinuousLyapunovEquation: Q must be " << A.rows() << "x" << A.cols() << ", got " << Q.rows() << "x"
        << Q.cols();
    throw std::invalid_argument(msg.str());
  }
  if (!A.allFinite() || !Q.allFinite()) {
    throw std::invalid_argument("SolveContinuousLyapunovEquation: A or Q contains NaN/Inf");
  }
  const double asym = (Q - Q.transpose()).norm();
  if (asym > symmetry_tolerance * std::max(1.0, Q.norm())) {
    std::ostringstream msg;
    msg << "SolveContinuousLyapunovEquation: Q is not symmetric (‖Q − Qᵀ‖_F = " << asym << ")";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

Eigen::MatrixXd SolveContinuousLyapunovEquationUnchecked(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                         const Eigen::Ref<const Eigen::MatrixXd>& Q) {
  const Eigen::Index n = A.rows();
  Eigen::ComplexSchur<Eigen::MatrixXd> schur(A, true);
  if (schur.info() != Eigen::Success) {
    throw std::invalid_argument("SolveContinuousLyapunovEquation: Schur decomposition of A failed");
  }
  const Eigen::MatrixXcd& T = schur.matrixT();
  const Eigen::MatrixXcd& U = schur.matrixU();
  Eigen::MatrixXcd C = -(U.adjoint() * Q.cast<std::complex<double>>() * U);
  Eigen::MatrixXcd Y = Eigen::MatrixXcd::Zero(n, n);
  const double scale = std::max(1.0, T.norm());
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      std::complex<double> rhs = C(i, j);
      for (Eigen::Index k = 0; k < i; ++k) rhs -= std::conj(T(k, i)) * Y(k, j);
      for (Eigen::Index k = 0; k < j; ++k) rhs -= Y(i, k) * T(k, j);
      const std::complex<double> denom = std::conj(T(i, i)) + T(j, j);
      if (std::abs(denom) <= 1e3 * std::numeric_limits<double>::epsilon() * scale) {
        std::ostringstream msg;
        msg << "SolveContinuousLyapunovEquation: singular equation, eigenvalues " << T(i, i) << " and " << T(j, j)
            << " of A satisfy λ_i + conj(λ_j) ≈ 0";
        throw std::invalid_argument(msg.str());
      }
      Y(i, j) = rhs / denom;
    }
  }
  Eigen::MatrixXd P = (U * Y * U.adjoint()).real();
  return 0.5 * (P + P.transpose());
}

Eigen::MatrixXd SolveContinuousLyapunovEquation(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                                const ContinuousLyapunovOptions& options) {
  CheckSizes(A, Q, options.symmetry_tolerance);
  const Eigen::VectorXcd eigenvalues = A.eigenvalues();
  Eigen::Index worst = 0;
  eigenvalues.real().maxCoeff(&worst);
  if (eigenvalues(worst).real() >= -options.hurwitz_margin * std::max(1.0, A.norm())) {
    std::ostringstream msg;
    msg << "SolveContinuousLyapunovEquation: A is not Hurwitz, it has eigenvalue " << eigenvalues(worst)
        << " with non-negative real part (Aᵀ P + P A + Q = 0 has no "
        << "positive-definite solution)";
    throw std::invalid_argument(msg.str());
  }
  return SolveContinuousLyapunovEquationUnchecked(A, Q);
}

double ContinuousLyapunovRelativeResidual(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                          const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                          const Eigen::Ref<const Eigen::MatrixXd>& P) {
  const Eigen::MatrixXd AtP = A.transpose() * P;
  const Eigen::MatrixXd PA = P * A;
  const double denom = std::max(AtP.norm() + PA.norm() + Q.norm(), std::numeric_limits<double>::min());
  return (AtP + PA + Q).norm() / denom;
}

}  // namespace rome
