#pragma once
// VerticalComMpc: the vertical-COM planner of the stepping-stones paper, Eq. (28), pure math.
//
//   min_{u_0..u_{N−1}}  Σ_k (u_k)²                                       (u = p̈_com^z, m/s²)
//   s.t.  z_{k+1} = A z_k + B u_k,  A = [1 dt; 0 1], B = [dt²/2; dt]     (double integrator, exact ZOH)
//         u_k >= −g                                                       (contact: the leg can only push)
//         u_k <= a_max                                                    (ours, off by default: how hard it can)
//         z_0 = [p^z(t), ṗ^z(t)],  z_N = z⁻ = [p_comf^{z,d}, u_des]      (boundary conditions)
//   with dt = T̂_s / N and T̂_s the predicted time to impact, Eq. (27).
// The paper writes z_1 = z_0, z_N = z⁻ and dt = T̂_s/N; we use N intervals z_0 → z_N so that the horizon is
// exactly T̂_s. The states are eliminated (condensed QP, N variables):
//   p_N = p_0 + T ṗ_0 + Σ_k dt² (N − k − ½) u_k,   ṗ_N = ṗ_0 + Σ_k dt u_k.
// TerminalCondition::kEquality imposes z_N = z⁻ exactly (Eq. (28)); kWeightedCost replaces it by
// ρ_p (p_N − p^f)² / dt⁴ + ρ_v (ṗ_N − u_des)² / dt² in the cost (dt = T/N), which is always feasible. The weights
// ρ are dimensionless; dividing the terminal errors by dt² and dt makes them accelerations, like the inputs, so
// the relaxation is equally tight for every horizon T (a constant weight would loosen as T → 0). It is solved
// with two slack variables s = scaled terminal errors (N + 2 variables, diagonal H = diag(2, …, 2, 2ρ_p, 2ρ_v),
// condition number ρ), not as a dense rank-2 penalty (condition number ~ρ N², which the QP rejects).
// Relaxation (ours): with kEquality, when the equality QP is infeasible (e.g. z⁻ needs ṗ to fall faster than g
// allows, or lies exactly on that boundary at the end of a free-fall arc, where rounding decides), and
// relax_terminal_on_infeasible is set, the weighted-cost QP is solved instead and terminal_relaxed() is true.
// The equality rows are scaled by 1/dt² and 1/dt so that their coefficients are O(N).
//
// Memory: the constructor sizes the QP workspace; Solve() performs no heap allocation. H and A_eq never change
// after construction, so the QP is hot-started (rome::DenseQpSolver keeps the factorization of its working set;
// Solve(QpDataChange::kVectorsOnly), verified by the solver) when params.qp.warm_start and hot_start are set.

#include <limits>
#include <memory>

#include <Eigen/Core>

#include "solvers/qp/dense_qp_solver.h"

namespace rome {

struct VerticalComMpcParams {
  enum class TerminalCondition { kEquality, kWeightedCost };
  /// [-] N, number of intervals. The paper leaves N to the user (Algorithm 1); ours: 20.
  int horizon_steps = 20;
  double gravity = 9.81;  ///< [m/s²] the contact constraint u_k >= −g
  /// [m/s²] a_max, the largest upward COM acceleration the plan may ask for (u_k <= a_max). Ours; +inf = the
  /// paper (no bound). The stance leg's push is limited by its motors: a plan that needs more than they give (a
  /// COM far below its pre-impact height late in the step) is followed at the limit by the robot, which then
  /// reaches the impact rising fast instead of at u_des. With the bound such a target is infeasible and the
  /// relaxed QP below trades the terminal errors (terminal_position_weight, terminal_velocity_weight) instead.
  double max_acceleration = std::numeric_limits<double>::infinity();
  TerminalCondition terminal_condition = TerminalCondition::kEquality;  ///< Paper: equality (Eq. (28))
  double terminal_position_weight = 1e6;  ///< [-] ρ_p > 0, for kWeightedCost and the relaxation (ours)
  double terminal_velocity_weight = 1e6;  ///< [-] ρ_v > 0, for kWeightedCost and the relaxation (ours)
  /// [s] The horizon T̂_s is raised to at least this (dt = max(T̂_s, min)/N), so that the plan stays finite as
  /// the impact approaches (ours).
  double min_horizon_s = 0.01;
  /// With kEquality: solve the kWeightedCost QP when the equality QP is infeasible (ours; see above).
  bool relax_terminal_on_infeasible = true;
  QpSettings qp{};  ///< Settings of the dense QP solver.
};

class VerticalComMpc {
 public:
  /// Sizes the QP. Throws std::invalid_argument naming the parameter if N < 1, g <= 0, weights < 0 or
  /// min_horizon_s <= 0.
  explicit VerticalComMpc(VerticalComMpcParams params = {});

  /// Solves Eq. (28) from the measured [p^z, ṗ^z] to [p_final, v_final] in `horizon_s` (clamped below by
  /// min_horizon_s). Returns the QP status; non-finite data returns kInvalidInput. On success the plan below is
  /// updated; otherwise it keeps the previous plan. Allocation-free.
  QpStatus Solve(double p_z, double pdot_z, double p_final, double v_final, double horizon_s);

  const VerticalComMpcParams& params() const { return params_; }
  int horizon_steps() const { return params_.horizon_steps; }
  QpStatus status() const { return status_; }
  /// True if the last successful solve used the weighted terminal cost because the equality was infeasible.
  bool terminal_relaxed() const { return terminal_relaxed_; }
  /// The last successful plan: inputs u_0..u_{N−1} [m/s²], interval dt [s], and the states z_0..z_N.
  const Eigen::VectorXd& inputs() const { return u_; }
  double first_input() const { return u_[0]; }
  double dt() const { return dt_; }
  const Eigen::VectorXd& positions() const { return p_; }   ///< N+1 [m]
  const Eigen::VectorXd& velocities() const { return v_; }  ///< N+1 [m/s]
  bool has_plan() const { return has_plan_; }
  /// The QP of the last solve (the relaxed one if terminal_relaxed()). Its first N variables are the inputs; with
  /// slacks (kWeightedCost or relaxed) variables N, N+1 are the scaled terminal errors.
  const DenseQpSolver& qp() const { return terminal_relaxed_ ? *soft_qp_ : *qp_; }

  /// Position, velocity and acceleration of a plan (start state p0, v0, piecewise-constant inputs u over
  /// intervals dt) at time s after its start. Beyond the horizon the plan continues with zero acceleration.
  static Eigen::Vector3d EvaluatePlan(double p0, double v0, const Eigen::Ref<const Eigen::VectorXd>& u, double dt,
                                      double s);

 private:
  VerticalComMpcParams params_;
  void BuildQp(DenseQpSolver* qp, bool with_slacks) const;
  void StorePlan(const Eigen::VectorXd& x, double p_z, double pdot_z, double dt);
  std::unique_ptr<DenseQpSolver> qp_;
  std::unique_ptr<DenseQpSolver> soft_qp_;  // only for kEquality with relax_terminal_on_infeasible
  Eigen::VectorXd u_, p_, v_;
  double dt_ = 0;
  bool has_plan_ = false;
  bool terminal_relaxed_ = false;
  QpStatus status_ = QpStatus::kInvalidInput;
};

}  // namespace rome
