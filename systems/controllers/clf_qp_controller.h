#pragma once
// ClfQpController: a CLF-QP controller block configured by data (hopping paper Eq. (22)-(37), (45)-(51); walking paper
// Eq. (18)-(25)). One block serves AMBER, planar Cassie, the exoskeleton and Cassie: the robot, its contact modes and
// its outputs are arguments, not subclasses.
//
// inputs:  state (nq + nv)             [q; v] of the plant (HybridContactPlant "state"); any base (nq = nv + 1 on
//                                      the quaternion free-flyer, v its twist: free_flyer.h)
//          mode (int, typed)           the plant's contact mode (an index into mode_contacts)
//          desired (3 ny)              [y_d; ẏ_d; ÿ_d], ny = Σ output sizes, outputs in construction order. For a
//                                      relative-degree-2 output the three thirds hold y_d (m, rad), ẏ_d, ÿ_d; for a
//                                      relative-degree-1 output y_d holds y1_d (its own unit, e.g. N m s), ẏ_d holds
//                                      ẏ1_d and ÿ_d is unused. Rows of outputs inactive in the current mode are
//                                      ignored.
//          normal_force_reference (nc) [N] only with params.force_band: the reference normal force of each contact
//                                      (walking paper Eq. (25); e.g. the aSLIP's leg force); inactive contacts ignored
// outputs: u (nu)                      actuator torques [N m], zero-order held between updates (no feedthrough)
//          contact_forces (3 nc)       the QP's planned ground force on each contact [N], world axes
//          V (1)                       V_ε(η) at the last update [-]
//          delta (1)                   the CLF relaxation δ of the last update
//          qp_failures (1)             updates whose first QP failed (each then took a fallback below)
//          qp_status (1)               QpStatus of the last update's final solve (0 = kOptimal)
//          fallbacks (4)               [drift_dropped, band_dropped, cop_dropped, held]: how many updates used each
//                                      fallback
//          clf_activity (2)            [clf_active, solved]: updates whose final QP solution has the CLF row active
//                                      (δ > 0, or the normalised row's slack ≤ params.clf_active_tolerance; η ≠ 0), and
//                                      updates solved (kOptimal); their ratio is how often the CLF constraint binds
//          solve_time_s (1)            wall time of the last update [s] (QP assembly, solves, fallbacks; steady_clock)
//          diagnostics (ClfQpDiagnostics, typed)  all of the above but u and contact_forces, by name
// discrete state: [u; contact_forces; the diagnostics] (read them with diagnostics(), not by offset). Updated
// periodically (params.update_period_s) and by an event update at the guard events params.resolve_at selects (default:
// every guard event), so the new contact mode's torque acts from the event instant on.
//
// Output dynamics (Eq. (24)): μ = [ẏ1 − ẏ1_d; ÿ2 − ÿ2_d; ÿs − ÿs*] = 𝒜 x + L_f, affine in the decision variables x
// (ys: the cost-only outputs of params.cost_only_outputs, ÿs* = ÿs_d − Kp es − Kd ės; none by default).
// RES-CLF (Eq. (26)-(33)): η = [y1 − y1_d; y2 − y2_d; ẏ2 − ẏ2_d] over the CLF outputs active in the mode,
// F, G of Eq. (26), P from the CARE Fᵀ P + P F − P G Gᵀ P + Q = 0 (Q = I), V = ηᵀ P_ε η, P_ε = I_ε P I_ε,
// γ = λ_min(Q)/λ_max(P) (params.gamma > 0 overrides). CLF row (Eq. (36)-(37)):
//   L_G V 𝒜 x ≤ −(γ/ε) V − L_F V − L_G V L_f + δ,   normalised by 1 + ||L_G V 𝒜||.
// QP:  minimise  ½ ||W (𝒜 x + L_f − σ)||² + ½ ρ_u Σ_j s_j u_j² + ½ p δ²     (s_j = s: largest diagonal of 𝒜ᵀW𝒜 on u,
//      by default; see params.u_regularization_kind for the per-actuator s_j = w_j / m_j², m_j = b_jᵀ M b_j;
//      σ = −Kp e − Kd ė on the RD2 CLF rows with params.cost_pd_feedback, else 0; the CLF row always uses L_f)
//      subject to the CLF row, the contact-wrench rows of every active contact (contact_wrench_constraints.h),
//      the force band (1 − c) F_ref ≤ F_z ≤ (1 + c) F_ref (optional), torque limits, δ ≥ 0.
// Two formulations (params.formulation), the same QP in two coordinates, so they give the same torques:
//   kEliminateContactForces (walking Eq. (20)-(22)): x = [u; δ]; the contact and loop-closure forces are the affine
//      function F = A_v u + b_v of u that keeps J q̈ + J̇ q̇ = −2α J q̇ − β² φ, A_v = −Λ⁻¹ J M⁻¹ B,
//      b_v = −Λ⁻¹ (J M⁻¹ (τ_s − h) + J̇ q̇ + 2α J q̇ + β² φ), Λ = J M⁻¹ Jᵀ.
//   kAugmentedInput (hopping Eq. (45)-(51)): x = [u; F; δ] with the holonomic equalities J M⁻¹ (B u + Jᵀ F) =
//      −J M⁻¹ (τ_s − h) − J̇ q̇ − 2α J q̇ − β² φ (contacts and loop closures such as Cassie's achilles rods).
// α, β come from params.contact_stabilization: the plant's (HybridContactPlantParams::dynamics) predict its forces
// exactly from an exact state; α = 0 keeps a measured J q̇ (sensor noise) out of the predicted forces.
//
// Fallbacks when the QP is infeasible (each counted on 'fallbacks', and qp_failures counts the update):
//   0. with params.predict_hold_drift: drop the hold-drift rows only and re-solve (the band and the brake stay; e.g.
//   a drift d that takes the wrench out of its cone faster than the band and torque limits allow); 1. drop the
//   force band, the hold-drift rows and the joint-limit brake rows (params.joint_limit_brake) and re-solve; 2. also
//   drop the centre-of-pressure rows and re-solve; 3. hold the previous u.
// One DenseQpSolver per mode, sized at construction, warm-started; an update allocates no heap memory.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "framework/system.h"
#include "systems/controllers/controller_setup.h"
#include "solvers/qp/dense_qp_solver.h"
#include "systems/controllers/clf_outputs.h"
#include "systems/controllers/contact_wrench_constraints.h"
#include "systems/controllers/joint_limit_brake.h"
#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/contact_dynamics.h"

namespace rome {

/// How the torque penalty ½ ρ_u Σ_j s_j u_j² scales each actuator (params.u_regularization_kind).
enum class TorqueRegularization {
  kUniform,  ///< s_j = s, the largest output curvature on u (diagonal of 𝒜ᵀW𝒜), times w_j
  /// s_j = w_j / m_j², m_j = b_jᵀ M(q) b_j [kg m²] the effective inertia of actuator j's joint (b_j: column j of B):
  /// ½ ρ_u s_j u_j² is ½ ρ_u w_j times the squared acceleration u_j alone gives that joint, the unit of the output
  /// rows. Light joints (a toe) then no longer set the penalty of heavy ones (a hip), as the uniform s does.
  kInverseJointInertia,
};

enum class ClfQpFormulation {
  kEliminateContactForces,  ///< x = [u; δ], F = A_v u + b_v (walking paper Eq. (20)-(22))
  kAugmentedInput,          ///< x = [u; F; δ] with holonomic equalities (hopping paper Eq. (45)-(51))
};

struct ClfQpParams {
  double update_period_s = 1e-3;  ///< [s] QP rate (walking [R]: 1 kHz; hopping paper: 2 kHz)
  ClfQpFormulation formulation = ClfQpFormulation::kEliminateContactForces;
  double epsilon = 0.1;            ///< ε [-] of the RES-CLF (ours; spec [R]: 0.02-0.1)
  double gamma = -1.0;             ///< γ [-]; ≤ 0: λ_min(Q)/λ_max(P) (spec [R])
  double relaxation_weight = 1e5;  ///< p [-] on ½ δ² (walking spec [R]: 1e5)
  double u_regularization = 1e-6;  ///< ρ_u [-], relative to the largest output curvature on u (ours)
  /// Ours (default kUniform, every mode): how ρ_u is spread over the actuators (see TorqueRegularization).
  TorqueRegularization u_regularization_kind = TorqueRegularization::kUniform;
  /// [-] per-actuator multipliers w_j of the torque penalty (actuator order); empty: all 1. Must be > 0.
  Eigen::VectorXd u_regularization_weights;
  /// The modes in which u_regularization_kind and u_regularization_weights apply; empty: every mode. Other modes use
  /// kUniform with w_j = 1.
  std::vector<int> u_regularization_modes;
  ContactWrenchParams contact;        ///< unilateral, friction, CoP and yaw rows per contact
  bool force_band = false;            ///< walking Eq. (25): declares the normal_force_reference input
  double force_band_halfwidth = 0.1;  ///< c [-] of Eq. (25) (walking paper: 0.1)
  /// [N] Ours (default 0, off): while a contact is loading (it was not in the mode at the previous update, or its
  /// reference did not fall since then) the band's lower edge is at least this. Without it a foot that touches down
  /// where the plan's force starts at 0 (walking: the aSLIP's F⁺ = 0 at touchdown) is held at F_z = 0 and the plant
  /// lifts it off again at once. Unloading contacts keep the band's (1 − c) F_ref, which reaches 0 at lift-off; a
  /// contact whose reference fell to 0 (to force_band_loading_fall_tolerance_N) stays unloading while it stays there
  /// (a foot the plant has not released yet: the floor would hold it for good).
  double force_band_loading_floor_N = 0.0;
  /// [N] a contact's reference counts as falling (unloading) only when it drops by more than this between two updates
  /// (ours): where the plan's force is 0 it carries solver noise of ~1e-5 N, which must not end the loading floor.
  double force_band_loading_fall_tolerance_N = 0.01;
  /// The reference load of contacts the plan loads but the current mode lacks (a late touchdown) goes to the active
  /// contacts, in proportion to their references (evenly if those are 0), so the band keeps the total (ours; off:
  /// each active contact keeps its own reference).
  bool force_band_carry_inactive = false;
  /// Ours (default off; kEliminateContactForces only): the band bounds F_z(u) + d_z, the normal force predicted at the
  /// end of the zero-order hold (d: the hold drift of predict_hold_drift), instead of F_z(u) at the solve instant. With
  /// a reference read one update period ahead (walking: WalkingDiagramParams::force_band_lead_periods) the band then
  /// holds the force the plant has when the next update samples it. The shift by d_z is at most the band's upper edge
  /// (a larger drift would ask F_z(u) < 0 against the unilateral row). Dropped with the band in fallback 1.
  bool force_band_at_hold_end = false;
  /// [N] Ours (default 0): the QP's band is this much inside Eq. (25)'s edges on each side (at most a quarter of the
  /// band's width), room for the error of the predicted force: where the QP holds a force on an edge, the plant's
  /// force there falls on either side of it by a few 10 mN. Applied before the loading floor. >= 0.
  double force_band_margin_N = 0.0;
  Eigen::VectorXd torque_limits;  ///< [N m]; empty: the model's
  /// {contact, joint}: the actuator of `joint` gets u = 0 while `contact` is active (e.g. a passive stance ankle).
  std::vector<std::pair<std::string, std::string>> zero_torque_in_contact;
  ConstrainedDynamicsParameters contact_stabilization;  ///< α, β [1/s] >= 0 (see the header)
  bool resolve_at_events = true;                        ///< also re-solve at guard events (see the header)
  EventTrigger resolve_at = EventTrigger::AnyGuard();
  QpSettings qp;  ///< DenseQpSolver tolerances (warm start on by default)
  /// Names of relative-degree-2 outputs kept out of the RES-CLF (ours; default none): such an output is tracked in the
  /// cost only, toward ÿ* = ÿ_d − Kp (y − y_d) − Kd (ẏ − ẏ_d) with its task's gains (TaskGains kp [1/s²], kd [1/s]), as
  /// in a task-space QP. When the torque or friction limits bind, the QP then trades that output's accuracy against
  /// the others' in its cost instead of spending the limits on keeping V decreasing along it.
  std::vector<std::string> cost_only_outputs;
  /// Ours (default off; kEliminateContactForces only): the contact-wrench rows of every active contact are imposed a
  /// second time on the force predicted at the end of the zero-order hold, F(u) + d, where d is how far the planned
  /// force drifted with the state over the last held sample at constant u (F(x_k, u_{k−1}) − F(x_{k−1}, u_{k−1}),
  /// scaled to one update period; 0 after a mode change). A stance force moving quickly toward the friction-pyramid
  /// edge keeps that margin over the hold, since the plant sees the held u, not the QP's solve instant.
  /// A contact whose band the force_band releases within the hold (its upper edge is 0, to
  /// force_band_loading_fall_tolerance_N: the plan lifts it off) gets
  /// none of these rows: the band already takes its F_z to 0 by the hold's end and the plant releases it before then,
  /// while a whole wrench of 0 at the hold's end is more than a drift outside the cone allows.
  bool predict_hold_drift = false;
  /// [s] Ours (default 0): predict_hold_drift's rows take no drift (d = 0, the rows as at the solve instant) until
  /// this long after the mode began (its first solve there, or the first solve of all): on a plant whose impacts last
  /// several steps (Bullet), the
  /// states right after a touchdown still move with the impact, and their difference is no hold drift.
  double hold_drift_settle_s = 0.0;
  /// Ours (default off): the cost of every relative-degree-2 CLF output targets ÿ* = ÿ_d − Kp (y − y_d) − Kd (ẏ − ẏ_d)
  /// with its task's gains (as the task-space QP's cost) instead of ÿ_d. With ÿ_d alone, an output's cost weight makes
  /// correcting its error expensive, so the CLF row decreases V through the cheapest outputs; with the PD target the
  /// weight ranks the outputs as in a task-space QP, and the CLF row still bounds V̇.
  bool cost_pd_feedback = false;
  /// [-] the CLF row counts as active on the clf_activity port when δ > 0 or its slack u₀ − a₀ᵀx, in the row's
  /// normalisation (see the header), is at most this (ours; DenseQpSolver's feasibility tolerance is 1e-9)
  double clf_active_tolerance = 1e-7;
  /// Ours (off by default): rows that brake each joint before its URDF position limit (joint_limit_brake.h); dropped
  /// with the force band in fallback 1.
  JointLimitBrakeParams joint_limit_brake;
};

/// What a ClfQpController reports about its updates (output port "diagnostics", ClfQpController::diagnostics). The
/// counts run over the updates since the context was created.
struct ClfQpDiagnostics {
  double V = 0.0;                     ///< V_ε(η) at the last solved update [-]
  double delta = 0.0;                 ///< the CLF relaxation δ of the last solved update [-]
  int qp_failures = 0;                ///< updates whose first QP failed (each then took a fallback)
  std::optional<QpStatus> qp_status;  ///< the last update's final solve; empty before the first update
  int drift_dropped = 0;              ///< updates re-solved without the hold-drift rows (fallback 0)
  int band_dropped = 0;               ///< updates re-solved without the force band and hold-drift rows (fallback 1)
  int cop_dropped = 0;                ///< updates re-solved also without the centre-of-pressure rows (fallback 2)
  int held = 0;                       ///< updates that held the previous u (fallback 3)
  int clf_active = 0;                 ///< solved updates whose solution has the CLF row active (see clf_activity)
  int solved = 0;                     ///< updates solved (kOptimal)
  double solve_time_s = 0.0;          ///< wall time of the last update [s]
};

class ClfQpController final : public QpControllerSystem {
 public:
  ClfQpController(std::string name, std::shared_ptr<const MultibodyModel> model, std::vector<ContactSet> mode_contacts,
                  std::vector<ClfOutput> outputs, ClfQpParams params = {});

  const MultibodyModel& model() const { return *model_; }
  const ClfQpParams& params() const { return params_; }
  int num_outputs() const { return ny_; }
  int output_offset(int i) const { return offsets_.at(i); }
  /// P_ε, F, G and γ/ε of the RES-CLF of mode `mode` (outputs active there).
  const Eigen::MatrixXd& P_epsilon(int mode) const { return clf_.at(mode).P_epsilon; }
  double convergence_rate(int mode) const { return clf_.at(mode).convergence_rate; }

  /// Builds and solves the QP at the context's inputs (no fallback), without touching the discrete state.
  QpStatus SolveQp(const LeafContext& context) const;
  /// The QP of the last solve (data and solution) and its layout.
  const DenseQpSolver& last_qp(const LeafContext& context) const;
  int last_mode(const LeafContext& context) const;
  /// After SolveQp: η, the output Jacobian 𝒜 and drift L_f over the decision variables (rows: active RD1 rows, then
  /// active RD2 rows, then active cost-only rows), for checks of V̇ = L_F V + L_G V (𝒜 x + L_f).
  const Eigen::VectorXd& last_eta(const LeafContext& context) const;
  Eigen::Ref<const Eigen::MatrixXd> last_output_matrix(const LeafContext& context) const;
  Eigen::Ref<const Eigen::VectorXd> last_output_drift(const LeafContext& context) const;
  /// The planned contact forces of the last solve, stacked in contact_dynamics.h row order (active contacts, loops).
  Eigen::Ref<const Eigen::VectorXd> last_constraint_forces(const LeafContext& context) const;

  /// The diagnostics after the last update in `context` (the "diagnostics" output's value).
  ClfQpDiagnostics diagnostics(const LeafContext& context) const;

  struct Scratch;

 private:
  // Discrete state: [u (nu); contact_forces (3 nc); one slot per DiagnosticsSlot, in this order].
  enum DiagnosticsSlot {
    kV,
    kDelta,
    kFailures,
    kStatus,
    kDriftDropped,
    kBandDropped,
    kCopDropped,
    kHeld,
    kSolveTime,
    kClfActive,
    kSolved,
    kNumSlots
  };
  int u_offset() const { return 0; }
  int forces_offset() const { return model_->nu(); }
  int slot(DiagnosticsSlot k) const { return forces_offset() + 3 * model_->num_contacts() + k; }

  std::any AllocateScratch() const override;
  EventStatus Update(const LeafContext& context, Eigen::VectorXd* next) const;
  int ModeFromInput(const LeafContext& context) const;
  void SetRowsEnabled(const LeafContext& context, bool drift, bool band, bool cop) const;
  // SolveQp's stages, in call order, on the QP of mode `mode` in `s`.
  /// M⁻¹ B, q̈0 and the constraint rows (A_v, b_v or the equalities); the number of constraint rows, −1 if Λ is
  /// singular.
  int CalcConstrainedDynamics(const LeafContext& context, const VectorRef& q, const VectorRef& v, bool same_mode,
                              Scratch& s, int mode) const;
  /// η and the output rows 𝒜, L_f, W of Eq. (24); returns the curvature scale of the torque penalty.
  double CalcOutputRows(const VectorRef& q, const VectorRef& v, const Eigen::VectorXd& desired, int rows, Scratch& s,
                        int mode) const;
  /// H and g; false if an actuator's effective inertia is not positive (kInverseJointInertia).
  bool FillCost(const VectorRef& q, double reg_scale, int rows, Scratch& s, int mode) const;
  /// Row 0: the CLF row of Eq. (36)-(37), normalised (free when no CLF output is active).
  void FillClfRow(Scratch& s, int mode) const;
  /// The contact-wrench rows, their hold-drift copies and the force band of every active contact.
  void FillWrenchRows(const LeafContext& context, const VectorRef& q, Scratch& s, int mode) const;
  /// The force band of active contact k [N]: its reference F_ref (with its share of the inactive contacts' load,
  /// force_band_carry_inactive) and the band's edges on F_z after the margin and the loading floor.
  struct Band {
    double reference = 0.0, lower = 0.0, upper = 0.0;
    bool loading = false;  ///< the loading floor's condition (force_band_loading_floor_N)
  };
  /// The band row of active contact k: `band` on F_z(u) (+ d_z with force_band_at_hold_end).
  void FillForceBandRow(const Band& band, int k, Scratch& s, int mode) const;
  Band BandOf(const Eigen::VectorXd& force_ref, int k, double active_ref, double inactive_ref, const Scratch& s,
              int mode) const;
  /// The planned constraint forces F of the solution (the first `rows` entries of the mode's F).
  void StorePlannedForces(int rows, Scratch& s, int mode) const;

  std::shared_ptr<const MultibodyModel> model_;
  std::vector<ContactSet> mode_contacts_;
  std::vector<ClfOutput> outputs_;
  std::vector<bool> cost_only_;  // per output: params.cost_only_outputs names it
  ClfQpParams params_;
  std::vector<int> offsets_;
  int ny_ = 0;
  Eigen::VectorXd u_max_;
  std::vector<std::vector<int>> zero_torque_;
  JointLimitBrake brake_;
  struct ModeClf {
    Eigen::MatrixXd P_epsilon, F, G;
    double convergence_rate = 0;
  };
  std::vector<ModeClf> clf_;
  int state_port_ = -1, mode_port_ = -1, desired_port_ = -1, force_ref_port_ = -1;
};

}  // namespace rome
