#pragma once
// BulletWorldPlant: a MultibodyModel stepped by Bullet's own physics world (btMultiBodyDynamicsWorld, double
// precision), as a discrete-time framework system. A second, independent plant behind the same ports as
// HybridContactPlant (contact_plant.h), for sim-to-sim checks: a controller that only works on the rigid,
// event-accurate plant is fragile.
//
// inputs/outputs: exactly ContactPlant's (contact_plant.h): u; q, v, state, mode (int), contact_forces,
//   contact_violation, com. Every output is a function of the discrete state alone (no feedthrough).
//   Optional input (params.external_force_input, as HybridContactPlant's): tau_external (nv), a generalized external
//   force [N or N m per coordinate] added to the joint torques of each substep (e.g. an ExternalPush's J_pᵀ F).
// discrete state: [q (nv); v (nv); contact forces (3 nc); touching (nc, 0/1); touchdown time (nc) [s];
//   lift-off time (nc) [s]; time the current mode began [s]; distance slid (nc) [m]: per contact, since it last held
//   (see slip_speed_mps)]
// periodic update (period step_s, offset update_offset_s): one step of the Bullet world, in `substeps` equal
//   substeps. Each substep applies B sat(u) (sat: the model's torque limits) and the spring/damper torques
//   τ_spring = −K (q − q_rest) − D v of the substep's start as joint torques, then btMultiBodyDynamicsWorld::
//   stepSimulation (collision detection, Bullet's sequential-impulse contact/friction/limit solver, semi-implicit
//   Euler). The state held after the update at t_k + update_offset_s is the state at t_k + step_s: a controller that
//   samples at t_k (offset 0) sees the state at t_k and its torque is applied over [t_k, t_k + step_s], the same
//   causality as a zero-order-held controller on the continuous plant. (So a logger at time t sees the state up to
//   one step ahead of t.)
// Contact forces: the normal and friction impulses of the Bullet manifold points of each contact, summed over the
//   substeps and divided by step_s (the step's mean ground force on the contact, world axes).
// Mode: from which contacts touch, with hysteresis. A contact starts touching when the step's mean normal force on it
//   exceeds touchdown_force_N, and stops when its lowest point is more than liftoff_height_m above the terrain
//   surface under it (Terrain::SurfaceHeight). A change is announced through a guard that fires mode_change_delay_s
//   after the update that saw it, with the names of HybridContactPlant's guards, so that event updates (supervisor,
//   MPC, controllers) run at touchdowns on either plant:
//     touchdown_<contact> (modes with a graph touchdown transition of <contact>): the contact started touching after
//       the current mode began. Reset: the graph's target mode. On a stepping-stone terrain a touchdown whose contact
//       frame origin is on no stone (stone_tolerance_m) ends the run: Failed("robot fell: ...").
//     liftoff_<contact> (every mode, every active contact): the contact stopped touching. Reset: the graph's lift-off
//       target, else the mode with exactly the remaining contacts, else Failed.
//   No velocity jump at a touchdown: Bullet's contact solver resolves the impact (restitution 0) within the step.
// Planned lift-offs (planned_liftoff_force_N >= 0): a contact whose lift-off from the current mode is a transition of
// the
//   graph also stops touching when the step's mean normal force is at most planned_liftoff_force_N. Any touchdown is
//   announced no earlier than min_time_in_mode_s after its contact last stopped touching.
// Falls: the update ends the run (Failed "robot fell") when the base height is below min_base_height_m.
// contact_violation: +2 when a contact slides: its |F_t| exceeds μ F_n (Bullet clamps each of its two friction
//   directions at μ F_n, a pyramid, so this marks a sliding contact), or a loaded point of it slides faster than
//   slip_speed_mps for more than slip_distance_m (Bullet's clamped friction rarely shows a slide in the force: a foot
//   pivoting on its one loaded corner keeps |F_t| well inside μ F_n); +1 never occurs (Bullet's normal impulses are ≥
//   0).
//
// The Bullet model (BuildBulletMultiBody, shared with MultibodyWorkspace): the model's tree on a fixed Bullet base,
// the floating base as the model's virtual joints, so q and v are the model's coordinates exactly.
//  * Collision geometry: each sidecar contact point is a sphere of radius point_radius_m centred at the point (a
//    point foot: one sphere; a line foot: toe and heel; a flat foot: its corners); the terrain is lowered by
//    point_radius_m, so a point touches when it reaches the terrain, as in HybridContactPlant. Nothing else
//    collides (robot links neither with the terrain nor with each other).
//  * Terrain: flat ground is a static plane; a stepping-stone terrain is one static box per stone (its top at the
//    stone's top, its length the stone's, 10 m wide in y, reaching stone_depth_m below the lowest stone top) over a
//    plane at the lowest top minus stone_depth_m: a foot that misses a stone falls into the gap and may hit a side.
//  * Reflected rotor inertia (armature, MultibodyModel::reflected_inertia): Bullet has none, so each actuated joint
//    with one gets a rotor: a one-link btMultiBody on a fixed base (a massless wheel about a fixed axis, inertia
//    I_reflected about it), geared 1:1 to the joint's velocity by a btMultiBodyGearConstraint. Its kinetic energy is
//    ½ I_reflected q̇², exactly the model's armature term; the gear holds to the solver's convergence (measured on AMBER
//    in flight: |q̇_joint − q̇_rotor| < 1e-13 rad/s with all 100 iterations, ~6e-6 rad/s with the default
//    solver_residual_threshold; GearVelocityError). Bullet solves a multibody constraint only in
//    the simulation island of its links' colliders, so every robot link gets a collider (an empty one where it has no
//    contact point); without it the gears of links without contacts were silently ignored.
//  * Joint limits (the URDF's, where finite): btMultiBodyJointLimitConstraint (enable_joint_limits).
//  * Loop closures (Cassie's achilles rods): one BulletRodConstraint each (bullet_rod_constraint.h), a
//    btMultiBodyConstraint with one bilateral row along the rod (|p_a − p_b| = L; Bullet's btMultiBodyPoint2Point would
//    hold a point, not a length), solved with the joints' ERP (joint_erp); the length error is micrometres
//    (docs/design-notes.md#bullet-rod-constraint-error).
// Errors (one line, naming the system and the value): step_s <= 0, substeps < 1, a contact with no points (no
//   collision geometry), a stone of zero or negative length (Terrain::Stones), non-positive point_radius_m.
// The Bullet world lives in the context's scratch; Context::Clone builds a fresh world for the copy (its solver warm
// start, Bullet's contact cache, starts empty).

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "systems/plants/contact_plant.h"

namespace rome {

struct BulletWorldPlantParams {
  double step_s = 1e-3;  ///< [s] world step (ours: the controllers' 1 kHz)
  int substeps = 1;      ///< [-] Bullet steps per world step (each step_s / substeps long)
  double update_offset_s =
      1e-6;  ///< [s] the update runs this long after each multiple of step_s (after the controllers' samples)
  int solver_iterations = 100;  ///< [-] most sequential-impulse iterations per substep (Bullet's default 10; ours: the
                                ///< armature gears need more)
  /// [(m/s)², (rad/s)²] the solver stops before solver_iterations once no velocity coordinate changed by more than
  /// its square root in the last iteration (Bullet's m_leastSquaresResidualThreshold, on our own residual: see
  /// ConvergingMultiBodySolver in the .cc; 0: always solver_iterations)
  double solver_residual_threshold = 1e-10;
  /// [-] warm start of the solver (ours; 0: every row starts from zero, Bullet's multibody default): each constraint
  /// row (armature gears, joint limits, rods, contact normals, and contact friction as a world vector projected on the
  /// new directions) starts from this fraction of its impulse of the previous substep. The stopping rule still decides
  /// when to stop. At 1 the solver stops after a sweep or two on the old impulses and keeps their error
  /// (docs/design-notes.md#bullet-warm-start).
  double warm_start_factor = 0.98;
  double contact_erp = 0.2;  ///< [-] contact penetration correction per substep (Bullet's m_erp2, default 0.2)
  double joint_erp = 0.2;    ///< [-] joint-limit error correction per substep (Bullet's m_erp, default 0.2)
  double cfm = 0.0;          ///< [-] constraint force mixing (Bullet's m_globalCfm, default 0: rigid)
  /// [N/m], [N s/m] contact spring and damper (Bullet's btCollisionObject::setContactStiffnessAndDamping); 0 (default):
  /// rigid contact with contact_erp and cfm.
  double contact_stiffness_N_per_m = 0.0;
  double contact_damping_Ns_per_m = 0.0;
  double restitution = 0.0;           ///< [-] coefficient of restitution (0: plastic impacts, as HybridContactPlant)
  bool external_force_input = false;  ///< declare the tau_external input (see the top of this file)
  /// [-] Bullet multiplies the two objects' friction coefficients: the terrain gets 1 and each foot its contact's
  /// friction_coefficient (the sidecar's μ), so μ is the model's.
  double point_radius_m = 1e-3;  ///< [m] radius of the sphere at each contact point (ours)
  double stone_depth_m = 1.0;    ///< [m] stones reach this far below the lowest stone top, where a floor plane lies
  double touchdown_force_N =
      1e-6;  ///< [N] a contact starts touching when the step's mean normal force exceeds this (ours)
  double liftoff_height_m =
      2e-3;  ///< [m] and stops when its lowest point is this far above the surface under it (ours)
  /// [N] A planned lift-off (a lift-off transition of the graph from the current mode: the trailing foot of a double
  /// support, both feet at a jump's take-off) also stops touching when the step's mean normal force falls to this
  /// value, as HybridContactPlantParams::planned_liftoff_force_N, without waiting for the foot to rise
  /// liftoff_height_m: a controller that unloads a foot and waits for the mode change to lift it would otherwise wait
  /// forever (walking), and one whose stance torques assume contact would act on an airborne robot until its feet are 2
  /// mm up (hopping: measured 10 ms, in which the pelvis pitch rate swung from +3.3 to −6.5 rad/s). Negative (default):
  /// off.
  double planned_liftoff_force_N = -1.0;
  /// [s] planned_liftoff_force_N releases only a contact that has touched for at least this long (ours; 0: any). A
  /// swing foot that lands a few ms before its planned touchdown carries almost nothing until the controller loads it
  /// in the double support, and would otherwise be released at once and land again (walking on Bullet: a bounce per
  /// step). A contact that rises liftoff_height_m stops touching whenever it does.
  double planned_liftoff_min_contact_s = 0.0;
  /// [s] A contact's touchdown is announced no earlier than this long after it last stopped touching
  /// (HybridContactPlantParams::min_time_in_mode_s): a foot released by planned_liftoff_force_N still rests on the
  /// ground and touches again in the next step; if it is still touching then, the touchdown is announced. 0: at once.
  double min_time_in_mode_s = 0.0;
  double mode_change_delay_s = 1e-9;  ///< [s] the touchdown/lift-off guard fires this long after the update that saw it
  double min_base_height_m = 0.2;     ///< [m] base below this height ends the run as a fall
  double stone_tolerance_m = 0.0;     ///< [m] how far beyond a stone's edge a touchdown still counts
  bool saturate_torques = true;       ///< clip u to the model's torque limits before applying it
  bool enable_joint_limits = true;    ///< the URDF's finite position limits as Bullet joint-limit constraints
  double max_impulse_Ns =
      1e6;  ///< [N s] cap of every constraint impulse (Bullet's default 1000 would bind in hard impacts at small steps)
  /// Slip by sliding (ours): a touching contact slides while one of its loaded points (normal force above
  /// slip_min_point_force_N) moves along the surface faster than slip_speed_mps; it slips (contact_violation +2) once
  /// it has slid more than slip_distance_m without holding in between (infinity: off). See the .cc for the
  /// measurements.
  double slip_speed_mps = 0.01;         ///< [m/s]
  double slip_distance_m = 0.01;        ///< [m]
  double slip_min_point_force_N = 1.0;  ///< [N]
};

class BulletWorldPlant final : public ContactPlant {
 public:
  BulletWorldPlant(std::string name, std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph,
                   Terrain terrain, BulletWorldPlantParams params = {});
  ~BulletWorldPlant() override;

  const BulletWorldPlantParams& params() const { return params_; }
  /// Sets q, v (sizes checked) and the mode; the mode clock starts at the context time; a contact counts as touching
  /// when its lowest point is within liftoff_height_m of the terrain (so a foot standing there must first lift off
  /// before its touchdown is announced) and as having touched for planned_liftoff_min_contact_s already (it stands,
  /// it is not landing: a planned lift-off may release it at once).
  void SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                const std::string& mode) const override;
  /// Number of rotor links (actuated joints with reflected inertia) added to the Bullet tree.
  int num_rotors() const { return static_cast<int>(rotor_dofs_.size()); }
  /// Sequential-impulse iterations Bullet's solver used in the last substep of `context` (-1 before any step).
  int SolverIterationsUsed(const LeafContext& context) const;
  /// The solver's residual after its last iteration of the last substep (see solver_residual_threshold).
  double SolverResidual(const LeafContext& context) const;
  /// Largest |q̇_joint − q̇_rotor| over the rotors after the last step of `context` [rad/s]: how well the gears held.
  double GearVelocityError(const LeafContext& context) const;

  /// The ground's mean wrench on `contact` over the last step of `context` (world axes; torque about the world origin,
  /// origin = 0), from Bullet's manifold points: with CheckContactForce it gives the contact's centre of pressure.
  /// Diagnostic (the step's scratch, not state): valid after a step, before the next.
  ContactWrench LastStepContactWrench(const LeafContext& context, int contact) const;
  /// The distance `contact` has slid without holding (see slip_speed_mps) once it exceeds slip_distance_m, else 0 [m].
  double SlipDistance(const LeafContext& context, int contact) const override;

  /// Discrete-state offsets (see the top of this file).
  int forces_offset() const { return 2 * model_->nv(); }
  int touching_offset() const { return forces_offset() + 3 * model_->num_contacts(); }

  struct World;

 private:
  std::any AllocateScratch() const override;
  EventStatus Step(const LeafContext& context, Eigen::VectorXd* next) const;
  /// Height of the lowest point of `contact` above the terrain surface under it at q [m].
  double ContactHeight(const LeafContext& context, const Eigen::Ref<const Eigen::VectorXd>& q, int contact) const;
  void DeclareModeChangeGuards();  // the touchdown and lift-off guards of every mode (constructor only)
  void EnterMode(double t, int to, State* next) const;

  BulletWorldPlantParams params_;
  std::vector<int> rotor_dofs_;  ///< v index of each rotor's joint
  int td_time_offset_ = 0, lo_time_offset_ = 0, mode_start_offset_ = 0, slide_offset_ = 0;
};

}  // namespace rome
