#pragma once
// What one step of the stepping-stones plan asks of the robot's actuators and of friction on a periodic course (every
// step the same l, h), computed before a run from the robot model and the diagram's parameters, with no simulation.
//
// The periodic plan: the pre-impact posture NLP, Eq. (21), for the step (as the supervisor asks it: COM at ε l and at
// the walking height above the lower foot) gives q_f; on a periodic gait the next step starts from q_f with the legs'
// roles swapped (φ_0 = φ_f, the swing foot at (−l, −h) from the new stance foot). Over the step the COM follows the
// LIP of Eq. (12) horizontally (from the post-impact state of the E* orbit, L⁺ = L_des, Eq. (16)) and the vertical-COM
// plan of Eq. (28) vertically (from ṗ^{z+} = (h/l) ṗ^{x+} to [p_comf^{z,d}, u_des] in T̂_s, Eq. (18), (25)-(27)); the
// torso and swing foot follow Eq. (22)-(24) (SteppingStonesOutputTrajectories, the diagram's swing parameters).
// At each sample time the posture q is the one that puts the stance foot at the origin, the COM at (p^x, p^z), the
// torso at φ and the swing foot on its curve (Newton on these positions); v follows from their velocities. The
// accelerations, torques and the stance force then solve, as one linear system,
//   M(q) q̈ + h(q, v) = B τ + J_stᵀ λ          (the multibody model, multibody_dynamics.h)
//   J_st q̈ + J̇_st v = 0                       (the stance foot stays put)
//   J_y q̈ + J̇_y v = Ÿ_d                        (the outputs of Eq. (19) follow the plan exactly)
// i.e. what the controllers (which track exactly these outputs) would have to apply to follow the plan from the
// planned state. The COM's forward acceleration is not prescribed (no output tracks it; a point foot leaves it to
// the dynamics). Point feet only (AMBER): a line foot adds an ankle and a pitch row the plan does not determine.
// A measurement of the plan, not a feasibility test: the closed loop walks many gaits whose plan needs several times
// the torque limits (in short transients after the impact and before the touchdown) and slips on gaits whose plan
// needs less; no threshold on these numbers separates the two (docs/design-notes.md, "the plan's torque need").

#include <string>
#include <vector>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"

namespace rome {

/// Sampling and tolerances of the plan's inverse dynamics (ours).
struct PlanTorqueNeedParams {
  int samples = 60;               ///< [-] evenly spaced times in the step (t = T̂_s (i + 0.5) / samples)
  double ik_tolerance_m = 1e-10;  ///< [m] largest position residual the posture Newton iteration accepts
  int max_ik_iterations = 50;     ///< [-] Newton iterations per sample
};

/// One planned sample (relative to the stance foot, at the origin of the world frame).
struct PlanInverseDynamicsSample {
  double time_s = 0.0;    ///< [s] after the impact that starts the step
  Eigen::VectorXd q, v;   ///< posture and velocity (nv)
  Eigen::VectorXd vdot;   ///< [rad/s², m/s²] q̈ (nv)
  Eigen::VectorXd tau;    ///< [N m] joint torques, actuator order (nu)
  Eigen::Vector2d force;  ///< [N] stance contact force (x, z) in the world frame
};

struct PlanTorqueNeed {
  double max_torque_ratio = 0.0;         ///< [-] largest |τ_i| / limit_i over the samples and actuators
  int actuator = -1;                     ///< the actuator of max_torque_ratio (model.actuators() index)
  bool on_stance_leg = false;            ///< whether that actuator's joint moves the stance foot
  double torque_Nm = 0.0;                ///< [N m] its |τ| at that sample
  double limit_Nm = 0.0;                 ///< [N m] its limit (robot file)
  double time_of_max_s = 0.0;            ///< [s] after the step's start
  double max_stance_torque_ratio = 0.0;  ///< [-] max_torque_ratio over the stance leg's joints only
  double max_swing_torque_ratio = 0.0;   ///< [-] max_torque_ratio over the other joints
  /// [N m s] ∫ Σ_k max(|τ_k| − limit_k, 0) dt over the step, the stance leg's joints and the others: the torque
  /// impulse the plan asks beyond the limits (a short spike asks little, a long saturation much).
  double stance_excess_impulse_Nms = 0.0;
  double swing_excess_impulse_Nms = 0.0;
  double stance_over_limit_fraction = 0.0;  ///< [-] fraction of the step with some stance joint over its limit
  double max_friction_ratio = 0.0;          ///< [-] largest |F_x| / F_z of the stance foot (infinity if F_z <= 0)
  double min_normal_force_N = 0.0;          ///< [N] smallest F_z
  double step_duration_s = 0.0;             ///< [s] T̂_s
  double mean_speed_mps = 0.0;              ///< [m/s] l / T̂_s
};

/// The plan's inverse dynamics (see the top of this file) on periodic steps (step_length_m, step_height_m) with the
/// diagram's parameters `params` (E*, ε, the posture NLP, the MPC and the swing curve; stones stone_length_m long, for
/// the swing's clearance over the stance stone when params leave it to the terrain). Fills `samples_out` if given.
/// Throws std::invalid_argument naming the value if l <= 0, the robot has no point feet named left_foot/right_foot,
/// the posture NLP fails, the plan is not finite, the MPC's QP fails or a posture is not found.
PlanTorqueNeed CalcPeriodicPlanTorqueNeed(const MultibodyModel& model, double step_length_m, double step_height_m,
                                          double stone_length_m, const SteppingStonesDiagramParams& params,
                                          const PlanTorqueNeedParams& need_params = {},
                                          std::vector<PlanInverseDynamicsSample>* samples_out = nullptr);

}  // namespace rome
