#pragma once
// Whether the walking diagram (walking_diagram.h) can use a robot, checked before any plan is built: a robot it cannot
// use is bad input (exit 1 in the walking example), not a failed run. And whether the robot can follow a built plan
// (the feasibility check, ours; walking issue 39 §4), checked before any simulation step:
//   * torques: the plan's single-support inverse dynamics (ForEachSingleSupportInverseDynamics: the kinematic replay
//     on a sample_period_s grid, q̇ and q̈ by central differences, the stance sole welded) against each actuator's
//     limit (the URDF effort or the sidecar's torque_limit_Nm), |u_j| ≤ (1 − torque_margin) limit_j;
//   * the stance sole as a RIGID flat sole on its four corners (the robot file's corner points; the sole rectangle
//     they span), its wrench taken about the sole's centre in the foot frame: F_z ≥ min_normal_force_N, |F_t| ≤ μ F_z
//     (μ: the contact's friction_coefficient unless set), the CoP inside the sole less cop_margin_m, and the yaw moment
//     within the contact wrench cone of the four corners with a friction pyramid μ' per corner (Caron, Pham and
//     Nakamura, ICRA 2015, closed form; μ' = μ/√2 with inscribe_pyramid, inside each corner's cone):
//       −μ'(X+Y) F_z + |Y F_x − μ' τ_x| + |X F_y − μ' τ_y| ≤ τ_z ≤ μ'(X+Y) F_z − |Y F_x + μ' τ_x| − |X F_y + μ' τ_y|;
//   * joint position limits: every replay sample (single and double support) within the model's limits less
//     joint_limit_margin_rad.
// Double support is checked for joint limits only (its force split between the feet is the controller's choice).
// Units: s, m, N, N m, rad.

#include <functional>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"
#include "systems/planners/walking_plan.h"

namespace rome {

struct WalkingDiagramParams;

/// Throws std::invalid_argument naming the robot, what it has and what the diagram needs, unless `model` has a spatial
/// floating base (the plans are 3D), flat contacts named "left_foot" and "right_foot" (the footed H-LIP and the force
/// matching need a sole; SoleOf checks the ankle over it) and actuators.
void CheckWalkingRobot(const MultibodyModel& model);

/// Tolerances of the feasibility check (all ours).
struct WalkingFeasibilityParams {
  double sample_period_s = 2e-3;  ///< [s] replay grid (as the momentum compensation's): ≥ 174 samples per 0.35 s SSP
  double torque_margin = 0.0;     ///< [-] |u_j| ≤ (1 − this) of its limit; in [0, 0.5]
  double friction_coefficient = -1.0;  ///< [-] μ of the ground; < 0: each foot contact's friction_coefficient
  bool inscribe_pyramid = true;        ///< the corners' pyramid |f_x|, |f_y| ≤ μ/√2 f_z, inside each corner's cone
  double cop_margin_m = 0.0;           ///< [m] the CoP keeps this far inside the sole's edges; in [0, 0.02]
  double min_normal_force_N = 0.0;     ///< [N] the stance sole pushes at least this much
  double joint_limit_margin_rad = 0.0;  ///< [rad] joints keep this far inside their limits; in [0, 0.1]
  /// Whether a sole or joint-limit finding makes the plan infeasible (`problem`); off, it is only reported (ours: on
  /// 2026-12-06 every plan of the gait range asks more torsion than a rigid sole holds and replays the ankles beyond
  /// their URDF limits, docs/design-notes.md, so the walking example refuses on the torques by default).
  bool enforce_sole_wrench = true;
  bool enforce_joint_limits = true;
  double start_time_s = 0.0;  ///< [s] samples before this time are not checked (≥ 0)
  /// Throws std::invalid_argument "WalkingFeasibilityParams: FIELD = VALUE is outside RANGE" for the first bad field.
  void Validate() const;
};

/// A flat sole's rectangle about its centre (foot frame) and its ground friction.
struct SoleRectangle {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< [m] the corners' centroid, body frame
  double half_length_m = 0, half_width_m = 0;        ///< [m] X, Y of the closed form
  double friction_coefficient = 1.0;                 ///< [-] μ
};
/// The sole of flat contact `contact` of `model` (its corners' bounding rectangle). Throws std::invalid_argument naming
/// the contact if it is not flat.
SoleRectangle SoleRectangleOf(const MultibodyModel& model, const std::string& contact);

/// What a rigid sole cannot give for wrench [τ; f] (about the sole's centre, foot frame, N m and N): "" if it can,
/// else one clause such as "needs a yaw moment of 0.29 m F_z (the rigid sole holds 0.05 m F_z there)". The first of:
/// normal force, friction, CoP, yaw moment. `excess` (if given) is set to how far past its bound the wrench is, as a
/// fraction of the bound's scale (0 when it fits).
std::string SoleWrenchProblem(const SoleRectangle& sole, const Eigen::Matrix<double, 6, 1>& wrench,
                              const WalkingFeasibilityParams& params, double* excess = nullptr);

struct WalkingFeasibilityReport {
  /// "" when the plan fits; else one line: "gait L,T_SSP,T_DSP,W: the left knee needs 326 N m (limit 300 N m) at
  /// 0.21 s of single support (t = 3.46 s)": the enforced kinds' worst findings, torque first, then the sole, then
  /// the joint limits ("; also ..." for the others).
  std::string problem;
  /// Each kind's worst finding in the same words ("" when none), whether enforced or not.
  std::string torque_problem, sole_problem, joint_limit_problem;
  Eigen::VectorXd peak_torque_Nm;  ///< [N m] largest |u_j| per actuator over the single-support samples
  Eigen::VectorXd peak_time_s;     ///< [s] where
  double peak_yaw_ratio_m = 0;     ///< [m] largest |τ_z| / F_z about the sole's centre
  int single_support_samples = 0, samples = 0;
  double solve_s = 0;  ///< [s] wall time of the check
};

/// Checks `plan` (pass the diagram's plan, WalkingDiagram::plan, with its COM correction) on `model` up to
/// `end_time_s` as described in the header; `diagram` gives the swing-foot settings. Throws std::invalid_argument for
/// bad params, std::runtime_error if a replay pose does not converge.
WalkingFeasibilityReport CheckWalkingPlanFeasibility(const MultibodyModel& model, const WalkingPlan& plan,
                                                     const WalkingDiagramParams& diagram,
                                                     double end_time_s = std::numeric_limits<double>::infinity(),
                                                     const WalkingFeasibilityParams& params = {});

/// A StandToWalkParams::change_check for `model`: the plan's COM corrected as BuildWalkingDiagram(model, plan,
/// diagram) corrects it, then CheckWalkingPlanFeasibility from the transition's start to its end with `params` (by
/// default the torques only, as the walking example's --feasibility torque); throws std::runtime_error with the
/// report's problem when it refuses the transition. Throws std::invalid_argument for a null model or bad params.
std::function<void(const WalkingPlan&, double, double)> WalkingChangeFeasibilityCheck(
    std::shared_ptr<const MultibodyModel> model, const WalkingDiagramParams& diagram,
    WalkingFeasibilityParams params = {.enforce_sole_wrench = false, .enforce_joint_limits = false});

/// "gait L,T_SSP,T_DSP,W" of the plan's segment at time t (a periodic step), "the transition into gait ..." (a footed
/// H-LIP transition), or "standing" (the first double support); read off the plan's footholds and durations.
std::string WalkingPlanPhaseName(const WalkingPlan& plan, double t);

}  // namespace rome
