#include "solvers/riccati/continuous_algebraic_riccati_equation.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "solvers/riccati/continuous_lyapunov_equation.h"

namespace rome {
namespace {

constexpr const char* kWho = "SolveContinuousAlgebraicRiccatiEquation";

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(std::string(kWho) + ": " + what); }

void CheckSymmetric(const Eigen::Ref<const Eigen::MatrixXd>& M, const char* name, double tol) {
  const double asym = (M - M.transpose()).norm();
  if (asym > tol * std::max(1.0, M.norm())) {
    std::ostringstream msg;
    msg << name << " is not symmetric (‖" << name << " − " << name << "ᵀ‖_F = " << asym << ")";
    Fail(msg.str());
  }
}

void CheckInputs(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B,
                 const Eigen::Ref<const Eigen::MatrixXd>& Q, const Eigen::Ref<const Eigen::MatrixXd>& R,
                 const ContinuousAlgebraicRiccatiOptions& options) {
  const Eigen::Index n = A.rows();
  const Eigen::Index m = B.cols();
  std::ostringstream msg;
  if (n == 0 || A.cols() != n) {
    msg << "A must be square and non-empty, got " << A.rows() << "x" << A.cols();
    Fail(msg.str());
  }
  if (B.rows() != n || m == 0) {
    msg << "B must have " << n << " rows and at least one column, got " << B.rows() << "x" << m;
    Fail(msg.str());
  }
  if (Q.rows() != n || Q.cols() != n) {
    msg << "Q must be " << n << "x" << n << ", got " << Q.rows() << "x" << Q.cols();
    Fail(msg.str());
  }
  if (R.rows() != m || R.cols() != m) {
    msg << "R must be " << m << "x" << m << ", got " << R.rows() << "x" << R.cols();
    Fail(msg.str());
  }
  if (!A.allFinite() || !B.allFinite() || !Q.allFinite() || !R.allFinite()) { Fail("A, B, Q or R contains NaN/Inf"); }
  CheckSymmetric(Q, "Q", options.symmetry_tolerance);
  CheckSymmetric(R, "R", options.symmetry_tolerance);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_r(R, Eigen::EigenvaluesOnly);
  if (eig_r.eigenvalues().minCoeff() <= 0.0) {
    msg << "R must be positive definite, its smallest eigenvalue is " << eig_r.eigenvalues().minCoeff();
    Fail(msg.str());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_q(Q, Eigen::EigenvaluesOnly);
  if (eig_q.eigenvalues().minCoeff() < -options.symmetry_tolerance * std::max(1.0, Q.norm())) {
    msg << "Q must be positive semidefinite, its smallest eigenvalue is " << eig_q.eigenvalues().minCoeff();
    Fail(msg.str());
  }
  // PBH test: every eigenvalue λ of A with Re λ ≥ 0 needs rank [A − λI, B] = n.
  const Eigen::VectorXcd lambda = A.eigenvalues();
  // [A − λI, B] = X + iY has the singular values of the real [[X, −Y], [Y, X]], each twice.
  Eigen::MatrixXd AB(2 * n, 2 * (n + m));
  const double scale = std::max(1.0, std::sqrt(A.squaredNorm() + B.squaredNorm()));
  for (Eigen::Index i = 0; i < n; ++i) {
    if (lambda(i).real() < -options.axis_tolerance * scale) continue;
    AB.setZero();
    AB.topLeftCorner(n, n) = A;
    AB.topLeftCorner(n, n).diagonal().array() -= lambda(i).real();
    AB.block(0, n, n, m) = B;
    AB.bottomRightCorner(n, n + m) = AB.topLeftCorner(n, n + m);
    AB.block(0, n + m, n, n).diagonal().setConstant(lambda(i).imag());
    AB.block(n, 0, n, n).diagonal().setConstant(-lambda(i).imag());
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(AB);
    const double sigma_min = svd.singularValues()(2 * n - 1);
    if (sigma_min <= options.rank_tolerance * scale) {
      msg << "(A, B) is not stabilizable: eigenvalue " << lambda(i)
          << " of A is uncontrollable (σ_min[A − λI, B] = " << sigma_min << ")";
      Fail(msg.str());
    }
  }
}

}  // namespace

double ContinuousAlgebraicRiccatiRelativeResidual(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& B,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& R,
                                                  const Eigen::Ref<const Eigen::MatrixXd>& P) {
  const Eigen::MatrixXd AtP = A.transpose() * P;
  const Eigen::MatrixXd PA = P * A;
  const Eigen::MatrixXd BtP = B.transpose() * P;
  const Eigen::MatrixXd PSP = BtP.transpose() * R.llt().solve(BtP);
  const double denom = std::max(AtP.norm() + PA.norm() + PSP.norm() + Q.norm(), std::numeric_limits<double>::min());
  return (AtP + PA - PSP + Q).norm() / denom;
}

ContinuousAlgebraicRiccatiSolution SolveContinuousAlgebraicRiccatiEquationWithDetails(
    const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B,
    const Eigen::Ref<const Eigen::MatrixXd>& Q, const Eigen::Ref<const Eigen::MatrixXd>& R,
    const ContinuousAlgebraicRiccatiOptions& options) {
  CheckInputs(A, B, Q, R, options);
  const Eigen::Index n = A.rows();
  const Eigen::LLT<Eigen::MatrixXd> R_llt(R);
  const Eigen::MatrixXd S = B * R_llt.solve(B.transpose());  // B R⁻¹ Bᵀ

  Eigen::MatrixXd H(2 * n, 2 * n);
  H << A, -S, -Q, -A.transpose();

  // Hamiltonian eigenvalues on the imaginary axis ⇒ no stabilizing solution.
  const Eigen::VectorXcd mu = H.eigenvalues();
  const double h_scale = std::max(1.0, H.norm());
  for (Eigen::Index i = 0; i < mu.size(); ++i) {
    if (std::abs(mu(i).real()) <= options.axis_tolerance * h_scale) {
      std::ostringstream msg;
      msg << "the Hamiltonian has eigenvalue " << mu(i)
          << " on the imaginary axis: (Q, A) has an unobservable mode on the imaginary axis, "
             "no stabilizing solution exists";
      Fail(msg.str());
    }
  }

  ContinuousAlgebraicRiccatiSolution solution;
  // Matrix sign function with determinant scaling.
  Eigen::MatrixXd Z = H;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(2 * n);
  for (int k = 0; k < options.max_sign_iterations; ++k) {
    lu.compute(Z);
    const double log_abs_det = lu.matrixLU().diagonal().array().abs().log().sum();
    const double c = std::exp(-log_abs_det / static_cast<double>(2 * n));
    Eigen::MatrixXd Z_next = 0.5 * (c * Z + lu.inverse() / c);
    const double change = (Z_next - Z).cwiseAbs().colwise().sum().maxCoeff();
    const double size = Z.cwiseAbs().colwise().sum().maxCoeff();
    Z.swap(Z_next);
    solution.sign_iterations = k + 1;
    if (change <= options.sign_tolerance * size) break;
  }
  // If the sign iteration hit its cap, the Newton polish below usually still converges; the
  // final residual/stability check decides.
  Eigen::MatrixXd lhs(2 * n, n), rhs(2 * n, n);
  lhs << Z.topRightCorner(n, n), Z.bottomRightCorner(n, n) + Eigen::MatrixXd::Identity(n, n);
  rhs << Z.topLeftCorner(n, n) + Eigen::MatrixXd::Identity(n, n), Z.bottomLeftCorner(n, n);
  Eigen::MatrixXd P = lhs.colPivHouseholderQr().solve(-rhs);
  P = 0.5 * (P + P.transpose());

  // Newton–Kleinman polish: (A − S P)ᵀ ΔP + ΔP (A − S P) + Res(P) = 0.
  double residual = ContinuousAlgebraicRiccatiRelativeResidual(A, B, Q, R, P);
  for (int k = 0; k < options.max_newton_refinements && residual > 0.0; ++k) {
    const Eigen::MatrixXd Acl = A - S * P;
    const Eigen::MatrixXd Res = A.transpose() * P + P * A - P * S * P + Q;
    Eigen::MatrixXd P_next;
    try {
      P_next = P + SolveContinuousLyapunovEquationUnchecked(Acl, 0.5 * (Res + Res.transpose()));
    } catch (const std::invalid_argument&) { break; }
    const double next_residual = ContinuousAlgebraicRiccatiRelativeResidual(A, B, Q, R, P_next);
    if (!(next_residual < residual)) break;
    P = P_next;
    residual = next_residual;
    solution.newton_refinements = k + 1;
    if (residual < 1e-15) break;
  }

  const Eigen::VectorXcd closed_loop = (A - S * P).eigenvalues();
  const double max_real = closed_loop.real().maxCoeff();
  if (!P.allFinite() || max_real >= 0.0 || residual > 1e-6) {
    std::ostringstream msg;
    msg << "failed to find the stabilizing solution (relative residual " << residual
        << ", max Re λ(A − B K) = " << max_real << ", sign iterations " << solution.sign_iterations << ")";
    Fail(msg.str());
  }
  solution.K = R_llt.solve(B.transpose() * P);
  solution.P = std::move(P);
  solution.relative_residual = residual;
  return solution;
}

Eigen::MatrixXd SolveContinuousAlgebraicRiccatiEquation(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                                        const Eigen::Ref<const Eigen::MatrixXd>& B,
                                                        const Eigen::Ref<const Eigen::MatrixXd>& Q,
                                                        const Eigen::Ref<const Eigen::MatrixXd>& R,
                                                        const ContinuousAlgebraicRiccatiOptions& options) {
  return SolveContinuousAlgebraicRiccatiEquationWithDetails(A, B, Q, R, options).P;
}

}  // namespace rome
