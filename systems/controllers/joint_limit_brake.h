#pragma once
// JointLimitBrake: rows of a whole-body QP that brake each joint before its URDF position limit (ours; issue 39).
// For every coordinate i with a finite limit, with q̈ affine in the QP's variables x (q̈ = q̈0 + Q_u u [+ M⁻¹ Jᵀ F]):
//   2 (q_lower,i + m − q_i − q̇_i T) / T²  ≤  q̈_i  ≤  2 (q_upper,i − m − q_i − q̇_i T) / T²
// i.e. the position predicted at constant acceleration over the horizon T, q_i + q̇_i T + ½ q̈_i T², stays at least the
// margin m inside each limit (params: margin_rad, horizon_s). Inside the band the bound is loose; a joint moving
// toward a limit gets a deceleration bound that grows as it nears it. Units: rad (m for a prismatic joint), s.
// Fill writes preallocated rows of a DenseQpSolver and allocates nothing. On a quaternion free-flyer base, i is a
// joint's velocity index and its position is q[i + 1] (MultibodyModel::PositionIndexOfVelocity); the base has no
// limits.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "solvers/qp/dense_qp_solver.h"
#include "systems/multibody/multibody_model.h"

namespace rome {

struct JointLimitBrakeParams {
  bool enabled = false;      ///< off by default (ours): the walking plans bend the ankles beyond their limits
  double margin_rad = 0.02;  ///< [rad] m: the predicted position stays this far inside each limit (ours)
  double horizon_s = 0.05;   ///< [s] T: the prediction horizon, a few control periods (ours)
  /// Throws std::invalid_argument "WHO: params.joint_limit_brake.FIELD = VALUE must be ..." for a bad field.
  void Validate(const std::string& who) const;
};

class JointLimitBrake {
 public:
  JointLimitBrake() = default;
  /// The limited coordinates of `model` (finite lower or upper limit), when params.enabled; none otherwise.
  JointLimitBrake(const MultibodyModel& model, const JointLimitBrakeParams& params, const std::string& who);
  int num_rows() const { return static_cast<int>(limited_.size()); }
  const std::vector<int>& limited() const { return limited_; }
  /// The bounds [lo, hi] on q̈ of velocity coordinate `i` at (q_i, q̇_i) [rad/s²] (the formula above; ±inf without a
  /// limit).
  void Bounds(double q, double v, int i, double* lo, double* hi) const;
  /// Rows offset … offset + num_rows() − 1 of `qp`: A = [Q_u.row(i), MinvJT.row(i) (augmented: columns nu …), 0],
  /// l/u = the bounds − q̈0_i. `minv_jt` has zero columns without force variables.
  void Fill(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
            const Eigen::VectorXd& qdd0, const Eigen::MatrixXd& Qu, const Eigen::Ref<const Eigen::MatrixXd>& minv_jt,
            int offset, DenseQpSolver& qp) const;
  /// Frees the rows (l = −inf, u = +inf), e.g. for a fallback solve.
  void Disable(int offset, DenseQpSolver& qp) const;

 private:
  JointLimitBrakeParams params_;
  std::vector<int> limited_;       // velocity indices
  std::vector<int> positions_;     // their indices in q
  Eigen::VectorXd lower_, upper_;  // per velocity index
};

}  // namespace rome
