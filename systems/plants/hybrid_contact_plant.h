#pragma once
// HybridContactPlant: a MultibodyModel as an event-accurate hybrid framework system.
// Its ports are ContactPlant's (contact_plant.h); BulletWorldPlant has the same ones.
//
// inputs:  u (nu)                      actuator torques [N m], joint side, in MultibodyModel::actuators() order
//          tau_external (nv)           only with params.external_force_input: generalized external force
// outputs: q (nq)                      generalized positions (see multibody_model.h for the coordinates)
//          v (nv)                      generalized velocities
//          state (nq + nv)             [q; v]
//          mode (int, typed)           index of the active contact mode (ContactModeGraph::modes order)
//          contact_forces (3 nc)       ground force on each contact [N], world axes; zero when not in contact
//          contact_violation (nc)      per contact: 0 ok, +1 negative normal force, +2 outside the friction cone
//          com (6)                     [p_com (m); v_com (m/s)], world; elements x, y, z, vx, vy, vz
// continuous state: [q; v], dq/dt = G(q) v (MultibodyModel::MapVelocityToQDot): v itself, except on the quaternion
//   free-flyer base (nq = nv + 1, free_flyer.h), whose quaternion rate 1/2 quat (x) (0, w_B) is linear in the stored
//   quaternion, minus params.quaternion_norm_gain_per_s (|quat|^2 - 1) quat. The exact flow keeps |quat| = 1; the
//   integrator's error moves the norm, which the dynamics never see (every kinematic and dynamic call normalises the
//   quaternion); the gain makes that error decay, and SetState and every touchdown reset project the quaternion back
//   onto the unit sphere. Measured drift: docs/design-notes.md#quaternion-norm.
// discrete state (1 + nc): [0]     time the current mode began [s]
//                          [1 + i] time contact i last left the ground (lift-off, or the old stance of an impact) [s];
//                                  SetState sets every entry to the context time, the default context to 0
// modes: the graph's modes, in ContactModeGraph::modes order.
//
// Flow in mode m with active contacts C(m) (plus every loop closure of the model):
//   M q̈ + h = B sat(u) + τ_spring + Jᵀ F,  J q̈ + J̇ q̇ = −2α J q̇ − β² φ   (contact_dynamics.h)
// Guards (all directional, on CVODE's rootfinder; names are stable):
//   touchdown_<contact>  (modes with a touchdown transition of <contact>): lowest contact point height above the
//     terrain crosses 0 falling. A contact that left the ground less than min_time_in_mode_s ago is not armed (it
//     starts at height ~0); every other contact is armed at once.
//     Reset: plastic impact q̇⁺ = (I − M⁻¹Jᵀ(JM⁻¹Jᵀ)⁻¹J) q̇⁻ with the TARGET mode's contact set; on a
//     stepping-stone terrain a touchdown that is not on a stone ends the run: Failed("robot fell: ...").
//   liftoff_<contact>  (every mode, every contact c ∈ C(m)): the normal force on c (world z of the ground force,
//     ExtractContactWrench) crosses 0 falling (params.planned_liftoff_force_N for the graph's own lift-off
//     transitions). Contact is unilateral in every graph. Reset: mode change only, to the graph's lift-off transition
//     of c from m if there is one, else to the mode whose contact set is exactly C(m) \ {c}, else the run ends:
//     Failed("'<c>' lifted off at t = ... s (...), but the contact-mode graph has no mode to lift off into").
//   slip  (every mode with contacts; one witness component per contact, index = contact index): μ_c F_n − |F_t|
//     crosses 0 falling (inactive contacts: +1). μ_c = ContactInfo::friction_coefficient. Ends the run:
//     Failed("'<c>' slipped at t = ... s: |F_t|/F_n = ... reached the friction coefficient mu = ..."). A slip is a
//     failure, not a switch to a Coulomb sliding mode: the walking controllers keep every stance inside the cone,
//     so leaving it means the controller or the plan is wrong; a sliding mode would need a second, non-welded
//     contact model (and its own impact law) that nothing here needs yet, and would hide those errors.
//     3D flat contacts (a sole whose points are the four corners of a rectangle in its body frame; params.sole_torsion)
//     also slip torsionally, as a rigid sole on four corners does: the component is then
//       min(mu_c F_n - |F_t|, m_tau / (X + Y)),
//     m_tau = the margin of the sole's wrench (foot frame, torque about the rectangle's centre, half-sizes X, Y) to
//     the yaw rows of the contact wrench cone of four corners with friction pyramids mu' = mu_c/sqrt(2) inscribed in
//     their cones (Caron, Pham, Nakamura, ICRA 2015), in N m:
//       m_tau = min over s = ±1 of  mu'(X+Y) f_z - s tau_z - |Y f_x + s mu' tau_x| - |X f_y + s mu' tau_y|;
//     a pure twist about the centre slips at |tau_z| = mu'(X+Y) f_z, a CoP at a corner holds none. Ends the run:
//     Failed("'<c>' slipped torsionally at t = ...: |tau_z| = ... N m beyond the ... N m four corners hold ...").
//     Lift-off guards of a mode are declared before its slip guard: a contact that unloads with F_t = 0 (the cone's
//     apex, both witnesses reach 0 at once) lifts off, and the old mode's slip guard is then inactive.
//   fall  (all modes; floating bases only): base height below min_base_height_m: Failed("robot fell: ...").
//   joint_stop  (all modes, with params.joint_stops; one component per finite URDF position limit: q_i − q_lower,i and
//     q_upper,i − q_i): a joint reaches its limit. Ends the run: Failed("joint '<j>' reached its lower limit -0.35 at
//     t = ... s (joint stop)"). A joint already more than joint_stop_tolerance beyond a limit right after an event
//     (e.g. a start pose outside the limits) ends the run there (the event publish), since its witness cannot cross.
// Violations no witness can see: after every event (initialisation, a guard reset, another system's discrete update
// such as a zero-order-held u) the plant's event publish checks every active contact. Its witnesses restart from the
// post-event values, so a normal force (friction margin) that jumped below 0 at the event would never cross: such
// a contact's liftoff_<contact> (slip component) witness becomes immediate_event_delay_s − (t − t_event), so it
// lifts off (slips) immediate_event_delay_s after the event through the same reset and target rules as above; the
// messages then give t_event and the force right after the event. Example: a touchdown whose held input makes the
// new stance foot pull lifts that foot off again at once. A value within event_tolerance_N beyond its bound (rounding,
// when a controller holds the force on the cone or at F_n = 0) is taken as on the bound: until the next event that
// contact's witness is the value + event_tolerance_N, so it still fires if the force then leaves the bound. (The
// pending set lives in the context's scratch, not in the state: every event publish recomputes it, and it only applies
// while the mode it was found in is active.)

#include <memory>
#include <string>
#include <vector>

#include "systems/plants/contact_plant.h"

namespace rome {

struct HybridContactPlantParams {
  ConstrainedDynamicsParameters dynamics;  ///< Baumgarte gains and regularisation (contact_dynamics.h)
  double min_time_in_mode_s = 0.05;        ///< [s] a contact's touchdown guard arms this long after it left the ground.
  double min_base_height_m = 0.2;          ///< [m] base below this height ends the run as a fall.
  double stone_tolerance_m = 0.0;          ///< [m] how far beyond a stone's edge a touchdown still counts.
  bool saturate_torques = true;            ///< clip u to the model's torque limits before applying it.
  /// [s] A contact whose normal force is already < -event_tolerance_N (or friction margin, likewise) right after an
  /// event (initialisation, a reset, another system's discrete update, e.g. a zero-order-held input) lifts off (or
  /// slips) this long after the event: its witness is replaced by a ramp that crosses 0 then (see the header).
  double immediate_event_delay_s = 1e-9;
  /// [N] Right after an event, a normal force or friction margin (mu F_n - |F_t|) between -event_tolerance_N and 0 is
  /// rounding on the bound, not a violation (see the header). The guards' crossings themselves are exact.
  double event_tolerance_N = 1e-6;
  /// true: every stance contact lifts off at F_n = 0 and the run fails when one leaves the friction cone (the
  /// guards above). false: contacts stay welded except at the graph's own lift-off transitions, whatever their
  /// forces (the plant before unilateral contact; kept to measure what an idealised plant hides).
  bool unilateral_contact = true;
  /// [N] A contact whose lift-off is a transition of the graph (e.g. the trailing foot, double → single support) lifts
  /// off when its normal force falls through this value instead of 0 (walking spec §7.5 [R]: 1 % of m g). As F_n → 0
  /// the ratio |F_t|/F_n of a force held over a control sample is ill-conditioned and would end the run as a slip just
  /// before the lift-off; the controller unloads the foot to ~0 and the plant then releases it. 0: exactly at F_n = 0.
  double planned_liftoff_force_N = 0.0;
  /// Joint stops (ours): reaching a URDF position limit ends the run as a failure (the joint_stop guard above). A rigid
  /// stop's impact is not modelled: a controller must keep every joint inside its limits. Off by default for now: the
  /// walking plans bend the exoskeleton's ankles to -0.83 rad (URDF limit -0.35 rad; docs/design-notes.md#joint-limits)
  /// and the other robots' runs are not measured against their limits yet.
  bool joint_stops = false;
  /// [rad, or m for a prismatic joint] right after an event a joint this far beyond a limit is rounding on the limit,
  /// not a violation (ours; the stop guard's crossing itself is exact to the rootfinder's tolerance).
  double joint_stop_tolerance = 1e-9;
  /// true: the plant also has the input tau_external (nv), a generalized force [N or N m per coordinate] added to the
  /// flow's right-hand side (M q̈ + h = B sat(u) + τ_spring + τ_ext + Jᵀ F), e.g. an ExternalPush
  /// (systems/perturbations/external_push.h). false: no such input (nothing to connect).
  bool external_force_input = false;
  /// [-] Quaternion base only: SetState refuses a base quaternion whose norm is farther than this from 1 (and projects
  /// one within it onto the unit sphere). Ours; the integrator's own drift is far smaller (docs/design-notes.md).
  double max_quaternion_norm_error = 1e-6;
  /// [1/s] Quaternion base only: the quaternion rate gets -gain (|quat|^2 - 1) quat, zero on the unit sphere, so the
  /// norm error the integrator makes decays instead of accumulating between resets (ours; 0 = off; measured in
  /// docs/design-notes.md#quaternion-norm).
  double quaternion_norm_gain_per_s = 10.0;

  /// true: 3D four-corner flat contacts slip torsionally outside their corners' wrench cone (the slip guard, see the
  /// header): the plant's sole is as strict as a rigid sole's four corners (ours). false (default for now: 8 walking
  /// closed-loop tests then slip torsionally, docs/design-notes.md#walking-sole-torsion): only the linear cone.
  bool sole_torsion = false;
};

class HybridContactPlant final : public ContactPlant {
 public:
  HybridContactPlant(std::string name, std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph,
                     Terrain terrain, HybridContactPlantParams params = {});

  const HybridContactPlantParams& params() const { return params_; }

  /// Sets q, v and the mode in a context (sizes checked); the mode clock starts at the context time, and every
  /// contact counts as having left the ground then (touchdown guards arm min_time_in_mode_s later).
  void SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                const std::string& mode) const override;

  struct Scratch;

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  std::any AllocateScratch() const override;
  /// Constrained dynamics at the context's state, computed once per context version.
  const Scratch& EvalDynamics(const LeafContext& context) const;
  /// Ground force on each contact [N], world axes, 3 x nc (zero columns for inactive contacts), cached per version.
  const Eigen::Matrix3Xd& EvalContactForces(const LeafContext& context) const;
  double TouchdownWitness(const LeafContext& context, int contact) const;
  /// Projects the quaternion base's quaternion (x's entries 3..6) onto the unit sphere; no-op on other bases.
  void NormalizeBaseQuaternion(Eigen::VectorXd& x) const;
  /// Mode change at time t: discrete[0] = t, contacts active in `from` but not in `to` left the ground at t.
  void EnterMode(double t, int from, int to, State* next) const;
  // The constructor's declarations, in this order: the outputs; per mode, each active contact's lift-off guard, then
  // the mode's slip guard; the event publish that finds violations no guard can see; the graph's touchdowns, the fall.
  void DeclarePlantOutputs();
  void DeclareLiftoffAndSlipGuards();
  void DeclarePostEventCheck();
  void DeclareTouchdownAndFallGuards();
  /// The joint_stop guard and its post-event check (params.joint_stops).
  void DeclareJointStops();
  /// mu F_n - |F_t| of a contact [N].
  double FrictionMargin(const Eigen::Matrix3Xd& forces, int contact) const;
  /// The slip witness of a contact [N]: FrictionMargin, and for a four-corner sole the torsion margin over X + Y.
  double SlipMargin(const LeafContext& context, int contact) const;
  /// Four-corner soles (params.sole_torsion): the yaw-row margin m_tau of contact `contact` [N m] (see the header).
  double TorsionMargin(const LeafContext& context, int contact) const;
  /// The torsional slip's failure message (t: the slip's time).
  std::string TorsionMessage(const LeafContext& context, int contact, double t) const;
  /// Fills sole_ and sole_centre_ (params.sole_torsion; throws for a flat contact that is not four rectangle corners).
  void FindFourCornerSoles();
  /// Witness of a violation found right after an event: > 0 at the event, crossing 0 immediate_event_delay_s later.
  double PendingWitness(const LeafContext& context) const;

  HybridContactPlantParams params_;
  std::vector<std::vector<double>> liftoff_threshold_;  // [mode][contact] N: planned_liftoff_force_N or 0
  // Per contact: the four-corner sole's half-sizes X, Y and centre (body frame); X < 0: no torsion check.
  std::vector<Eigen::Vector3d> sole_;  // (X, Y, unused)
  std::vector<Eigen::Vector3d> sole_centre_;
};

}  // namespace rome
