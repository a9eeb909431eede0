#pragma once
// Kernels of the quaternion free-flyer base (free_flyer.h) as ONE 6-DOF joint (Featherstone 2008, Sec. 4.4: a joint
// of motion subspace S of 6 columns), used by multibody_dynamics.cc, multibody_kinematics.cc and contact_dynamics.cc
// when MultibodyWorkspace::free_flyer_as_one_joint() holds.
//
// Body layout of a quaternion model (the loader's): bodies 0..4 are massless and posed at the base, body 5 is the
// URDF root link; bodies 0..5 carry v's first six entries. In world axes at O = the base origin (the workspace's
// reference point), with R = R_world_base,
//   S_base = [[0, R]; [R, 0]]   (rows [angular; linear], columns [v_B, w_B]),
// so a spatial vector maps to base twist coordinates by S_base^T [n; f] = [R^T f; R^T n], and the base body's
// acceleration from v̇_base is S_base v̇_base (S_base is fixed in the base: no bias term).
// All functions need ws.SetPositions (and, for the RNEA, ws.SetVelocities) done; no heap allocation.
#include <Eigen/Core>

#include "systems/multibody/multibody_workspace.h"

namespace rome {

inline constexpr int kFreeFlyerRootBody = 5;  ///< the URDF root link's body on a quaternion model

/// Fills ws.M: the joint block by the CRBA over bodies 6.., the base columns S_base^T Ic_i S_i, and the base block
/// S_base^T Ic_root S_base = [[m 1, -[h_B]x]; [h_B]x, I_B]] (m, h_B = m c_B, I_B about the base origin, base axes).
void CalcFreeFlyerMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws);

/// Recursive Newton-Euler over the tree with the base as one joint: tau = M qdd + h (reflected inertia included);
/// qdd == nullptr means qdd = 0 (tau = h). tau has nv entries.
void CalcFreeFlyerRnea(const MultibodyModel& model, MultibodyWorkspace& ws, const double* qdd, double* tau);

/// The base's six columns of the linear velocity Jacobian of a point at r = p - O (world): [R, -[r]x R].
Eigen::Matrix<double, 3, 6> FreeFlyerPointJacobianColumns(const MultibodyWorkspace& ws, const Eigen::Vector3d& r);

}  // namespace rome
