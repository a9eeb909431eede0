#pragma once
// Centroidal angular-momentum compensation of a walking plan's COM reference (ours; not in the walking paper).
//
// The walking paper's ROMs are point masses: they carry no angular momentum, so a plan's COM motion puts the robot's
// centre of pressure at the ROM's pivot only if the robot's centroidal angular momentum H stays constant. The
// exoskeleton's legs are 30 % of its mass; swinging one 0.6 m in 0.4 s gives |Ḣ_y| up to ~130 N m, which the moment
// balance about the COM,
//     Ḣ = (p_cop − p_com) × F,   F = m (p̈_com + g ẑ),
// can only meet by moving the CoP Ḣ_y / F_z ≈ 0.14-0.23 m off the pivot (measured on gait A), beyond the sole.
// The same moment can come from the horizontal ground force instead: shifting the COM reference by δ with
//     δ̈_x = ω² δ_x − Ḣ_y / (m z),   δ̈_y = ω² δ_y + Ḣ_x / (m z),   ω² = F_z / (m z)       (C1)
// keeps the robot's CoP at the ROM's pivot, since then (p_cop − p_rom)·F_z = m z (ω² δ − δ̈) − Ḣ = 0 (x; y alike).
// (C1) is a linear inverted pendulum driven by Ḣ: it is solved as a two-point boundary-value problem over the whole
// plan by central differences on a uniform grid (a tridiagonal system), with δ = 0 at its start (a standing start)
// and the bounded end δ + δ̇/ω = 0 (the unstable mode of (C1) at rest: the plan may end while walking, and δ = 0 there
// bent the last steps measurably). Ḣ(t) is predicted by a kinematic replay of the plan on the robot: at each sample,
// Newton's method puts the COM on the (corrected) reference, the pelvis level with zero yaw, and each ankle on its
// foothold or its swing trajectory with the foot at its swing pitch; v and Ḣ follow by central differences. H depends
// weakly on δ, so replay and solve alternate `iterations` times.
//
// Units: m, s, N m. The model must have a spatial floating base with joints base_yaw, base_pitch, base_roll and flat
// contacts on links left_foot and right_foot.
#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"
#include "systems/planners/walking_output_reference.h"
#include "systems/planners/walking_plan.h"

namespace rome {

struct CentroidalMomentumCompensationParams {
  double sample_period_s = 2e-3;  ///< [s] grid of the replay and of (C1) (ours)
  int iterations = 2;             ///< [-] replay / solve rounds (ours; the second changes δ by < 1 mm on gait A)
};

struct CentroidalMomentumCompensationReport {
  /// [m] the largest CoP offset from the ROM's pivot that the robot's angular momentum asks for in single support,
  /// |Ḣ × ẑ| / F_z, without the correction and with it (the last replay against the last δ)
  double max_cop_shift_uncorrected_m = 0, max_cop_shift_corrected_m = 0;
  double max_correction_m = 0;              ///< [m] largest |δ| (x or y)
  double max_angular_momentum_rate_Nm = 0;  ///< [N m] largest |Ḣ_x|, |Ḣ_y| of the last replay
};

/// (C1) on a uniform grid t_k = k h, k = 0 … N: δ̈ = ω²_k δ − a_k by central differences with δ_0 = 0 and
/// δ_N + (δ_N − δ_{N−1}) / (h ω_N) = 0 (a tridiagonal system, diagonally dominant for ω² ≥ 0). Returns δ (N + 1).
/// Throws std::invalid_argument if the sizes differ or h ≤ 0.
Eigen::VectorXd SolveDrivenInvertedPendulum(const Eigen::VectorXd& omega2, const Eigen::VectorXd& a, double h);

/// A whole-body pose with the COM at `com`, the pelvis level with zero yaw and each foot with zero roll and yaw,
/// pitched toe down by `left_pitch` / `right_pitch` [rad] about the world y axis (0: flat), its ankle (the foot frame's
/// origin) at `left_ankle` / `right_ankle`; Newton from `q_guess` on the 15 coordinates other than the base angles.
/// Throws std::runtime_error naming the robot if it does not converge to 1e-10.
Eigen::VectorXd SolveWalkingPose(const MultibodyModel& model, const Eigen::Vector3d& com,
                                 const Eigen::Vector3d& left_ankle, const Eigen::Vector3d& right_ankle,
                                 const Eigen::VectorXd& q_guess, double left_pitch = 0.0, double right_pitch = 0.0);

/// The kinematic replay of `plan` described above, at t_k = k h, k = 0 … N (N = ⌊end_time / h⌋): column k is the
/// SolveWalkingPose pose with the COM at the plan's plus column k of `com_shift` (2 × (N + 1), x and y; empty: none),
/// each ankle on its foothold or swing trajectory (never below swing.ankle_height_m) at its swing pitch. Throws
/// std::invalid_argument for h outside (0, 0.02] s, an empty plan or a mis-sized com_shift; std::runtime_error if a
/// pose does not converge.
Eigen::MatrixXd ReplayWalkingPlan(const MultibodyModel& model, const WalkingPlan& plan,
                                  const SwingFootTrajectoryParams& swing, double h,
                                  const Eigen::MatrixXd& com_shift = {});

/// Adds the correction δ of (C1) to `plan` (WalkingPlan::SetComCorrection). `swing` must be the swing-foot
/// parameters the diagram tracks (their ankle height set from the robot). Throws std::invalid_argument for a bad
/// parameter, std::runtime_error if a replay pose does not converge.
CentroidalMomentumCompensationReport CompensateCentroidalMomentum(
    const MultibodyModel& model, WalkingPlan& plan, const SwingFootTrajectoryParams& swing,
    const CentroidalMomentumCompensationParams& params = {});

}  // namespace rome
