#pragma once
// LqrController: linear state feedback about an operating point, with the gain of the infinite-horizon LQR.
//
// inputs:  x (n)   state of the plant, in the plant's units
// outputs: u (m)   u = u0 − K (x − x0), direct feedthrough from x
// K is the LQR gain of (A, B, Q, R, N) from the CARE (systems/controllers/linear_quadratic_regulator.h); (x0, u0) is
// the operating point (A, B) were taken about, usually an equilibrium f(x0, u0) = 0. The block has no state; its
// output allocates nothing.
//
// Errors (std::invalid_argument, one line): those of LinearQuadraticRegulator, and x0 or u0 of the wrong size or
// not finite (naming the system).
#include <string>

#include <Eigen/Core>

#include "framework/linearize.h"
#include "framework/system.h"
#include "solvers/riccati/continuous_algebraic_riccati_equation.h"
#include "systems/controllers/linear_quadratic_regulator.h"

namespace rome {

class LqrController final : public LeafSystem {
 public:
  /// Gain from the CARE of (A, B, Q, R, N) (N empty: no cross term), operating point x0 (n), u0 (m).
  LqrController(std::string name, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                const Eigen::MatrixXd& R, const Eigen::VectorXd& x0, const Eigen::VectorXd& u0,
                const Eigen::MatrixXd& N = Eigen::MatrixXd(), const ContinuousAlgebraicRiccatiOptions& riccati = {});
  /// Gain from the CARE of a linearisation (framework/linearize.h): its A, B, x0 and u0.
  LqrController(std::string name, const LinearSystemMatrices& linearization, const Eigen::MatrixXd& Q,
                const Eigen::MatrixXd& R, const Eigen::MatrixXd& N = Eigen::MatrixXd(),
                const ContinuousAlgebraicRiccatiOptions& riccati = {});

  const Eigen::MatrixXd& K() const { return lqr_.K; }
  const Eigen::MatrixXd& S() const { return lqr_.S; }
  const Eigen::VectorXd& x0() const { return x0_; }
  const Eigen::VectorXd& u0() const { return u0_; }

 private:
  LinearQuadraticRegulatorResult lqr_;
  Eigen::VectorXd x0_, u0_;
  Eigen::MatrixXd minus_K_;   // −K
  Eigen::VectorXd u_offset_;  // u0 + K x0, so u = u_offset − K x
};

}  // namespace rome
