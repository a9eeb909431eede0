#pragma once
// Kinematic quantities of a MultibodyModel (all in world coordinates, SI units).
//
// Every function takes the model, the workspace and the state it needs; the workspace caches
// the state by value, so asking for several quantities at the same (q, v) costs one
// kinematics pass (Bullet forward kinematics + one tree sweep). No heap allocation.
//
// Conventions:
//   frame Jacobian rows are [angular; linear] (Drake order): [omega; v_p] = J_frame(q) v
//   point Jacobian: v_p = J_point(q) v  (3 x nv)
//   *JdotQdot: the acceleration with qdd = 0, i.e. d/dt(J) v:  a_p = J qdd + Jdot_qdot
//   centroidal momentum h_G = [k_G; l] = A_G(q) v (angular about the COM first, then linear),
//   d/dt h_G = A_G qdd + Adot_G_v  (Orin, Goswami & Lee 2013).
// "body" is a body index (MultibodyModel::BodyIndex("link")), "p_link" a point in that link's
// URDF frame.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

using VectorRef = Eigen::Ref<const Eigen::VectorXd>;

// Pose of the link frame in the world.
Eigen::Isometry3d CalcLinkPose(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body);
Eigen::Vector3d CalcPointPosition(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body,
                                  const Eigen::Vector3d& p_link);
// [omega; v_p] of the frame attached to the link at p_link.
Vector6d CalcFrameVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           int body, const Eigen::Vector3d& p_link);
Eigen::Vector3d CalcPointVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                  const VectorRef& v, int body, const Eigen::Vector3d& p_link);
// J is 6 x nv (frame) or 3 x nv (point); overwritten.
void CalcFrameJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body,
                       const Eigen::Vector3d& p_link, Eigen::Ref<Eigen::MatrixXd> J);
void CalcPointJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body,
                       const Eigen::Vector3d& p_link, Eigen::Ref<Eigen::MatrixXd> J);
Vector6d CalcFrameJdotQdot(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           int body, const Eigen::Vector3d& p_link);
Eigen::Vector3d CalcPointJdotQdot(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                  const VectorRef& v, int body, const Eigen::Vector3d& p_link);

// Centre of mass.
Eigen::Vector3d CalcComPosition(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q);
Eigen::Vector3d CalcComVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v);
void CalcComJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                     Eigen::Ref<Eigen::MatrixXd> J_com);  // 3 x nv
Eigen::Vector3d CalcComJdotQdot(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v);

// Centroidal momentum (6 x nv matrix A_G, rows [angular about COM; linear]).
void CalcCentroidalMomentumMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                  Eigen::Ref<Eigen::MatrixXd> A_G);
Vector6d CalcCentroidalMomentum(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v);
Vector6d CalcCentroidalMomentumBias(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                    const VectorRef& v);  // Adot_G v

// Energies: kinetic (rigid bodies + reflected rotor inertia 1/2 I_r v^2), potential
// (gravity + spring 1/2 k (q - rest)^2).
double CalcKineticEnergy(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v);
double CalcPotentialEnergy(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q);

}  // namespace rome
