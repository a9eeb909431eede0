#pragma once
// Cassie's virtual leg and its stiffness, Eq. (4)-(13) of the hopping paper (Xiong & Ames, IROS 2018), computed on
// our model robots/cassie (cassie.urdf + cassie.rome.json) with systems/multibody.
//
// API summary (stable; used by the hopping controllers and the `identified` variant of the spring-mass ROM):
//   CassieVirtualLeg leg(model, "left");         one leg of a loaded Cassie MultibodyModel
//   leg.TarsusAngle(q_knee)                       tarsus from the achilles-rod closure at zero spring deflection
//   leg.Length(q_knee), leg.LengthJacobian(q_knee)   Eq. (13): L(q_knee) = L_r(q_knee, 0, 0) [m], dL/dq_knee [m/rad]
//   leg.KneeAngle(L)                              inverse of Eq. (13) (Newton) [rad]
//   leg.RealLength(q)                             L_r(q): hip-pitch joint -> toe joint distance at a full q [m]
//   leg.Stiffness(q_knee), leg.Damping(q_knee)    Eq. (12) along the leg, tangential displacement blocked [N/m, N s/m]
//   IdentifyCassieLegStiffness(leg)               the 4-term regression of footnote 1 -> LegStiffness (+ samples)
//   CassieSpringMassParams(model, variant)        ROM params for Cassie: m = model total mass, 2 legs, K/D variant
//                                                 (kIdentified is what the plant matches: standing-deflection test)
//
// Definitions:
//   L_r(q) = |p_toe − p_hip|, p_hip the hip-pitch joint (origin of the hip-pitch link frame), p_toe the toe
//   (foot-pitch) joint (origin of the foot link frame). Eq. (13): L(q_knee) = L_r at q_shin = q_heel = 0 with the
//   tarsus from the rod closure, so L depends on the knee motor angle only and its Jacobian has one entry.
//   Eq. (8)-(12): q_A = {knee, shin, heel, (toe)}; the passive tarsus is eliminated through the closure h(q) = 0,
//   dq_tarsus = −(∂h/∂q_tarsus)⁻¹ ∂h/∂q_A dq_A, so the reduced Jacobian of p_toe is J_A = J_p,A − J_p,tarsus
//   (∂h/∂q_tarsus)⁻¹ ∂h/∂q_A. K_A = diag(∞, k_shin, k_heel, ∞) (motors rigid; the toe does not move p_toe), so the
//   compliance is C = Σ_{shin, heel} J_j J_jᵀ / k_j (2 × 2 in the leg's sagittal plane) and K_leg = C⁻¹ (Eq. 12).
//   The paper regresses the vertical element of K_leg in stance; we take the element along the leg axis
//   u = (p_toe − p_hip)/L_r, uᵀ K_leg u (force along the leg with the tangential displacement blocked), which is the
//   vertical element when the foot is under the hip (the standing and hopping poses). D(L): the same formula with
//   the spring dampings in place of the stiffnesses ("approximated in the same way", footnote 1).
// Each call poses one leg of the model with the pelvis at the origin, hip roll = yaw = pitch = 0; the result does
// not depend on those. Not thread-safe (one mutable workspace); offline/setup use (the Newton solves allocate
// nothing, but keep it out of the control loop anyway).

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/rom/spring_mass_model.h"

namespace rome {

class CassieVirtualLeg {
 public:
  /// `side` is "left" or "right". Throws std::invalid_argument naming the model and the missing joint, frame,
  /// spring or loop closure ("<side>_knee", "<side>_achilles", ...).
  CassieVirtualLeg(const MultibodyModel& model, std::string side = "left");
  CassieVirtualLeg(const CassieVirtualLeg& other);
  ~CassieVirtualLeg();

  const std::string& side() const { return side_; }
  const MultibodyModel& model() const { return *model_; }
  int knee_index() const { return knee_; }  ///< velocity (= position) index of <side>_knee
  int tarsus_index() const { return tarsus_; }
  int shin_index() const { return shin_; }
  int heel_index() const { return heel_; }

  /// Tarsus angle [rad] closing the achilles rod at q_shin = q_heel = 0. std::runtime_error naming the knee angle
  /// if Newton does not converge (the rod cannot close).
  double TarsusAngle(double q_knee) const;
  /// Eq. (13) [m].
  double Length(double q_knee) const;
  /// dL/dq_knee [m/rad] (the tarsus follows the closure).
  double LengthJacobian(double q_knee) const;
  /// Inverse of Eq. (13): the knee angle with Length(q_knee) = L [rad]; std::domain_error naming L if it is outside
  /// the knee's joint range.
  double KneeAngle(double L) const;
  /// L_r(q) for a full configuration q of the model (springs deflected or not) [m].
  double RealLength(const Eigen::Ref<const Eigen::VectorXd>& q) const;
  /// Eq. (12): along-leg stiffness [N/m] / damping [N s/m] of one leg at zero spring deflection.
  double Stiffness(double q_knee) const;
  double Damping(double q_knee) const;
  /// The leg's 2 × 2 Cartesian stiffness K_leg = C⁻¹ in the sagittal plane, world (x, z) axes, at zero deflection.
  Eigen::Matrix2d CartesianStiffness(double q_knee) const;

 private:
  // q of the leg at q_knee (springs zero, tarsus closed); also the closure's Jacobian pieces.
  Eigen::VectorXd LegConfiguration(double q_knee) const;
  Eigen::Matrix2d Compliance(double q_knee, bool damping) const;
  double AlongLeg(double q_knee, bool damping) const;

  const MultibodyModel* model_;
  std::string side_;
  int knee_ = -1, shin_ = -1, tarsus_ = -1, heel_ = -1, loop_ = -1;
  int hip_body_ = -1, foot_body_ = -1;
  Eigen::Vector3d p_hip_link_, p_foot_link_;  // joint origins in their body frames
  double k_shin_ = 0, k_heel_ = 0, d_shin_ = 0, d_heel_ = 0;
  std::unique_ptr<MultibodyWorkspace> ws_;
};

struct LegStiffnessIdentificationOptions {
  double min_length = 0.60;  ///< [m] shortest L of the fit (spec C2 [R]: 0.6 m)
  double max_length = 0.92;  ///< [m] longest L of the fit (spec C2 [R]: 0.92 m, the Caltech knee limit −54.4°)
  int num_samples = 36;      ///< L values, evenly spaced
};

struct LegStiffnessIdentification {
  LegStiffness leg;                     ///< regressed K(L), D(L) (coefficients of L⁰, L¹, L², L⁴)
  Eigen::VectorXd lengths;              ///< sample L [m]
  Eigen::VectorXd stiffness;            ///< Eq. (12) at the samples [N/m]
  Eigen::VectorXd damping;              ///< [N s/m]
  double max_relative_fit_error = 0.0;  ///< max |fit − sample| / sample over the samples (K and D)
};

/// Eq. (4)-(13) + footnote 1: samples L over [min_length, max_length], evaluates Eq. (12) and regresses
/// c0 + c1 L + c2 L² + c4 L⁴ by least squares. Throws std::invalid_argument for bad options (named).
LegStiffnessIdentification IdentifyCassieLegStiffness(const CassieVirtualLeg& leg,
                                                      const LegStiffnessIdentificationOptions& options = {});

/// Spring-mass ROM parameters for a Cassie model: mass = model.total_mass(), n_legs = 2, gravity 9.81 m/s², and the
/// `published` or the `identified` (IdentifyCassieLegStiffness on the model's left leg, default options) K(L), D(L).
/// The identified variant is the one our plant matches (tests/systems/rom/spring_mass_standing_deflection_test.cc).
SpringMassParams CassieSpringMassParams(const MultibodyModel& model,
                                        LegStiffnessVariant variant = LegStiffnessVariant::kIdentified);

}  // namespace rome
