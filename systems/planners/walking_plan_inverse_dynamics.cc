#include "systems/planners/walking_plan_inverse_dynamics.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/planners/centroidal_momentum_compensation.h"

namespace rome {

void ForEachSingleSupportInverseDynamics(const MultibodyModel& model, const WalkingPlan& plan,
                                         const SwingFootTrajectoryParams& swing,
                                         const WalkingPlanInverseDynamicsParams& params,
                                         const std::function<void(const WalkingPlanInverseDynamicsSample&)>& visit) {
  const double h = params.sample_period_s;
  if (!(h > 0 && h <= 0.02))
    throw std::invalid_argument("ForEachSingleSupportInverseDynamics: sample_period_s must be in (0, 0.02] s, got " +
                                std::to_string(h));
  if (!(params.end_time_s > 0))
    throw std::invalid_argument("ForEachSingleSupportInverseDynamics: end_time_s must be > 0 s, got " +
                                std::to_string(params.end_time_s));
  const int nv = model.nv(), nu = model.nu();
  if (nu + 6 != nv)
    throw std::invalid_argument("ForEachSingleSupportInverseDynamics: robot '" + model.name() + "' has " +
                                std::to_string(nu) + " actuators for " + std::to_string(nv) +
                                " velocities; single support is square only with nv - 6");
  const int feet[2] = {model.BodyIndex("left_foot"), model.BodyIndex("right_foot")};
  const Eigen::MatrixXd q = ReplayWalkingPlan(model, plan, swing, h);
  const Eigen::Index N = q.cols() - 1;
  const Eigen::VectorXd times =
      Eigen::VectorXd::LinSpaced(N + 1, 0.0, static_cast<double>(N) * h);  // ReplayWalkingPlan's grid
  Eigen::MatrixXd A(nv, nv), J(6, nv);
  A.setZero();
  for (int j = 0; j < nu; ++j) A(model.actuators()[j].v_index, j) = 1.0;
  MultibodyWorkspace ws(model);
  WalkingPlanInverseDynamicsSample s;
  Eigen::VectorXd tau(nv);
  for (Eigen::Index k = 1; k < N && times[k] <= params.end_time_s; ++k) {
    const WalkingDomain domain = plan.Sample(times[k]).domain;
    const bool double_support = domain == WalkingDomain::kDoubleSupport;
    if (double_support && !params.visit_double_support) continue;
    s.time_s = times[k];
    s.q = q.col(k);
    s.v = (q.col(k + 1) - q.col(k - 1)) / (2.0 * h);
    s.qdd = (q.col(k + 1) - 2.0 * q.col(k) + q.col(k - 1)) / (h * h);
    s.double_support = double_support;
    if (double_support) {
      s.stance_body = -1;
      s.u.setConstant(nu, std::numeric_limits<double>::quiet_NaN());
      s.wrench.setConstant(std::numeric_limits<double>::quiet_NaN());
      visit(s);
      continue;
    }
    if (plan.Sample(times[k - 1]).domain != domain || plan.Sample(times[k + 1]).domain != domain)
      continue;  // a difference across a switch
    s.stance_body = feet[domain == WalkingDomain::kLeftStance ? 0 : 1];
    CalcInverseDynamics(model, ws, s.q, s.v, s.qdd, tau);
    CalcFrameJacobian(model, ws, s.q, s.stance_body, Eigen::Vector3d(0, 0, -swing.ankle_height_m),
                      J);  // the sole point below the ankle
    A.rightCols(6) = J.transpose();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
    if (!(std::abs(lu.determinant()) > 0.0))
      throw std::runtime_error("ForEachSingleSupportInverseDynamics: robot '" + model.name() +
                               "': the single-support equations are singular at t = " + std::to_string(s.time_s) +
                               " s");
    const Eigen::VectorXd x = lu.solve(tau);
    s.u = x.head(nu);
    s.wrench = x.tail<6>();
    visit(s);
  }
}

WalkingPlanTorqueReport CalcWalkingPlanTorques(const MultibodyModel& model, const WalkingPlan& plan,
                                               const SwingFootTrajectoryParams& swing,
                                               const WalkingPlanInverseDynamicsParams& params) {
  WalkingPlanTorqueReport r;
  r.peak_torque_Nm = Eigen::VectorXd::Zero(model.nu());
  r.peak_time_s = Eigen::VectorXd::Zero(model.nu());
  ForEachSingleSupportInverseDynamics(model, plan, swing, params, [&](const WalkingPlanInverseDynamicsSample& s) {
    if (s.double_support) return;
    for (int j = 0; j < model.nu(); ++j) {
      if (std::abs(s.u[j]) > r.peak_torque_Nm[j]) r.peak_torque_Nm[j] = std::abs(s.u[j]), r.peak_time_s[j] = s.time_s;
    }
    const double fn = s.wrench[5];
    r.peak_normal_force_N = std::max(r.peak_normal_force_N, fn);
    const double ratio = fn > 0 ? std::hypot(s.wrench[3], s.wrench[4]) / fn : std::numeric_limits<double>::infinity();
    if (ratio > r.peak_friction_ratio) r.peak_friction_ratio = ratio, r.peak_friction_ratio_time_s = s.time_s;
    if (fn > 0) {
      r.peak_cop_offset_m.x() = std::max(r.peak_cop_offset_m.x(), std::abs(s.wrench[1] / fn));
      r.peak_cop_offset_m.y() = std::max(r.peak_cop_offset_m.y(), std::abs(s.wrench[0] / fn));
      r.peak_yaw_moment_ratio_m = std::max(r.peak_yaw_moment_ratio_m, std::abs(s.wrench[2] / fn));
    }
    ++r.samples;
  });
  for (int j = 0; j < model.nu(); ++j) {
    const double fraction = r.peak_torque_Nm[j] / model.actuators()[j].torque_limit_Nm;
    if (fraction > r.worst_limit_fraction) r.worst_limit_fraction = fraction, r.worst_actuator = j;
  }
  return r;
}

}  // namespace rome
