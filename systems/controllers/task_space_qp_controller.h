#pragma once
// TaskSpaceQpController: task-space (TSC) QP controller of the stepping-stones paper, Sec. V, Eq. (29)–(31).
//
// inputs:  state (nq + nv)           [q; v] of the plant (HybridContactPlant "state"); any base (nq = nv + 1 on
//                                    the quaternion free-flyer, v its twist: free_flyer.h)
//          mode (int, typed)         index of the plant's active contact mode (HybridContactPlant "mode")
//          desired (3 ny)            [y_d; ẏ_d; ÿ_d], each ny = Σ task sizes, tasks in construction order
//                                    (units of each task: m, rad; m/s, rad/s; m/s², rad/s²). Rows of tasks that
//                                    are inactive in the current mode are ignored.
// outputs: u (nu)                    actuator torques [N m], zero-order held between updates (no feedthrough)
//          qdd (nv)                  the QP's planned generalized acceleration q̈ [m/s², rad/s²]
//          contact_forces (3 nc)     the QP's planned ground force on each contact [N], world axes, zero when
//                                    the contact is inactive (same layout as the plant's "contact_forces")
//          qp_failures (1)           number of updates whose QP failed so far [-]
//          qp_status (1)             QpStatus of the last update as an integer (0 = kOptimal; dense_qp_solver.h)
//          solve_time_s (1)          wall time of the last update [s] (QP assembly and solve; steady_clock)
//          diagnostics (TaskSpaceQpDiagnostics, typed)  the three above, the fallback counts and the task cost, by name
// discrete state: [u (nu); qdd (nv); contact_forces (3 nc); the diagnostics] (read them with diagnostics(), not by
// offset), updated periodically
// (params.update_period_s, 1 kHz as in the paper) and, by an event update, at every guard event that
// params.resolve_at selects (default: every guard event of the diagram), so that at a touchdown or lift-off the
// torque of the new contact mode acts from the event instant on (no torque computed for the previous mode is held
// into the new one). Every output reads only the discrete state.
//
// Formulation (TSID style). The paper eliminates q̈ and F and optimises u alone (q̈ = A_q u + b_q); we keep
// x = [q̈ (nv); u (nu); F (rows)] with the dynamics as equalities, which is the same QP in a sparser, better
// conditioned form (no M⁻¹), and gives q̈ and F directly:
//   minimise   Σ_tasks w_i ||J_i q̈ + J̇_i q̇ − ÿ*_i||²  +  s (ρ_q̈ ||q̈||² + ρ_u ||u||² + ρ_F ||F||²)  (Eq. (30))
//              ÿ*_i = ÿ_d + Kp (y_d − y) + Kd (ẏ_d − J_i q̇)                       (PD output dynamics)
//   subject to M q̈ + h = B u + τ_spring + J_cᵀ F                                   (Eq. (3) of the paper)
//              J_c q̈ + J̇_c q̇ = −2α J_c q̇ − β² φ                                 (stance contact and loop closures,
//                                                                                α, β from
//                                                                                params.contact_stabilization: pass the
//                                                                                plant's, so that the QP's forces are
//                                                                                the plant's; α = β = 0 is the paper's
//                                                                                J_c q̈ + J̇_c q̇ = 0)
//              F_z ≥ F_min, |F_x| ≤ μ F_z (|F_y| too for 3D point feet)          (GRF, Eq. (31))
//              line/flat planar foot [τ_y, F_x, F_z]: CoP inside the foot, x_min F_z ≤ −τ_y ≤ x_max F_z
//              −u_max ≤ u ≤ u_max                                                 (torque limit, Eq. (31))
//              u_j = 0 for the joints listed with an active contact                (e.g. Cassie's stance toe)
// J_c stacks the active contacts of the mode and every loop closure (contact_dynamics.h row order); loop-closure
// forces are free. The point-foot stance ankle torque is zero by construction (there is no ankle actuator).
// One DenseQpSolver per contact mode (sized for that mode) lives in the context scratch and is warm-started
// from its previous active set; an update allocates no heap memory.
//
// On QP failure (infeasible, iteration limit) the default policy (QpFailurePolicy::kRelaxContactForces) solves the
// same QP once more without the GRF rows (unilateral, friction, CoP), keeping the dynamics, the contact
// accelerations and the torque limits: the robot gets the best torques its actuators can give, and the plant
// then decides, through its own lift-off and slip physics, what the contact really does. Whenever the first QP
// fails, qp_failures is incremented and qp_status records its status (so a relaxed solve is never silent); if the
// relaxed QP fails too, the update holds the previous u (and q̈, F) and qp_status records that second status.
// kHoldPrevious skips the relaxed solve; kZeroTorque outputs u = 0. The caller decides whether failures end the
// run (e.g. a monitor on qp_failures). Bad data (a NaN in the state, a wrong mode) ends the run with an error.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "framework/system.h"
#include "systems/controllers/controller_setup.h"
#include "solvers/qp/dense_qp_solver.h"
#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/contact_dynamics.h"

namespace rome {

class HybridContactPlant;

enum class QpFailurePolicy {
  kRelaxContactForces,  ///< re-solve without the GRF inequality rows, then hold the previous u (the default)
  kHoldPrevious,        ///< keep the previous update's u
  kZeroTorque,          ///< output u = 0
};

struct TaskSpaceQpParams {
  double update_period_s = 1e-3;  ///< [s] QP rate (the paper solves its low-level QP at 1 kHz).
  // Regularisation weights are relative: each is multiplied by the largest diagonal entry s of J_yᵀ W J_y, so the
  // QP stays well conditioned for any task weights. They bias task accelerations that the robot could meet exactly
  // by about ρ s |u| / (w |∂ÿ/∂u|²); the PD loop turns that into a steady output error of bias / Kp (measured on
  // AMBER with the defaults: below 1e-4 m). Keep them ≥ 1e-7: DenseQpSolver treats pivots < 1e-8 max H_jj as singular.
  double qdd_regularization = 1e-6;    ///< ρ_q̈ [s⁴/m² relative] on ||q̈||².
  double u_regularization = 1e-6;      ///< ρ_u [1/(N m)² relative] on ||u||² (picks the least-torque solution).
  double force_regularization = 1e-6;  ///< ρ_F [1/N² relative] on ||F||² (internal forces in double support).
  double min_normal_force_N = 0.0;     ///< [N] F_z ≥ this on every active contact (unilateral contact).
  double friction_coefficient = -1.0;  ///< [-] μ of the friction pyramid; < 0 uses each contact's model value.
  /// [-] the pyramid uses friction_margin · μ (1 = the paper's cone; < 1 keeps the plant's forces, which drift over a
  /// zero-order-held sample, inside the true cone).
  double friction_margin = 1.0;
  /// [N] the pyramid's apex is shifted up to F_z = this: |F_t| ≤ μ' (F_z − offset) (ContactWrenchParams' row of the
  /// CLF-QP). A foot about to lift off then keeps |F_t|/F_z well inside μ while the plant's forces drift over a held
  /// sample, where a pyramid through the origin allows μ' at any load. 0: the paper's cone.
  double friction_cone_offset_N = 0.0;
  /// Ours (default off): the GRF rows (normal-force floor, friction pyramid, CoP) of every active contact also hold for
  /// the force predicted at the end of the zero-order hold, F + d, where d is how far the plant's force moved with the
  /// state over the last held sample at constant u (F(x_k, u_{k−1}) − F(x_{k−1}, u_{k−1}), from the constrained forward
  /// dynamics, scaled to one update period; 0 after a mode change or a held update), as ClfQpParams::
  /// predict_hold_drift. The rows are tightened, never loosened: each bound is the stricter of the two.
  bool predict_hold_drift = false;
  Eigen::VectorXd torque_limits;  ///< [N m] per actuator; empty = the model's torque limits.
  /// α [1/s] on contact and loop-closure velocities, β [1/s] on loop-closure position errors φ: the same struct the
  /// plant integrates with (HybridContactPlantParams::dynamics), so the planned forces are the forces the plant
  /// applies. Default: the plant's default (α = β = 10 1/s; ours); the paper's J_c q̈ + J̇_c q̇ = 0 is α = β = 0.
  ConstrainedDynamicsParameters contact_stabilization;
  /// Re-solve at guard events (touchdown, lift-off) as well as periodically, so the new mode's torque acts from the
  /// event on. false reproduces a plain 1 kHz zero-order hold (the previous mode's torque is held until the next
  /// sample).
  bool resolve_at_events = true;
  EventTrigger resolve_at = EventTrigger::AnyGuard();  ///< which guard events re-solve the QP
  /// {contact, joint}: the actuator on `joint` gets u = 0 while `contact` is active (the paper zeroes Cassie's
  /// stance toe torque). Empty for point-foot robots.
  std::vector<std::pair<std::string, std::string>> zero_torque_in_contact;
  QpFailurePolicy failure_policy = QpFailurePolicy::kRelaxContactForces;
  QpSettings qp;  ///< DenseQpSolver tolerances (warm start on by default).
};

/// What a TaskSpaceQpController reports about its updates (output port "diagnostics",
/// TaskSpaceQpController::diagnostics). The counts run over the updates since the context was created; each update is
/// counted in exactly one of solved, relaxed and held.
struct TaskSpaceQpDiagnostics {
  int qp_failures = 0;  ///< updates whose first QP failed (relaxed + held)
  /// The last update's first solve, or the relaxed solve's when that failed too; empty before the first update.
  std::optional<QpStatus> qp_status;
  int solved = 0;   ///< updates whose first QP solved (kOptimal)
  int relaxed = 0;  ///< updates that used the relaxed QP's answer (QpFailurePolicy::kRelaxContactForces)
  int held = 0;     ///< updates that used no QP answer (held the previous u, or zero torque under kZeroTorque)
  /// [w (m/s²)², w (rad/s²)²] ½ Σ_i w_i ||J_i q̈ + J̇_i q̇ − ÿ*_i||² at the last used answer (Eq. (30)'s task terms, no
  /// regularisation; ≥ 0, 0 when every active task is met exactly).
  double task_cost = 0.0;
  double solve_time_s = 0.0;  ///< wall time of the last update [s]
};

class TaskSpaceQpController final : public QpControllerSystem {
 public:
  /// `mode_contacts[m]`: the contacts active in the plant's mode m (see ActiveContactsPerMode). Tasks are
  /// stacked in the given order in the desired port.
  TaskSpaceQpController(std::string name, std::shared_ptr<const MultibodyModel> model,
                        std::vector<ContactSet> mode_contacts, std::vector<std::shared_ptr<const TaskSpaceTask>> tasks,
                        TaskSpaceQpParams params = {});

  const MultibodyModel& model() const { return *model_; }
  const TaskSpaceQpParams& params() const { return params_; }
  const std::vector<std::shared_ptr<const TaskSpaceTask>>& tasks() const { return tasks_; }
  /// ny: total size of the stacked task outputs.
  int num_task_outputs() const { return ny_; }
  /// Offset of task `i` in the stacked outputs (and in each third of the desired port).
  int task_offset(int i) const { return task_offsets_.at(i); }
  const Eigen::VectorXd& torque_limits() const { return u_max_; }

  /// Builds and solves the QP at the context's inputs, without touching the discrete state (the periodic
  /// update calls this). Throws std::runtime_error naming the port for a bad mode input.
  QpStatus SolveQp(const LeafContext& context) const;
  /// Re-solves the QP last built by SolveQp without its GRF inequality rows and normal-force bounds (dynamics,
  /// contact accelerations and torque limits kept), then restores those rows for the next update.
  QpStatus SolveRelaxedQp(const LeafContext& context) const;
  /// The diagnostics after the last update in `context` (the "diagnostics" output's value).
  TaskSpaceQpDiagnostics diagnostics(const LeafContext& context) const;
  /// The QP solved last in `context` (data, solution, multipliers) and its layout: x = [q̈; u; F].
  const DenseQpSolver& last_qp(const LeafContext& context) const;
  int last_mode(const LeafContext& context) const;
  /// Number of constraint force rows F in the last QP (active contacts of its mode + loop closures).
  int last_num_force_rows(const LeafContext& context) const;

  struct Scratch;

 private:
  // Discrete state: [u (nu); qdd (nv); contact_forces (3 nc); one slot per DiagnosticsSlot, in this order].
  enum DiagnosticsSlot { kFailures, kStatus, kSolveTime, kSolved, kRelaxed, kHeld, kTaskCost, kNumSlots };
  int u_offset() const { return 0; }
  int qdd_offset() const { return model_->nu(); }
  int forces_offset() const { return model_->nu() + model_->nv(); }
  int slot(DiagnosticsSlot k) const { return forces_offset() + 3 * model_->num_contacts() + k; }
  /// ½ Σ w ||J q̈ + J̇ q̇ − ÿ*||² of the last SolveQp's tasks at `qdd`.
  double TaskCost(Scratch& s, const Eigen::Ref<const Eigen::VectorXd>& qdd) const;

  std::any AllocateScratch() const override;
  EventStatus Update(const LeafContext& context, Eigen::VectorXd* next) const;
  int ModeFromInput(const LeafContext& context) const;
  /// d of params.predict_hold_drift for `mode` at (q, v) (zero when unavailable); uses the scratch workspace.
  void CalcHoldDrift(const LeafContext& context, int mode, const VectorRef& q, const VectorRef& v) const;
  /// The GRF rows' bounds of `mode` (apex offset, normal-force floor, CoP), tightened by the hold drift.
  void SetContactRowBounds(Scratch& s, int mode) const;

  std::shared_ptr<const MultibodyModel> model_;
  std::vector<ContactSet> mode_contacts_;
  std::vector<std::shared_ptr<const TaskSpaceTask>> tasks_;
  TaskSpaceQpParams params_;
  std::vector<int> task_offsets_;
  int ny_ = 0;
  Eigen::VectorXd u_max_;
  std::vector<std::vector<int>> zero_torque_;  // per mode: actuator indices forced to 0
  int state_port_ = -1, mode_port_ = -1, desired_port_ = -1;
};

}  // namespace rome
