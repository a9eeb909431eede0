#pragma once
// Constrained dynamics, impact map and ground-contact helpers for a MultibodyModel.
//
// Active constraint set: a ContactSet bit mask (bit i = model.contacts()[i] in contact); all
// loop closures of the model are always active. Rows are stacked as: active contacts in
// index order, then every loop closure. Rows per contact (world axes, F in the same order):
//   planar model : point -> [v_x, v_z] of the point                  F = [F_x, F_z]
//                  line/flat -> [omega_y, v_x, v_z] of the contact frame F = [tau_y, F_x, F_z]
//   spatial/fixed: point -> v of the point (3)                        F = force (3)
//                  line  -> v of points[0] (3), then n1.v, n2.v of points[1], with n1, n2
//                           unit vectors perpendicular to the line (5 independent rows)
//                           F = [f_0 (3); f_1 along n1; f_1 along n2]
//                  flat  -> [omega; v] of the contact frame (6)     F = [torque; force]
//   loop closure -> d/dt |p_a - p_b| (1)                             F = rod tension (N),
//                           positive pulling p_a towards p_b
// The contact frame has the link's orientation and its origin at the point / midpoint /
// corner centroid (ContactInfo::frame_origin).
//
// Constrained forward dynamics:
//   M qdd + h = B u + tau_spring + J^T F                  (no tau_ext: use the overload)
//   J qdd + Jdot_qdot = -2 alpha J v - beta^2 phi          (Baumgarte stabilisation)
// phi is the position error of loop closures (|p_a - p_b| - distance); contacts have no
// position target here, so only the velocity term acts on them.
// Solution: qdd_free = M^-1 (B u + tau_spring - h), Lambda = J M^-1 J^T,
//   (Lambda + eps I) F = -(J qdd_free + Jdot_qdot + 2 alpha J v + beta^2 phi),
//   qdd = qdd_free + M^-1 J^T F,
// with eps = regularization * mean(diag Lambda), followed by two steps of iterative refinement
// against the unregularised Lambda (removes the O(eps) bias for full-rank Lambda). Redundant
// rows (e.g. a flat foot plus a point welded to it) make Lambda singular: F stays finite and
// qdd exact as long as the redundant rows are consistent (v satisfies J v = 0); with an
// inconsistent v the result is the regularised least-squares compromise.
//
// Plastic impact map (rigid, perfectly inelastic; Hurmuzlu & Marghitu 1994):
//   v+ = (I - M^-1 J^T (J M^-1 J^T)^-1 J) v-,   impulse = -(J M^-1 J^T)^-1 J v-   (N s)
// J contains the rows of the post-impact contact set (and the loop closures).
#include <cstdint>

#include <Eigen/Core>

#include "systems/multibody/multibody_dynamics.h"

namespace rome {

using ContactSet = std::uint64_t;
inline ContactSet ContactBit(int contact) { return ContactSet{1} << contact; }

struct ConstrainedDynamicsParameters {
  double baumgarte_alpha_per_s = 10.0;  // velocity feedback, 1/s (critically damped with beta)
  double baumgarte_beta_per_s = 10.0;   // position feedback on loop closures, 1/s
  double regularization = 1e-10;        // relative Tikhonov term on J M^-1 J^T (dimensionless)
};

// Number of stacked constraint rows for `active` (throws on bits beyond num_contacts()).
int CountConstraintRows(const MultibodyModel& model, ContactSet active);

// Fills ws.J (rows x nv), ws.Jdot_qdot and ws.phi (top `rows` entries); returns rows.
int CalcConstraintJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           ContactSet active);

// qdd (nv) and F (first `rows` entries written; F.size() >= rows). Returns rows.
int CalcConstrainedForwardDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                   const VectorRef& v, const VectorRef& u, ContactSet active,
                                   const ConstrainedDynamicsParameters& params, Eigen::Ref<Eigen::VectorXd> qdd,
                                   Eigen::Ref<Eigen::VectorXd> F);
// Same with an extra generalized force tau_ext (nv) on the right-hand side.
int CalcConstrainedForwardDynamics(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                   const VectorRef& v, const VectorRef& u, const VectorRef& tau_ext, ContactSet active,
                                   const ConstrainedDynamicsParameters& params, Eigen::Ref<Eigen::VectorXd> qdd,
                                   Eigen::Ref<Eigen::VectorXd> F);

// Static gravity compensation in a stance: the minimum-norm [u; F] of [B Jᵀ] [u; F] = h(q, 0) − τ_spring(q, 0) (the
// motor torques and the active contacts' and loop closures' forces that hold q at rest); returns u (nu). Not
// real-time (allocates; a dense complete orthogonal decomposition): a feedforward computed once, e.g. for a PD stance.
Eigen::VectorXd CalcStanceGravityCompensation(const MultibodyModel& model, ContactSet active, const Eigen::VectorXd& q);

// Plastic impact with the constraint set `active` (new stance contacts + loop closures).
// Returns rows; impulse (first `rows` entries) in the row convention above.
int CalcImpactMap(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v_minus,
                  ContactSet active, const ConstrainedDynamicsParameters& params, Eigen::Ref<Eigen::VectorXd> v_plus,
                  Eigen::Ref<Eigen::VectorXd> impulse);

// ---------------- ground-contact helpers (flat ground z = 0, normal +z) ----------------
// World position / velocity of point `point` of contact `contact`.
Eigen::Vector3d CalcContactPointPosition(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         int contact, int point);
Eigen::Vector3d CalcContactPointVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         const VectorRef& v, int contact, int point);
// Lowest world height over the contact's points (the guard "foot touches the ground").
double CalcContactHeight(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int contact);

struct ContactWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N, world axes
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // N m about origin, world axes
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // contact frame origin, world
};
// Wrench the ground applies on contact `contact`, from the stacked F of `active`.
ContactWrench ExtractContactWrench(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                   ContactSet active, const Eigen::Ref<const Eigen::VectorXd>& F, int contact);

struct ContactForceCheckParameters {
  double min_normal_force_N = 0.0;  // unilateral: F_z >= this
  double cop_margin_m = 0.0;        // CoP must stay this far inside the support polygon
};
struct ContactForceCheck {
  double normal_force_N = 0.0;                    // F_z
  double tangential_force_N = 0.0;                // |F_xy|
  double friction_ratio = 0.0;                    // |F_xy| / F_z (inf if F_z <= 0)
  Eigen::Vector2d cop = Eigen::Vector2d::Zero();  // centre of pressure (x, y), world
  bool unilateral_ok = false, friction_ok = false, cop_ok = false;
  bool ok() const { return unilateral_ok && friction_ok && cop_ok; }
};
// Normal force, friction-cone (|F_t| <= mu F_n) and centre-of-pressure check (CoP inside the
// convex hull of the contact points; always true for point contacts).
ContactForceCheck CheckContactForce(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                    int contact, const ContactWrench& wrench,
                                    const ContactForceCheckParameters& params = {});

}  // namespace rome
