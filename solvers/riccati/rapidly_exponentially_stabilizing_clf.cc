#include "solvers/riccati/rapidly_exponentially_stabilizing_clf.h"

#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "solvers/riccati/continuous_algebraic_riccati_equation.h"
#include "solvers/riccati/continuous_lyapunov_equation.h"

namespace rome {
namespace {

[[noreturn]] void Fail(const std::string& what) {
  throw std::invalid_argument("ComputeRapidlyExponentiallyStabilizingClf: " + what);
}

}  // namespace

void MakeOutputDynamics(int o1, int o2, Eigen::MatrixXd* F, Eigen::MatrixXd* G) {
  if (o1 < 0 || o2 < 0 || o1 + o2 == 0) {
    std::ostringstream msg;
    msg << "MakeOutputDynamics: need o1 ≥ 0, o2 ≥ 0 and o1 + o2 > 0, got o1 = " << o1 << ", o2 = " << o2;
    throw std::invalid_argument(msg.str());
  }
  const int n = o1 + 2 * o2;
  F->setZero(n, n);
  G->setZero(n, o1 + o2);
  F->block(o1, o1 + o2, o2, o2).setIdentity();
  G->topLeftCorner(o1, o1).setIdentity();
  G->bottomRightCorner(o2, o2).setIdentity();
}

RapidlyExponentiallyStabilizingClf ComputeRapidlyExponentiallyStabilizingClf(
    const Eigen::Ref<const Eigen::MatrixXd>& F, const Eigen::Ref<const Eigen::MatrixXd>& G,
    const Eigen::Ref<const Eigen::MatrixXd>& Q, const RapidlyExponentiallyStabilizingClfParameters& parameters) {
  const int o1 = parameters.num_relative_degree_one_outputs;
  const int o2 = parameters.num_relative_degree_two_outputs;
  std::ostringstream msg;
  if (o1 < 0 || o2 < 0 || o1 + o2 == 0) {
    msg << "num_relative_degree_one_outputs = " << o1 << " and num_relative_degree_two_outputs = " << o2
        << " must be ≥ 0 with a positive sum";
    Fail(msg.str());
  }
  const Eigen::Index n = o1 + 2 * o2;
  if (F.rows() != n || F.cols() != n) {
    msg << "F must be " << n << "x" << n << " (o1 + 2 o2), got " << F.rows() << "x" << F.cols();
    Fail(msg.str());
  }
  if (G.rows() != n) {
    msg << "G must have " << n << " rows, got " << G.rows();
    Fail(msg.str());
  }
  if (Q.rows() != n || Q.cols() != n) {
    msg << "Q must be " << n << "x" << n << ", got " << Q.rows() << "x" << Q.cols();
    Fail(msg.str());
  }
  if (!(parameters.epsilon > 0.0)) {
    msg << "epsilon must be > 0, got " << parameters.epsilon;
    Fail(msg.str());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_q(0.5 * (Q + Q.transpose()), Eigen::EigenvaluesOnly);
  const double lambda_min_Q = eig_q.eigenvalues().minCoeff();
  if (!(lambda_min_Q > 0.0)) {
    msg << "Q must be positive definite, its smallest eigenvalue is " << lambda_min_Q;
    Fail(msg.str());
  }

  RapidlyExponentiallyStabilizingClf clf;
  if (parameters.equation == ClfEquation::kRiccati) {
    const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(G.cols(), G.cols());
    clf.P = SolveContinuousAlgebraicRiccatiEquation(F, G, Q, R);
  } else {
    clf.P = SolveContinuousLyapunovEquation(F, Q);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_p(clf.P, Eigen::EigenvaluesOnly);
  const double lambda_min_P = eig_p.eigenvalues().minCoeff();
  if (!(lambda_min_P > 0.0)) {
    msg << "P is not positive definite (λ_min(P) = " << lambda_min_P << ")";
    Fail(msg.str());
  }
  const double eps = parameters.epsilon;
  clf.epsilon = eps;
  Eigen::VectorXd scaling = Eigen::VectorXd::Ones(n);
  scaling.segment(o1, o2).setConstant(1.0 / eps);
  clf.I_epsilon = scaling.asDiagonal();
  clf.P_epsilon = scaling.asDiagonal() * clf.P * scaling.asDiagonal();
  clf.gamma = lambda_min_Q / eig_p.eigenvalues().maxCoeff();
  clf.convergence_rate = clf.gamma / eps;
  return clf;
}

}  // namespace rome
