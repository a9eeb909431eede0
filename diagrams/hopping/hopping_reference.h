#pragma once
// HoppingReference: the hybrid domain and the desired outputs of the hopping CLF-QP (hopping paper Sec. IV, Fig. 5,
// Eq. (41)-(44)), from the spring-mass ROM's leg-length plans (Eq. (14)-(16)).
//
// inputs:  state (2 nv)        plant [q; v]
//          mode (int, typed)   plant contact mode (ContactModeGraph::JumpFlightLanding order: jump, flight, landing)
//          contact_forces (3 nc) the plant's ground force on each contact [N], world axes (read in Jump when
//                              params.jump_force_feedback or jump_force_integral_per_s ≠ 0)
// outputs: desired (3·ny)      [y_d; ẏ_d; ÿ_d] in the HoppingOutputLayout given (diagrams/hopping/hopping_outputs.h):
//            jump:    H_pitch 0; L_L = L_R = L_plan(t − t_jump) (+ the GRF correction, params.jump_force_feedback);
//                     COM x, y = support centre; yaw = yaw at the start;
//                     pitch (when Jump tracks the pelvis pitch): θ_d, θ̇_d from the centroidal pitch momentum (below)
//            flight:  motors = their positions at lift-off, toes corrected so the soles stay level once the springs
//                     unload (see below); hips optionally turned with the pelvis pitch (params.flight_hip_pitch_follow,
//                     then 'desired' depends on 'state')
//            landing: L_L = L_R = L_plan(t − t_touchdown); COM x: quintic from its post-impact value and rate to the
//                     support centre over landing_blend_s; pitch: quintic from its post-impact value and rate to 0
//                     (spec [R], C10); COM y = support centre; yaw as in jump
//          domain (int, typed) 0 jump, 1 flight, 2 landing: the controller's mode. It follows the plant's mode at
//          lift-off
//                              and touchdown; the first "landing" domain (before any hop) is the settle phase, and a
//                              landing domain turns into jump after settle_time_s (the first hop) or, if hops remain,
//                              once the robot is at rest: rest_time_s, then until max |q̇| < rest_max_speed, at most
//                              max_rest_time_s.
//          plan_status (3)     [jump plans solved, landing plans solved (at a planned lift-off and at each touchdown),
//                              planner failures (a failed solve at lift-off has no fallback: it only warms the next)]
//                              A lift-off during Landing (a bounce) also enters Flight, and its touchdown counts as a
//                              hop (hops done) with a landing plan of its own.
// discrete state: see the k* offsets in the source; the leg-length plans (node times, L, L̇) live there.
//
// Event work: a periodic update (update_period_s) switches landing → jump when its time is up (solving the jump plan
// from the measured state, JumpPlanner); an event update at the plant's guards records the lift-off snapshot (motor
// targets) and the landing plan solved from the touchdown predicted at lift-off (LandingSolve::kPredictedAtLiftoff: it
// only warms the next solve; a failure is counted, not fatal) and, at touchdown, the post-impact state and the landing
// plan solved from it (LandingPlanner, kAtTouchdown; the warm start is the planner's
// business). A planner that fails is counted on plan_status and its plan replaced by the documented fallback: jump:
// the run cannot hop, the domain stays landing and the block reports failure through EventStatus::Failed; landing: a
// quintic from the post-impact leg length to the standing leg length over landing_fallback_s.
//
// Jump pitch reference (ours; used when the Jump outputs track the pelvis pitch instead of H_pitch, Eq. (41)): every
// period θ̇_d = θ̇ − k H_pitch / I_p and θ_d += T θ̇_d, with I_p = ∂H_pitch/∂θ̇ along "the pelvis pitches, the hips turn
// back so the soles keep their world pitch" (hip ratio from finite differences at the start of Jump). The pelvis thus
// turns against the legs' angular momentum, so H_pitch at lift-off is smaller, while its pitch stays an RD2 output
// (H_pitch itself as the RD1 output gives the closed loop an unstable mode, see diagrams/hopping/hopping_diagram.h).
//
// Flight toe targets: holding the motors keeps the soles level while the pelvis pitch holds, except that the shin and
// heel springs unload in flight, which turns the tarsus back onto the rigid rule q_knee + q_tarsus = c (c from the
// model's nominal pose, springs undeflected; 13.0° for Cassie). The toe target compensates that rotation, found by
// evaluating the sole's pitch at the predicted unloaded configuration (one finite difference of the toe angle).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/system.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

/// Offsets of the hopping outputs in the CLF-QP's stacked output vector (diagrams/hopping/hopping_outputs.h);
/// momentum = -1 when the Jump outputs do not include H_pitch. motors: 10 entries from there.
struct HoppingOutputLayout {
  int momentum = 0, leg_left = 1, leg_right = 2, com_x = 3, com_y = 4, yaw = 5, pitch = 6, motors = 7, size = 17;
};

/// A leg-length plan: nodes (t_k from the start of the domain, L_k, L̇_k), evaluated as a cubic Hermite (spec [R]).
struct LegLengthPlan {
  Eigen::VectorXd t, L, Ldot;  ///< [s], [m], [m/s]
  /// [m], [m/s] the ROM's mass height x (real leg length) and its rate at the nodes; empty: none (optional, for
  /// HoppingReferenceParams::landing_deflection_feedback).
  Eigen::VectorXd x, xdot;
  /// [N] the ROM's total leg force F and [N/m] its stiffness n_legs K(L) at the nodes; empty: none (optional, for
  /// HoppingReferenceParams::jump_force_feedback).
  Eigen::VectorXd force, stiffness;
  double duration() const { return t.size() > 0 ? t[t.size() - 1] : 0.0; }
};

/// The ROM state the planners start from (hopping spec A2): x = mean real leg length L_r (hip-pitch joint to toe
/// joint) [m], ẋ = COM vertical velocity [m/s], L = mean virtual leg length L(q_knee) [m], L̇ = mean dL/dq_knee q̇_knee.
struct RomState {
  double x = 0, xdot = 0, L = 0, Ldot = 0;
};

struct HoppingReferenceParams {
  double update_period_s = 5e-4;  ///< [s] periodic check for the timed landing → jump switch (hopping: 2 kHz)
  double settle_time_s = 1.5;     ///< [s] settle in landing before the first jump (spec [R] A5: 1.5 s)
  double rest_time_s = 1.5;       ///< [s] between a touchdown and the next jump when hops remain (ours): at least
  /// [rad/s, m/s] ...and until every |q̇_i| < this (ours: the hopping issue's "at rest"; 0: rest_time_s alone), ...
  double rest_max_speed = 0.05;
  double max_rest_time_s = 5.0;     ///< [s] ...but at most this long (ours)
  int hops = 1;                     ///< number of hops (≥ 1)
  double landing_blend_s = 0.3;     ///< [s] COM x and pitch quintics after touchdown (spec [R] C10: 0.3 s)
  double landing_fallback_s = 0.5;  ///< [s] fallback landing quintic (ours)
  int max_plan_nodes = 201;         ///< nodes a plan may have
  /// k [-] of the Jump pitch reference θ̇_d = θ̇ − k H_pitch / I_p (see PeriodicUpdate; ours); 0: hold the pitch.
  double jump_momentum_gain = 2.0;
  /// k [-] (ours; 0 holds the hips at their lift-off angles, Eq. (43)): in Flight the hip-pitch targets turn with the
  /// pelvis pitch θ, q_hip_d = q_hip_lo − k r (θ − θ_lo), q̇_hip_d = −k r θ̇, r = HipPerPitch at lift-off; k = 1 keeps
  /// the legs at their lift-off world pitch, so the feet stay under the hips as the pelvis rotates.
  double flight_hip_pitch_follow = 0.0;
  /// g [-] (ours; 0: off, the paper's L_d = L_plan): in the Landing after a hop, L_d = L_plan + g (x − x_plan),
  /// L̇_d = L̇_plan + g (ẋ − ẋ_plan) with x the measured mean real leg length and ẋ the COM's vertical velocity
  /// (RomState), so that at g = 1 the spring deflection s = L − x, hence the ROM's leg force, follows the plan's.
  /// Needs plans with x (LegLengthPlan::x); makes 'desired' depend on 'state'.
  double landing_deflection_feedback = 0.0;
  /// GRF feedback in Jump (ours; k_F = k_I = 0: off, the paper's L_d = L_plan):
  ///   L_d = L_plan + w clamp(k_F e + ∫ k_I e dt, ±c_max),  e = (F_plan − F) / (n_legs K(L_plan)),
  ///   w = clamp(F_plan / F_plan(0), 0, 1)
  /// with F the plant's total normal ground force (input 'contact_forces', read when 'desired' is evaluated) and
  /// F_plan, n_legs K the plan's (LegLengthPlan::force, stiffness): the legs are lengthened by the ROM deflection of
  /// the missing force. The integral runs in the periodic update (clamped to ±c_max, restarted at 0 with each Jump). w
  /// fades the correction out as the plan's force falls to 0 at lift-off (without it the feet slipped at lift-off at an
  /// apex rise of 0.28 m) and also weakens it in the crouch, where F_plan < F_plan(0). L̇_d and L̈_d stay the plan's: the
  /// correction swings fast, and a low-passed or delayed one let the feet slip at lift-off. A jump plan without force
  /// and stiffness while k_F or k_I ≠ 0 is a failed plan. It closes the loop where the ROM's K(L) and the plant's legs
  /// differ (docs/design-notes.md#hopping-air-time). Makes 'desired' depend on 'contact_forces'.
  double jump_force_feedback = 0.0;        ///< k_F [-]
  double jump_force_integral_per_s = 0.0;  ///< k_I [1/s]
  /// c_max [m] (ours; 0.05 m let the feet slip at lift-off; docs/design-notes.md#hopping-force-correction-limit)
  double jump_force_correction_max_m = 0.1;
  std::string left_knee = "left_knee", right_knee = "right_knee";
  std::string left_shin = "left_shin_spring", right_shin = "right_shin_spring";
  std::string left_tarsus = "left_tarsus", right_tarsus = "right_tarsus";
  std::string left_toe = "left_toe", right_toe = "right_toe";
  std::string left_hip_pitch_link = "left_hip_pitch", right_hip_pitch_link = "right_hip_pitch";
  std::string left_toe_link = "left_foot", right_toe_link = "right_foot";  ///< link whose frame origin is the toe joint
  std::string left_contact = "left_foot", right_contact = "right_foot";    ///< the feet's line contacts
};

class HoppingReference final : public LeafSystem {
 public:
  using LegLengthFunction = std::function<void(double q_knee, double* L, double* dL_dq)>;
  /// Jump plan from the measured standing ROM state (Eq. (14)-(15)); returns false (and a message) on failure.
  using JumpPlanner = std::function<bool(const RomState& start, LegLengthPlan* plan, std::string* message)>;
  /// When the landing planner is called (hopping issue: "solved once at take-off from the predicted touchdown, and
  /// re-solved warm-started at touchdown").
  enum class LandingSolve {
    kPredictedAtLiftoff,  ///< `state` is the ROM state measured at lift-off; the planner predicts the touchdown itself
    kAtTouchdown,         ///< `state` is the post-impact ROM state (the plan the Landing tracks)
  };
  /// Landing plan (Eq. (16)); returns false on failure. The plan solved at lift-off only warms the touchdown solve.
  using LandingPlanner =
      std::function<bool(const RomState& state, LandingSolve when, LegLengthPlan* plan, std::string* message)>;

  HoppingReference(std::string name, std::shared_ptr<const MultibodyModel> model, LegLengthFunction leg_length,
                   JumpPlanner jump_planner, LandingPlanner landing_planner, HoppingOutputLayout layout,
                   HoppingReferenceParams params = {});

  const HoppingReferenceParams& params() const { return params_; }
  /// The ROM state of the robot at (q, v) (see RomState).
  RomState MeasureRomState(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const;
  /// The same with a caller's workspace (no allocation).
  RomState MeasureRomState(MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v) const;
  /// Sets the state to "settle in landing" at the context's time with the standing leg length of q held.
  void Initialize(LeafContext& context, const Eigen::VectorXd& q) const;
  /// Whether Initialize has run on this context (a forgotten initial state is reported by name, not simulated).
  bool initialized(const LeafContext& context) const;
  /// Node plans currently held (for logs and tests). A plan written without x, ẋ or force, stiffness comes back with
  /// those vectors NaN-filled (n nodes), not empty.
  LegLengthPlan jump_plan(const LeafContext& context) const;
  LegLengthPlan landing_plan(const LeafContext& context) const;
  /// Time the current domain began [s].
  double domain_start_time(const LeafContext& context) const;
  /// L, L̇, L̈ of a plan at time s from its start (held at the last node after the end).
  static Eigen::Vector3d Evaluate(const Eigen::Ref<const Eigen::VectorXd>& t,
                                  const Eigen::Ref<const Eigen::VectorXd>& L,
                                  const Eigen::Ref<const Eigen::VectorXd>& Ldot, int n, double s);

 private:
  EventStatus PeriodicUpdate(const LeafContext& context, Eigen::VectorXd* next) const;
  EventStatus GuardUpdate(const LeafContext& context, const EventRecord& event, State* next) const;
  void CalcDesired(const LeafContext& context, Eigen::VectorXd* y) const;
  void WritePlan(int offset, const LegLengthPlan& plan, Eigen::VectorXd* xd) const;
  void SnapshotSupport(const Eigen::VectorXd& q, Eigen::VectorXd* xd) const;
  double SolePitch(const Eigen::VectorXd& q, int contact) const;
  double HipPerPitch(const Eigen::VectorXd& q, int leg) const;
  double JumpForceError(const LeafContext& context, double s, double* fade) const;
  struct Scratch;
  std::any AllocateScratch() const override;

  std::shared_ptr<const MultibodyModel> model_;
  LegLengthFunction leg_length_;
  JumpPlanner jump_planner_;
  LandingPlanner landing_planner_;
  HoppingOutputLayout layout_;
  HoppingReferenceParams params_;
  int hip_pitch_[2], hip_actuator_[2], knee_[2], shin_[2], tarsus_[2], toe_[2], hip_link_[2], toe_link_[2], contact_[2];
  double rigid_knee_plus_tarsus_ = 0;
  int jump_plan_offset_ = 0, landing_plan_offset_ = 0, size_ = 0;
  int state_port_ = -1, mode_port_ = -1, forces_port_ = -1;
};

}  // namespace rome
