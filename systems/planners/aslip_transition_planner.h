#pragma once
// AslipTransitionPlanner: the transitional footed-aSLIP NLP of the walking paper, Eq. (9)-(10) (spec §3.2), by
// trapezoidal direct collocation on Ipopt. Offline: solved once per transition (standing → walking, gait A → B).
//
// Exactly two domains, DSP then SSP, with free durations T_DSP ∈ [0.1, 1.0] s and T_SSP ∈ [0.3, 0.6] s (spec [R]).
// Legs keep their labels (0 = left, 1 = right). State [x, z, ẋ, ż, L_L, L_R, L̇_L, L̇_R], input
// [L̈_L, L̈_R, u_L, u_R] (u the ankle pitch torques). One leg (`lifting_leg`) lifts at the end of the DSP.
//   Cost, Eq. (9):  Σ (dt/2)(L̈_L² + L̈_R² + (u_L/u_s)² + (u_R/u_s)²), u_s = 100 N m (spec [R] scaling).
//   Constraints:   the initial and final states are fixed (the start and the end of the motion [P]);
//                  Eq. (10) ZMP −L_h G_z ≤ u ≤ L_t G_z and |u| ≤ u_max per leg on the ground and node; u = 0 in the
//                  air; F ≥ 0, friction, spring range and the periodic NLP's bounds as in AslipPeriodicGaitPlanner;
//                  lift-off: the lifting leg's vertical GRF G_z = 0 at the last DSP node; optionally u = 0 at the
//                  last node (zero_final_ankle_torque).
// The final state is normally a periodic gait's pre-impact state (end of its SSP), so touchdown (s = 0) holds there.
//
// Option `lateral` (ours; the paper's remark after Eq. (15): the two transition problems "could be merged"): the
// state gains the lateral mass position and velocity [y, ẏ] (rows 8, 9) and the input the ankle roll torques
// [u_Lx, u_Rx] (entries 4, 5), with the lateral flow of the point mass on its legs,
//   ÿ = Σ_i (G_iz (y − y_i) + u_ix) / (m z)   (u_x = −G_z y_cop, spec §2.3),
// the lateral ZMP rows −W1 G_z ≤ u_x ≤ W2 G_z of Eq. (14) per leg on the ground, u_x = 0 in the air, and
// (u_x/u_s)² in the cost. The sagittal plan's vertical force split is then one the lateral motion can realise: the
// paper's separate footed H-LIP moves y by ÿ = Σ u/(m z0) in DSP whatever the split, and a split of 85/15 for
// 0.5 s (a push-off from a rear foot) has no lateral motion within a sole of ±3 cm.
#include <cstdint>

#include <Eigen/Core>

#include "solvers/collocation/direct_collocation.h"
#include "systems/planners/aslip_periodic_gait_planner.h"

namespace rome {

struct AslipTransitionParams {
  AslipPeriodicGaitParams bounds{};  ///< model, bounds, N, μ, tolerances (shared with the periodic NLP)
  double min_dsp_duration = 0.1, max_dsp_duration = 1.0;  ///< [s] (spec [R])
  double min_ssp_duration = 0.3, max_ssp_duration = 0.6;  ///< [s] (spec [R])
  double max_ankle_torque = 150.0;                        ///< [N m] u_y,max, ankle pitch limit (spec §1.1 [R])
  double torque_cost_scale = 100.0;                       ///< [N m] u_s in Eq. (9) (spec [R])
  /// u = 0 at the last SSP node (ours): the transition then joins a point-foot periodic gait without a jump in the
  /// ground reaction (the state is continuous there; the torque would not be).
  bool zero_final_ankle_torque = true;
  /// [N m] |u| bound of the stance ankle during the SSP (ours; default: max_ankle_torque). 0 makes the SSP point-foot
  /// like the periodic gait's, leaving the whole sole to the full-order robot's swing-leg momentum.
  double max_ssp_ankle_torque = -1.0;
  /// [-] the stance (non-lifting) leg's vertical GRF stays ≥ this fraction of m g over the DSP (ours; 0: only ≥ 0).
  /// Without it the plan may unload the stance foot to 0 mid-DSP, where the walking plant's lift-off guard fires.
  double min_dsp_stance_force_fraction = 0.0;
  /// [-] every leg's vertical GRF stays ≤ this fraction of m g in both domains (ours; 0: no bound). The NLP's cost
  /// (leg accelerations and ankle torques) does not see the robot's knees: unbounded, a gait change asks up to 1.9 m g.
  double max_vertical_force_fraction = 0.0;
  bool lateral = false;                     ///< see the header (ours)
  double foot_width_left_of_ankle = 0.06;   ///< [m] W1 of Eq. (14) (lateral only)
  double foot_width_right_of_ankle = 0.06;  ///< [m] W2 of Eq. (14) (lateral only)
  double max_ankle_roll_torque = 80.0;      ///< [N m] u_x,max (spec §1.1 [R]; lateral only)
};

struct AslipTransitionData {
  Eigen::Matrix<double, 8, 1> initial_state;  ///< at the start of the DSP
  Eigen::Matrix<double, 8, 1> final_state;    ///< at the end of the SSP (pre-impact)
  double left_foot_x = 0.0;                   ///< [m] pivots during the DSP
  double right_foot_x = 0.0;
  int lifting_leg = 1;  ///< 0 = left, 1 = right (spec [R] default: right)
  /// Lateral option only: world y of the feet [m] and the boundary lateral states [y (m), ẏ (m/s)].
  double left_foot_y = 0.125, right_foot_y = -0.125;
  Eigen::Vector2d initial_lateral_state = Eigen::Vector2d::Zero(), final_lateral_state = Eigen::Vector2d::Zero();
  /// Optional initial guess of the states (8 × N per domain) and durations [s], e.g. the source gait's DSP and the
  /// target gait's SSP for a gait change. Empty: straight line from the initial to the final state, mid-range
  /// durations.
  Eigen::MatrixXd dsp_state_guess, ssp_state_guess;
  double dsp_duration_guess = 0.0, ssp_duration_guess = 0.0;
};

struct AslipTransition {
  CollocationResult collocation;  ///< phases 0 = "dsp", 1 = "ssp"
  double max_constraint_violation = 0.0;
  double mean_height = 0.0;  ///< [m] time average of z (the footed H-LIP z0, spec §2.3)
  bool success() const { return collocation.success(); }
  /// With the lateral option the phases' states have 10 rows ([y, ẏ] last) and the inputs 6 ([u_Lx, u_Rx] last).
  /// [G_Lx, G_Lz, G_Rx, G_Rz] (N) at every node of phase p (4 × N), with the ankle torques.
  Eigen::MatrixXd GroundReactions(const ActuatedSpringLoadedInvertedPendulumParams& params,
                                  const AslipTransitionData& data, int phase) const;
  /// [s, from the DSP's start] The first DSP node where the lifting leg's vertical force, after falling below floor_N
  /// at an earlier node, is above floor_N again (a plant that releases the foot at that force would lift it and land it
  /// again in the double support); NaN when it never does.
  double LiftingLegReloadTime(const ActuatedSpringLoadedInvertedPendulumParams& params, const AslipTransitionData& data,
                              double floor_N) const;
};

class AslipTransitionPlanner {
 public:
  explicit AslipTransitionPlanner(AslipTransitionParams params = {});
  const AslipTransitionParams& params() const { return params_; }
  /// Contact of phase p (0 = DSP, 1 = SSP).
  static ActuatedSpringLoadedInvertedPendulumContact PhaseContact(const AslipTransitionData& data, int phase);
  DirectCollocation BuildProblem(const AslipTransitionData& data) const;
  /// Initial guess: data's guess if given, else states linear from the initial to the final state, durations at
  /// mid-range; zero inputs.
  /// With a cache: a stored plan for the same parameters and data is loaded instead (re-checked to 1e-6), and a new
  /// successful plan is stored. A failure that the same problem repeats (local infeasibility, the iteration limit, a
  /// failed restoration or line search; not a time limit) is stored too, and a later Solve of the same problem returns
  /// it without solving (status, iterations and violation as stored, a message naming the cache entry, no phases).
  AslipTransition Solve(const AslipTransitionData& data, const PlanCache* cache = nullptr) const;
  /// Every parameter and every number of the data.
  PlanCacheKey CacheKey(const AslipTransitionData& data) const;

  /// Standing at rest in DSP with both pivots at x = 0 and the mass at height z, each leg carrying m g / 2
  /// (rest lengths by AslipRestLengthForForce).
  static Eigen::Matrix<double, 8, 1> StandingState(const ActuatedSpringLoadedInvertedPendulumParams& params, double z);
  /// Standing at rest in DSP with the pivots at left_foot_x and right_foot_x (a step stance when they differ): the
  /// mass midway between them at height z, both legs equally long and each carrying a vertical m g / 2 (their
  /// horizontal components cancel), rest lengths by AslipRestLengthForForce.
  static Eigen::Matrix<double, 8, 1> StandingState(const ActuatedSpringLoadedInvertedPendulumParams& params, double z,
                                                   double left_foot_x, double right_foot_x);

 private:
  AslipTransitionParams params_;
};

}  // namespace rome
