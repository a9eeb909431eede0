#include "systems/controllers/lqr_controller.h"

#include <stdexcept>

namespace rome {

LqrController::LqrController(std::string name, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                             const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R, const Eigen::VectorXd& x0,
                             const Eigen::VectorXd& u0, const Eigen::MatrixXd& N,
                             const ContinuousAlgebraicRiccatiOptions& riccati)
    : LeafSystem(std::move(name)), x0_(x0), u0_(u0) {
  try {
    lqr_ = LinearQuadraticRegulator(A, B, Q, R, N, riccati);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("system '" + this->name() + "': " + e.what());
  }
  const int n = static_cast<int>(A.rows()), m = static_cast<int>(B.cols());
  if (x0.size() != n)
    throw std::invalid_argument("system '" + this->name() + "': x0 must have size " + std::to_string(n) + ", got " +
                                std::to_string(x0.size()));
  if (u0.size() != m)
    throw std::invalid_argument("system '" + this->name() + "': u0 must have size " + std::to_string(m) + ", got " +
                                std::to_string(u0.size()));
  if (!x0.allFinite() || !u0.allFinite())
    throw std::invalid_argument("system '" + this->name() + "': x0 or u0 contains NaN or Inf");
  minus_K_ = -lqr_.K;
  u_offset_ = u0_ + lqr_.K * x0_;
  DeclareInputPort("x", n);
  DeclareOutputPort("u", m, [this](const LeafContext& c, Eigen::VectorXd* u) {
    u->noalias() = minus_K_ * EvalInput(c, 0);
    *u += u_offset_;
  });
}

LqrController::LqrController(std::string name, const LinearSystemMatrices& linearization, const Eigen::MatrixXd& Q,
                             const Eigen::MatrixXd& R, const Eigen::MatrixXd& N,
                             const ContinuousAlgebraicRiccatiOptions& riccati)
    : LqrController(std::move(name), linearization.A, linearization.B, Q, R, linearization.x0, linearization.u0, N,
                    riccati) {}

}  // namespace rome
