#pragma once
// Unconstrained dynamics of a MultibodyModel:
//   M(q) qdd + h(q, v) = B u + tau_spring(q, v) + tau_ext
//   M = M_rigid (CRBA, Featherstone 2008 Sec. 6.2) + diag(reflected rotor inertia)
//   h = C(q, v) v + g(q)   (RNEA with qdd = 0, gravity (0, 0, -9.81) m/s^2)
//   tau_spring = -K (q - q_rest) - D v   (sidecar springs; restoring, right-hand side)
// Forward dynamics uses Bullet's articulated-body algorithm; Bullet knows nothing of the
// reflected inertia, which is added exactly through the Woodbury identity
//   (M_r + P D P^T)^-1 = M_r^-1 - M_r^-1 P (D^-1 + P^T M_r^-1 P)^-1 P^T M_r^-1
// using one Bullet M_r^-1 application per armature dof (cached per q).
// All functions write into the workspace or into caller-provided outputs; no heap allocation.
#include <Eigen/Core>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {

// Returns ws.M (valid until the next call with a different q).
const Eigen::MatrixXd& CalcMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q);
// Returns ws.h = C(q, v) v + g(q).
const Eigen::VectorXd& CalcBiasForces(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                      const VectorRef& v);
// Returns ws.tau_spring = -K (q - rest) - D v.
const Eigen::VectorXd& CalcSpringTorques(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         const VectorRef& v);
// Inverse dynamics: tau = M qdd + h - tau_spring (the generalized force that produces qdd).
void CalcInverseDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                         const VectorRef& qdd, Eigen::Ref<Eigen::VectorXd> tau);

// Inverse dynamics of the rigid tree by the recursive Newton-Euler algorithm (Featherstone 2008, Table 5.1), O(n):
// tau = M(q) qdd + h(q, v), reflected rotor inertia included, springs not (CalcInverseDynamics subtracts them).
void CalcRnea(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              const VectorRef& qdd, Eigen::Ref<Eigen::VectorXd> tau);

// out = M(q)^-1 f, via Bullet's calcAccelerationDeltasMultiDof (+ armature correction); on a quaternion base, through
// SolveMassMatrix (Bullet does not model it).
void ApplyInverseMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& f,
                            Eigen::Ref<Eigen::VectorXd> out);
// Same product through the tree-sparse L^T D L factor of the CRBA mass matrix (Featherstone's
// LTDL; dense Cholesky if the dof order is not parent-first). Faster for many columns.
void SolveMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                     Eigen::Ref<Eigen::MatrixXd> inout);
// Computes (once per q) the factor used by SolveMassMatrix: ws.L_packed and ws.D (M = L^T D L) when
// ws.use_tree_factor, else the dense Cholesky ws.M_llt. Throws std::runtime_error if M is not
// positive definite.
void FactorMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q);
// inout <- L^-T inout with the tree factor (requires FactorMassMatrix and ws.use_tree_factor).
// Then J M^-1 J^T = Y^T D^-1 Y with Y = L^-T J^T.
void SolveMassMatrixTransposeFactor(const MultibodyWorkspace& ws, Eigen::Ref<Eigen::MatrixXd> inout);
// rows <- rows L^-1 (the transpose of L^-T rows^T) with the tree factor, for a few rows of length nv: each step is an
// axpy over the rows (requires FactorMassMatrix and ws.use_tree_factor).
void SolveMassMatrixFactorRows(const MultibodyWorkspace& ws, Eigen::Ref<Eigen::MatrixXd> rows);

// Forward dynamics with Bullet's ABA: qdd = M^-1 (B u + tau_spring + tau_ext - h); on a quaternion base, the CRBA's M
// and its tree factor (SolveMassMatrix).
// tau_ext may be empty (size 0) for none.
void CalcForwardDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                         const VectorRef& u, const VectorRef& tau_ext, Eigen::Ref<Eigen::VectorXd> qdd);

}  // namespace rome
