#pragma once
// FootedHlipTransitionPlanner: the lateral transition QP of the walking paper, Eq. (11)-(15), on DenseQpSolver.
// Offline: solved once per transition, after the footed-aSLIP NLP has fixed the durations and the normal forces.
//
// Model (Sec. IV-B, spec §2.3, §3.3): footed H-LIP in a global y (spec [R]), ZOH input u^k on [t_k, t_{k+1}):
//   SSP interval: ÿ = λ² (y − y_stance) + u_stance/(m z0)   →  Y^{k+1} = A_s (Y^k − S) + S + B_s u_stance^k,
//                 S = [y_stance; 0]; the swing foot's torque is held at 0 by its zero normal force (Eq. (14)).
//   DSP interval: ÿ = (u_L + u_R)/(m z0)                    →  Y^{k+1} = A_d Y^k + B_d (u_L^k + u_R^k).
//   A, B: the exact zero-order hold (FootedLinearInvertedPendulumDiscretization; corrects Eq. (12)'s λT → λ²T).
// Eq. (15): min Σ_k (u_L^k² + u_R^k²) over {u_L, u_R, Y} ∈ R^N × R^N × R^{2N}, subject to
//   the dynamics (2(N−1) rows); Y^0 = [y0; ẏ0], Y^{N−1} = [y_f; ẏ_f] (4 rows);
//   Eq. (14) ZMP  −W1 F_i^k ≤ u_i^k ≤ W2 F_i^k per foot and node (2N rows), |u_i^k| ≤ u_max (bounds).
// Sign: u_x = −G_z y_cop (COP relative to the ankle, +y left), so Eq. (14) is y_cop ∈ [−W2, W1] (spec §2.3).
// Option normal_force_pivots (ours, off by default): every interval follows the point mass on its legs with the
// footed-aSLIP's vertical forces F_i held at the interval mean, ÿ = Σ_i F_i (y − y_i)/(m z0) + Σ_i u_i/(m z0), i.e.
// ÿ = a (y − c) + u/(m z0) with a = (F_L + F_R)/(m z0) and c the force-weighted foot position. The paper's DSP row
// ÿ = u/(m z0) leaves out the lateral push of unequally loaded feet, which a standing start in a step stance
// (the rear foot carrying ~7/8 of the weight for 0.5 s) turns into a lateral drift the sole cannot correct.
// With node_heights (ours) the interval's m z is m z_k, z_k the mean of its two nodes' heights, instead of m z0, as
// the transition NLP's own lateral rows do (with z0 wide side-by-side starts are infeasible:
// docs/design-notes.md#walking-footed-hlip-heights).
// Every interval's (a, c, z) is reported with the plan so that it can be re-sampled exactly (WalkingPlan).
// Variables are ordered [u_L^0..u_L^{N−1}, u_R^0..u_R^{N−1}, y^0, ẏ^0, ..., y^{N−1}, ẏ^{N−1}].
#include <string>
#include <vector>

#include <Eigen/Core>

#include "solvers/qp/dense_qp_solver.h"

namespace rome {

struct FootedHlipTransitionParams {
  double mass = 76.0;                       ///< [kg] m (the aSLIP mass, spec §2.3)
  double gravity = 9.81;                    ///< [m/s²]
  double foot_width_left_of_ankle = 0.06;   ///< [m] W1 (robots.md; symmetric foot, spec §2.3 [R])
  double foot_width_right_of_ankle = 0.06;  ///< [m] W2
  double max_ankle_roll_torque = 80.0;      ///< [N m] u_x,max (spec §1.1 [R] ankle roll limit)
  bool normal_force_pivots = false;         ///< see the header (ours); false: the paper's Eq. (11)-(13)
};

/// One transition: the grid, the footed-aSLIP normal forces on it, the feet and the boundary states.
struct FootedHlipTransitionData {
  Eigen::VectorXd node_times;          ///< N ≥ 2 strictly increasing times [s]
  std::vector<bool> single_support;    ///< N − 1 intervals: true = SSP on `stance_left` foot
  bool stance_left = true;             ///< which foot stands in the SSP intervals
  Eigen::VectorXd left_normal_force;   ///< N vertical GRFs F_L^k [N] (≥ 0)
  Eigen::VectorXd right_normal_force;  ///< N vertical GRFs F_R^k [N] (≥ 0)
  double left_foot_y = 0.125;          ///< [m] world y of the left ankle
  double right_foot_y = -0.125;        ///< [m] world y of the right ankle
  double z0 = 0.9;                     ///< [m] mean footed-aSLIP height over the transition (spec §2.3)
  /// [m] N footed-aSLIP heights at the nodes (ours; checked whenever given, used with normal_force_pivots only; empty:
  /// z0 everywhere). Interval k then
  /// uses z_k = (h_k + h_{k+1})/2 for m z, the height the footed-aSLIP NLP's own lateral rows move the mass on.
  Eigen::VectorXd node_heights;
  Eigen::Vector2d initial_state = Eigen::Vector2d::Zero();  ///< [y0 (m), ẏ0 (m/s)], world
  Eigen::Vector2d final_state = Eigen::Vector2d::Zero();    ///< [y_f, ẏ_f], world
};

struct FootedHlipTransitionPlan {
  QpStatus status = QpStatus::kInvalidInput;
  std::string message;           ///< names the planner and the QP status
  Eigen::VectorXd left_torque;   ///< u_L^k [N m], N
  Eigen::VectorXd right_torque;  ///< u_R^k [N m], N
  Eigen::MatrixXd states;        ///< 2 × N, [y; ẏ] world
  /// Per interval k (N − 1): ÿ = a_k (y − c_k) + u_k/(m z_k) with u_k the torque driving it (u_stance in the paper's
  /// SSP, u_L + u_R otherwise). a_k [1/s²] = λ² (paper SSP), 0 (paper DSP) or (F_L + F_R)/(m z_k); c_k [m] world.
  Eigen::VectorXd interval_stiffness;
  Eigen::VectorXd interval_pivot;
  Eigen::VectorXd interval_height;  ///< [m] z of each interval's m z (z0, or the node heights' mean)
  double cost = 0.0;                ///< Σ (u_L² + u_R²) [N² m²]
  int iterations = 0;
  bool success() const { return status == QpStatus::kOptimal; }
};

class FootedHlipTransitionPlanner {
 public:
  /// Throws std::invalid_argument naming the parameter unless mass, gravity, W1, W2, u_max are > 0.
  explicit FootedHlipTransitionPlanner(FootedHlipTransitionParams params = {});
  const FootedHlipTransitionParams& params() const { return params_; }
  /// Solves Eq. (15). Throws std::invalid_argument naming the field for inconsistent sizes, non-increasing times or
  /// negative forces; an infeasible transition returns status kInfeasible with a message.
  FootedHlipTransitionPlan Solve(const FootedHlipTransitionData& data) const;

 private:
  FootedHlipTransitionParams params_;
};

}  // namespace rome
