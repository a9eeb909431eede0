#include "systems/controllers/linear_quadratic_regulator.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace rome {

namespace {

constexpr const char* kWho = "LinearQuadraticRegulator: ";

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(kWho + what); }

std::string Shape(const Eigen::MatrixXd& M) { return std::to_string(M.rows()) + "x" + std::to_string(M.cols()); }

void CheckShape(const Eigen::MatrixXd& M, const char* name, Eigen::Index rows, Eigen::Index cols) {
  if (M.rows() != rows || M.cols() != cols)
    Fail(std::string(name) + " must be " + std::to_string(rows) + "x" + std::to_string(cols) + ", got " + Shape(M));
}

void CheckSymmetric(const Eigen::MatrixXd& M, const char* name, double tolerance) {
  const double asymmetry = (M - M.transpose()).norm();
  if (asymmetry > tolerance * std::max(1.0, M.norm())) {
    std::ostringstream msg;
    msg << name << " must be symmetric, got ‖" << name << " − " << name << "ᵀ‖_F = " << asymmetry;
    Fail(msg.str());
  }
}

}  // namespace

LinearQuadraticRegulatorResult LinearQuadraticRegulator(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                                        const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
                                                        const Eigen::MatrixXd& N,
                                                        const ContinuousAlgebraicRiccatiOptions& riccati) {
  const Eigen::Index n = A.rows(), m = B.cols();
  if (n == 0 || A.cols() != n) Fail("A must be square and non-empty, got " + Shape(A));
  if (m == 0) Fail("B must have at least one column, got " + Shape(B));
  CheckShape(B, "B", n, m);
  CheckShape(Q, "Q", n, n);
  CheckShape(R, "R", m, m);
  if (N.size() != 0) CheckShape(N, "N", n, m);
  if (!A.allFinite() || !B.allFinite() || !Q.allFinite() || !R.allFinite() || !N.allFinite())
    Fail("A, B, Q, R or N contains NaN or Inf");
  CheckSymmetric(Q, "Q", riccati.symmetry_tolerance);
  CheckSymmetric(R, "R", riccati.symmetry_tolerance);
  const Eigen::LLT<Eigen::MatrixXd> R_llt(R);
  if (R_llt.info() != Eigen::Success) {
    std::ostringstream msg;
    msg << "R must be positive definite, its smallest eigenvalue is "
        << Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(R).eigenvalues().minCoeff();
    Fail(msg.str());
  }
  Eigen::MatrixXd A_bar = A, Q_bar = Q;
  if (N.size() != 0) {
    const Eigen::MatrixXd Rinv_Nt = R_llt.solve(N.transpose());
    A_bar -= B * Rinv_Nt;
    Q_bar -= N * Rinv_Nt;
    Q_bar = (0.5 * (Q_bar + Q_bar.transpose())).eval();
    const double lambda_min = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Q_bar).eigenvalues().minCoeff();
    if (lambda_min < -riccati.symmetry_tolerance * std::max(1.0, Q.norm())) {
      std::ostringstream msg;
      msg << "Q − N R⁻¹ Nᵀ must be positive semidefinite, its smallest eigenvalue is " << lambda_min;
      Fail(msg.str());
    }
  }
  LinearQuadraticRegulatorResult result;
  try {
    result.S = SolveContinuousAlgebraicRiccatiEquation(A_bar, B, Q_bar, R, riccati);
  } catch (const std::invalid_argument& e) { Fail(e.what()); }
  Eigen::MatrixXd Bt_S_plus_Nt = B.transpose() * result.S;
  if (N.size() != 0) Bt_S_plus_Nt += N.transpose();
  result.K = R_llt.solve(Bt_S_plus_Nt);
  return result;
}

LinearQuadraticRegulatorResult LinearQuadraticRegulator(const System& system, Context& context,
                                                        const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
                                                        const std::string& input_port, const Eigen::MatrixXd& N,
                                                        const LinearizeParams& linearize,
                                                        const ContinuousAlgebraicRiccatiOptions& riccati) {
  if (input_port.empty()) Fail("system '" + system.name() + "': name the input port u");
  const LinearSystemMatrices lin = Linearize(system, context, input_port, "", linearize);
  return LinearQuadraticRegulator(lin.A, lin.B, Q, R, N, riccati);
}

}  // namespace rome
