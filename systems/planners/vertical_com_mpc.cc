#include "systems/planners/vertical_com_mpc.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rome {

VerticalComMpc::VerticalComMpc(VerticalComMpcParams params) : params_(params) {
  const int N = params_.horizon_steps;
  if (N < 1)
    throw std::invalid_argument("VerticalComMpc: parameter horizon_steps (N) must be >= 1, got " + std::to_string(N));
  if (!(params_.gravity > 0 && std::isfinite(params_.gravity)))
    throw std::invalid_argument("VerticalComMpc: parameter gravity must be positive (m/s²), got " +
                                std::to_string(params_.gravity));
  if (!(params_.min_horizon_s > 0 && std::isfinite(params_.min_horizon_s)))
    throw std::invalid_argument("VerticalComMpc: parameter min_horizon_s must be positive (s), got " +
                                std::to_string(params_.min_horizon_s));
  if (!(params_.max_acceleration > -params_.gravity))
    throw std::invalid_argument("VerticalComMpc: parameter max_acceleration must exceed -gravity (m/s²), got " +
                                std::to_string(params_.max_acceleration));
  if (!(params_.terminal_position_weight > 0) || !(params_.terminal_velocity_weight > 0))
    throw std::invalid_argument(
        "VerticalComMpc: parameters terminal_position_weight / terminal_velocity_weight must be > 0, got " +
        std::to_string(params_.terminal_position_weight) + " / " + std::to_string(params_.terminal_velocity_weight));
  const bool equality = params_.terminal_condition == VerticalComMpcParams::TerminalCondition::kEquality;
  qp_ = std::make_unique<DenseQpSolver>(equality ? N : N + 2, 2, 0, params_.qp);
  BuildQp(qp_.get(), /*with_slacks=*/!equality);
  if (equality && params_.relax_terminal_on_infeasible) {
    soft_qp_ = std::make_unique<DenseQpSolver>(N + 2, 2, 0, params_.qp);
    BuildQp(soft_qp_.get(), /*with_slacks=*/true);
  }
  u_ = Eigen::VectorXd::Zero(N);
  p_ = Eigen::VectorXd::Zero(N + 1);
  v_ = Eigen::VectorXd::Zero(N + 1);
}

void VerticalComMpc::BuildQp(DenseQpSolver* qp, bool with_slacks) const {
  const int N = params_.horizon_steps;
  // Cost Σ u_k² = ½ uᵀ (2I) u; slacks s (terminal errors as accelerations) cost ρ s².
  qp->H.setZero();
  qp->H.topLeftCorner(N, N).diagonal().setConstant(2.0);
  qp->g.setZero();
  qp->lb.head(N).setConstant(-params_.gravity);          // contact constraint u_k >= −g; slacks are free
  qp->ub.head(N).setConstant(params_.max_acceleration);  // the leg's push, u_k <= a_max (+inf: none)
  // Scaled terminal rows: Σ (N − k − ½) u_k [− s_p] = (p^f − p_0 − T ṗ_0)/dt², Σ u_k [− s_v] = (ṗ^f − ṗ_0)/dt.
  qp->A_eq.setZero();
  for (int k = 0; k < N; ++k) {
    qp->A_eq(0, k) = N - k - 0.5;
    qp->A_eq(1, k) = 1.0;
  }
  if (with_slacks) {
    qp->H(N, N) = 2.0 * params_.terminal_position_weight;
    qp->H(N + 1, N + 1) = 2.0 * params_.terminal_velocity_weight;
    qp->A_eq(0, N) = -1.0;
    qp->A_eq(1, N + 1) = -1.0;
  }
}

QpStatus VerticalComMpc::Solve(double p_z, double pdot_z, double p_final, double v_final, double horizon_s) {
  if (!(std::isfinite(p_z) && std::isfinite(pdot_z) && std::isfinite(p_final) && std::isfinite(v_final) &&
        std::isfinite(horizon_s))) {
    status_ = QpStatus::kInvalidInput;
    return status_;
  }
  const int N = params_.horizon_steps;
  const double T = std::max(horizon_s, params_.min_horizon_s);
  const double dt = T / N;
  const double b_p = (p_final - p_z - T * pdot_z) / (dt * dt);  // terminal position to be produced by the inputs
  const double b_v = (v_final - pdot_z) / dt;
  DenseQpSolver& qp = *qp_;
  qp.b_eq << b_p, b_v;
  // H and A_eq are fixed by the constructor (BuildQp); only b_eq moves: hot start without comparing matrices.
  status_ = qp.Solve(QpDataChange::kVectorsOnly);
  if (status_ == QpStatus::kOptimal) {
    terminal_relaxed_ = false;
    StorePlan(qp.x(), p_z, pdot_z, dt);
  } else if (status_ == QpStatus::kInfeasible && soft_qp_) {
    soft_qp_->b_eq << b_p, b_v;
    status_ = soft_qp_->Solve(QpDataChange::kVectorsOnly);
    if (status_ == QpStatus::kOptimal) {
      terminal_relaxed_ = true;
      StorePlan(soft_qp_->x(), p_z, pdot_z, dt);
    }
  }
  return status_;
}

void VerticalComMpc::StorePlan(const Eigen::VectorXd& x, double p_z, double pdot_z, double dt) {
  const int N = params_.horizon_steps;
  u_ = x.head(N);
  dt_ = dt;
  p_[0] = p_z;
  v_[0] = pdot_z;
  for (int k = 0; k < N; ++k) {
    p_[k + 1] = p_[k] + dt * v_[k] + 0.5 * dt * dt * u_[k];
    v_[k + 1] = v_[k] + dt * u_[k];
  }
  has_plan_ = true;
}

Eigen::Vector3d VerticalComMpc::EvaluatePlan(double p0, double v0, const Eigen::Ref<const Eigen::VectorXd>& u,
                                             double dt, double s) {
  double p = p0, v = v0;
  if (s <= 0) return Eigen::Vector3d(p, v, u.size() > 0 ? u[0] : 0.0);
  const int N = static_cast<int>(u.size());
  int k = 0;
  for (; k < N && s >= dt; ++k, s -= dt) {
    p += dt * v + 0.5 * dt * dt * u[k];
    v += dt * u[k];
  }
  const double a = k < N ? u[k] : 0.0;
  return Eigen::Vector3d(p + s * v + 0.5 * s * s * a, v + s * a, a);
}

}  // namespace rome
