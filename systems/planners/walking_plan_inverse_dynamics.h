#pragma once
// Inverse dynamics of a walking plan in single support (ours; not in the walking paper): the joint torques and the
// stance sole's wrench that the robot needs to follow the plan's kinematic replay, so a gait that asks more than the
// actuators have, or more friction, CoP travel or torsion than its sole can give, is known before the run.
//
// The motion is ReplayWalkingPlan's (centroidal_momentum_compensation.h): at t_k = k h the COM on the plan (with its
// COM correction, if any), the pelvis level with zero yaw, each foot flat on its foothold or its swing trajectory;
// v and q̈ by central differences. At each single-support sample whose neighbours are in the same domain, the
// equations of motion with the stance sole fixed,
//     M(q) q̈ + h(q, v) = B u + J_sᵀ W,     J_s: the 6 × nv frame Jacobian of the sole point below the stance ankle,
// are square in the 12 torques u and the stance wrench W = [moment; force] (world axes, at the sole point): one LU
// solve per sample. Double support is skipped (18 equations, 24 unknowns: the split between the feet is the
// controller's choice).
//
// Units: s, N m, N. The model must satisfy SolveWalkingPose's requirements, with as many actuators as the floating
// base leaves (nv − 6) and flat contacts on links left_foot and right_foot.
// Home: systems/planners, as WalkingPlan: it judges any WalkingPlan against any MultibodyModel's limits.
#include <Eigen/Core>

#include <functional>
#include <limits>
#include <string>

#include "systems/multibody/multibody_model.h"
#include "systems/planners/walking_output_reference.h"
#include "systems/planners/walking_plan.h"

namespace rome {

struct WalkingPlanInverseDynamicsParams {
  double sample_period_s = 2e-3;  ///< [s] grid of the replay (ours; as CentroidalMomentumCompensationParams)
  /// [s] samples after this time are skipped (the replay still covers the whole plan): the end of the run, when the
  /// plan goes on past it (infinity: the whole plan)
  double end_time_s = std::numeric_limits<double>::infinity();
  /// also visit the double-support samples (their q, v, q̈ only: u and wrench are NaN; e.g. for joint limits)
  bool visit_double_support = false;
};

/// One single-support sample of the plan's inverse dynamics.
struct WalkingPlanInverseDynamicsSample {
  double time_s = 0;
  bool double_support = false;         ///< a double-support sample (visit_double_support): u and wrench are NaN
  int stance_body = -1;                ///< body index of the stance foot (-1 in double support)
  Eigen::VectorXd q, v, qdd;           ///< the replay's pose and its central differences
  Eigen::VectorXd u;                   ///< [N m] actuator torques (actuator order)
  Eigen::Matrix<double, 6, 1> wrench;  ///< [N m; N] the stance sole's wrench at the point below the ankle, world axes
};

struct WalkingPlanTorqueReport {
  Eigen::VectorXd peak_torque_Nm;   ///< [N m] largest |u_j| over the single-support samples, per actuator
  Eigen::VectorXd peak_time_s;      ///< [s] where each peak occurs
  int worst_actuator = -1;          ///< the actuator with the largest peak / torque limit
  double worst_limit_fraction = 0;  ///< [-] that ratio (above 1: the plan asks more than the actuator has)
  double peak_normal_force_N = 0;   ///< [N] largest stance normal force
  /// [-] largest |F_t| / F_n of the stance sole: the friction coefficient the plan needs (above the ground's μ the
  /// stance foot must slip); a sample with F_n <= 0 (the foot would have to pull) counts as infinity
  double peak_friction_ratio = 0;
  double peak_friction_ratio_time_s = 0;  ///< [s] where it occurs
  /// [m] largest CoP offset from the point below the ankle, in x (forward) and y (left) of the world: CoP =
  /// (−M_y / F_n, M_x / F_n); the foot stays flat only while the CoP is inside the sole, whose heel, toe and side
  /// edges are measured from that same point
  Eigen::Vector2d peak_cop_offset_m = Eigen::Vector2d::Zero();
  double peak_yaw_moment_ratio_m = 0;  ///< [m] largest |M_z| / F_n (the torsion the sole must hold by friction)
  int samples = 0;                     ///< single-support samples solved
};

/// Calls `visit` for every single-support sample of `plan` (see the header). `swing` must be the swing-foot parameters
/// the diagram tracks (ankle height set from the robot). Throws std::invalid_argument for a bad parameter or model,
/// std::runtime_error if a replay pose does not converge or the equations of motion are singular at a sample.
void ForEachSingleSupportInverseDynamics(const MultibodyModel& model, const WalkingPlan& plan,
                                         const SwingFootTrajectoryParams& swing,
                                         const WalkingPlanInverseDynamicsParams& params,
                                         const std::function<void(const WalkingPlanInverseDynamicsSample&)>& visit);

/// The peak torques of ForEachSingleSupportInverseDynamics against the model's torque limits.
WalkingPlanTorqueReport CalcWalkingPlanTorques(const MultibodyModel& model, const WalkingPlan& plan,
                                               const SwingFootTrajectoryParams& swing,
                                               const WalkingPlanInverseDynamicsParams& params = {});

}  // namespace rome
