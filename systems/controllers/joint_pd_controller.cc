#include "systems/controllers/joint_pd_controller.h"

namespace rome {

JointPdController::JointPdController(std::string name, const Eigen::MatrixXd& B, JointPdGains gains)
    : LeafSystem(std::move(name)), Bt_(B.transpose()), gains_(std::move(gains)) {
  const int nv = static_cast<int>(B.rows()), nu = static_cast<int>(B.cols());
  auto check = [&](const Eigen::VectorXd& v, const char* what) {
    if (v.size() != nu)
      ThrowError(std::string("gain '") + what + "' has size " + std::to_string(v.size()) +
                 ", expected nu = " + std::to_string(nu));
  };
  check(gains_.kp, "kp");
  check(gains_.kd, "kd");
  check(gains_.q_des, "q_des");
  check(gains_.u_ff, "u_ff");
  DeclareInputPort("state", 2 * nv);
  DeclareOutputPort("u", nu, [this, nv](const LeafContext& c, Eigen::VectorXd* u) {
    const Eigen::VectorXd& x = EvalInput(c, 0);
    *u = gains_.u_ff + gains_.kp.cwiseProduct(gains_.q_des - Bt_ * x.head(nv)) -
         gains_.kd.cwiseProduct(Bt_ * x.tail(nv));
  });
}

}  // namespace rome
