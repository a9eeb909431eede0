#pragma once
// JointPdController: joint-space PD with feedforward on the actuated joints.
//
// inputs:  state (2 nv)   [q; v] of the plant
// outputs: u (nu)         u = u_ff + Kp (q_des − Bᵀq) − Kd Bᵀv   [N m], direct feedthrough from state
// B is the plant's nv × nu selection matrix (MultibodyModel::B()).

#include "framework/system.h"

namespace rome {

struct JointPdGains {
  Eigen::VectorXd kp;     ///< [N m/rad] per actuator
  Eigen::VectorXd kd;     ///< [N m s/rad] per actuator
  Eigen::VectorXd q_des;  ///< [rad] per actuator
  Eigen::VectorXd u_ff;   ///< [N m] per actuator
};

class JointPdController final : public LeafSystem {
 public:
  JointPdController(std::string name, const Eigen::MatrixXd& B, JointPdGains gains);

 private:
  Eigen::MatrixXd Bt_;
  JointPdGains gains_;
};

}  // namespace rome
