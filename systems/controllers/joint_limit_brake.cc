#include "systems/controllers/joint_limit_brake.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rome {

void JointLimitBrakeParams::Validate(const std::string& who) const {
  if (!(margin_rad >= 0.0) || !std::isfinite(margin_rad))
    throw std::invalid_argument(who + ": params.joint_limit_brake.margin_rad = " + std::to_string(margin_rad) +
                                " must be >= 0 and finite");
  if (!(horizon_s > 0.0) || !std::isfinite(horizon_s))
    throw std::invalid_argument(who + ": params.joint_limit_brake.horizon_s = " + std::to_string(horizon_s) +
                                " s must be positive and finite");
}

JointLimitBrake::JointLimitBrake(const MultibodyModel& model, const JointLimitBrakeParams& params,
                                 const std::string& who)
    : params_(params) {
  params_.Validate(who);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  lower_ = Eigen::VectorXd::Constant(model.nv(), -kInf);
  upper_ = Eigen::VectorXd::Constant(model.nv(), kInf);
  for (int i = 0; i < model.nv(); ++i) {
    const int p = model.PositionIndexOfVelocity(i);
    if (p < 0) continue;  // a twist entry of the quaternion base: no limit
    lower_[i] = model.position_lower_limits()[p];
    upper_[i] = model.position_upper_limits()[p];
    if (params_.enabled && (std::isfinite(lower_[i]) || std::isfinite(upper_[i]))) {
      if (std::isfinite(lower_[i]) && std::isfinite(upper_[i]) && upper_[i] - lower_[i] < 2 * params_.margin_rad)
        throw std::invalid_argument(who +
                                    ": params.joint_limit_brake.margin_rad = " + std::to_string(params_.margin_rad) +
                                    " leaves no room inside the limits of joint '" + model.JointName(i) + "' [" +
                                    std::to_string(lower_[i]) + ", " + std::to_string(upper_[i]) + "]");
      limited_.push_back(i);
      positions_.push_back(p);
    }
  }
}

void JointLimitBrake::Bounds(double q, double v, int i, double* lo, double* hi) const {
  const double T = params_.horizon_s, m = params_.margin_rad, drift = q + v * T;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  *lo = std::isfinite(lower_[i]) ? 2.0 * (lower_[i] + m - drift) / (T * T) : -kInf;
  *hi = std::isfinite(upper_[i]) ? 2.0 * (upper_[i] - m - drift) / (T * T) : kInf;
}

void JointLimitBrake::Fill(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
                           const Eigen::VectorXd& qdd0, const Eigen::MatrixXd& Qu,
                           const Eigen::Ref<const Eigen::MatrixXd>& minv_jt, int offset, DenseQpSolver& qp) const {
  const Eigen::Index nu = Qu.cols(), nf = minv_jt.cols();
  for (int k = 0; k < num_rows(); ++k) {
    const int i = limited_[k], r = offset + k;
    qp.A.row(r).setZero();
    qp.A.row(r).head(nu) = Qu.row(i);
    if (nf > 0) qp.A.row(r).segment(nu, nf) = minv_jt.row(i);
    double lo = 0, hi = 0;
    Bounds(q[positions_[k]], v[i], i, &lo, &hi);
    qp.l[r] = lo - qdd0[i];
    qp.u[r] = hi - qdd0[i];
  }
}

void JointLimitBrake::Disable(int offset, DenseQpSolver& qp) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < num_rows(); ++k) qp.l[offset + k] = -kInf, qp.u[offset + k] = kInf;
}

}  // namespace rome
