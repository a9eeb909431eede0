#pragma once
// The quaternion free-flyer base: its configuration, its velocity and the maps between them.
//
// Convention (the one place it is stated; MultibodyModel, the workspace and the tests follow it):
//   q_base = [p; quat]  (7 numbers): p = the base (URDF root link) origin in world coordinates, m;
//                       quat = (w, x, y, z), the unit quaternion of R_world_base (Drake's order; Pinocchio stores
//                       x, y, z, w).
//   v_base = [v_B; w_B] (6 numbers): the base twist in BASE coordinates (Pinocchio's "local" free-flyer convention):
//                       v_B = R_world_base^T dp/dt, m/s; w_B = the angular velocity in base axes, rad/s.
//                       Linear first, as the Euler base's [x, y, z, yaw, pitch, roll] rates (a frame Jacobian's rows
//                       stay [angular; linear]).
//   dp/dt = R v_B,  dquat/dt = 1/2 quat (x) (0, w_B)                      (MapFreeFlyerVelocityToQDot)
// Integration and differences use the exponential and logarithm of SE(3) (not of R3 x SO(3)): Integrate moves the
// base with the constant body twist xi = v dt for unit time,
//   (R, p) <- (R, p) Exp(xi):  R <- R Exp(w),  p <- p + R V(w) v,   V(w) = I + a [w]x + b [w]x^2,
//   a = (1 - cos t) / t^2, b = (t - sin t) / t^3, t = |w|,
// which is the exact flow of a constant body twist, and Difference is its inverse (the shortest rotation, |w| <= pi):
//   xi = Log((R0, p0)^-1 (R1, p1)):  w = Log(R0^T R1),  v = V(w)^-1 R0^T (p1 - p0).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rome {

using Vector7d = Eigen::Matrix<double, 7, 1>;
using FreeFlyerTwist = Eigen::Matrix<double, 6, 1>;

/// The unit quaternion stored in q_base (entries 3..6, w x y z) as R_world_base, normalised. Returns false (and leaves
/// *R unchanged) if its norm is not finite and positive.
bool FreeFlyerRotation(const Vector7d& q_base, Eigen::Quaterniond* R);
/// (R, p) Exp(xi), xi = [v; w] in base coordinates. The quaternion is normalised on input and output.
Vector7d FreeFlyerIntegrate(const Vector7d& q_base, const FreeFlyerTwist& xi);
/// Log((R0, p0)^-1 (R1, p1)): the body twist that FreeFlyerIntegrate turns q0 into q1 with.
FreeFlyerTwist FreeFlyerDifference(const Vector7d& q0, const Vector7d& q1);
/// dq_base/dt = G(q) v_base (7 numbers): [R v_B; 1/2 quat (x) (0, w_B)], R of the normalised quaternion; the quaternion
/// part is linear in quat, so an integrator needs no unit quaternion at its stages (the exact flow keeps |quat|).
Vector7d MapFreeFlyerVelocityToQDot(const Vector7d& q_base, const FreeFlyerTwist& v_base);
/// The free-flyer configuration of a ZYX-Euler base pose [x, y, z, yaw, pitch, roll] (R = Rz Ry Rx), with w >= 0.
Vector7d FreeFlyerFromEuler(const Eigen::Matrix<double, 6, 1>& q_euler);

/// SO(3) exponential Exp(w) as a unit quaternion, and its inverse (|result| <= pi).
Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& w);
Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q);
/// V(w) of the SE(3) exponential (above) applied to u, and V(w)^-1 u.
Eigen::Vector3d Se3LeftJacobianTimes(const Eigen::Vector3d& w, const Eigen::Vector3d& u);
Eigen::Vector3d Se3LeftJacobianInverseTimes(const Eigen::Vector3d& w, const Eigen::Vector3d& u);

}  // namespace rome
