#pragma once
// VerticalComMpcSystem: VerticalComMpc (stepping-stones paper, Eq. (28)) re-solved at the control rate.
// General, not the stepping-stones diagram's own: a double-integrator COM-height MPC to a target height and speed at
// a predicted time, with no robot and no contact mode.
//
// inputs:  com_vertical_state (2) = [p^z (m), ṗ^z (m/s)] measured COM height/velocity (same frame as the target;
//                                   relative to the stance foot in the paper)
//          target (3)             = [p_comf^{z,d} (m), u_des (m/s), T̂_s (s)] (MomentumRegulationPlannerSystem's
//                                   'vertical_com_target', Eq. (26)-(27))
// discrete state (8 + N): [t_plan (s), p_plan (m), v_plan (m/s), dt (s), last QP status (QpStatus as a number),
//                          QP failures, QP solves, terminal relaxations, u_0..u_{N−1} (m/s²)] — the plan that started
//                          at t_plan from the measured state (p_plan, v_plan).
// periodic update (period = params.control_period_s, offset 0): solve Eq. (28) from the measured state
//          (warm-started QP, no heap allocation). If the terminal equality is infeasible the weighted terminal
//          cost is used instead (VerticalComMpcParams::relax_terminal_on_infeasible; counted in
//          'terminal_relaxations'). On QP failure (any status other than kOptimal, including
//          non-finite inputs) the previous plan is kept and continues in time (the "shifted" plan: at time t it
//          is evaluated at t − t_plan), and the failure counter is incremented.
// event update (params.resolve_at_events, default on): the same solve at every guard event of the diagram, right
//          after the resets, so that after an impact the plan starts from the state measured about the new stance
//          foot at the impact instant (not one period later).
// outputs (no direct feedthrough):
//          com_height_desired (3) = [p^{z,d} (m), ṗ^{z,d} (m/s), p̈^{z,d} (m/s²)] = the plan at the current time.
//                                   Right after a solve this is [measured p^z, measured ṗ^z, u_0^z]: as in the
//                                   paper (Fig. 5), the MPC effectively commands the acceleration u_0^z.
//                                   With hold_plan_below_horizon_s > 0, the last plan is held once T̂_s drops
//                                   below it (see the parameter).
//          planned_inputs (N)     = u_0..u_{N−1} (m/s²)
//          qp_failures (1)        = number of failed solves so far
//          qp_status (1)          = status of the last solve (0 = kOptimal; see QpStatus)
//          terminal_relaxations (1) = number of solves that fell back to the weighted terminal cost

#include <memory>
#include <string>

#include "framework/system.h"
#include "systems/planners/vertical_com_mpc.h"

namespace rome {

struct VerticalComMpcSystemParams {
  VerticalComMpcParams mpc{};
  /// [s] period of the re-solve. The paper runs its QP controller at 1 kHz and updates u_des "constantly";
  /// we re-solve at the same 1 kHz.
  double control_period_s = 1e-3;
  /// [s] When the predicted time to impact T̂_s (target[2]) is below this and a plan exists, the update does not
  /// re-solve: the previous plan continues in time (the controller's PD on p^{z,d}, ṗ^{z,d} then tracks it).
  /// Ours; 0 = re-solve at every update as in the paper. Why: dt = T̂_s/N shrinks with T̂_s, so in the last
  /// few tens of milliseconds the re-solved plan turns into a deadbeat law whose accelerations grow like 1/T̂_s²
  /// for any small tracking error, up to the bound −g and beyond it in the relaxed QP (hundreds of m/s²).
  double hold_plan_below_horizon_s = 0.0;
  /// Re-solve at every guard event as well (ours): the measured state jumps at an impact (new stance foot).
  bool resolve_at_events = true;
};

class VerticalComMpcSystem final : public LeafSystem {
 public:
  // Indices into the discrete state.
  static constexpr int kPlanTime = 0, kPlanPosition = 1, kPlanVelocity = 2, kPlanDt = 3, kLastStatus = 4, kFailures = 5,
                       kSolves = 6, kRelaxations = 7, kInputs = 8;

  explicit VerticalComMpcSystem(std::string name = "vertical_com_mpc", VerticalComMpcSystemParams params = {});
  const VerticalComMpcSystemParams& params() const { return params_; }
  int horizon_steps() const { return params_.mpc.horizon_steps; }
  /// The MPC workspace of a context (for inspection in tests).
  const VerticalComMpc& workspace(const LeafContext& context) const {
    return *context.scratch<std::shared_ptr<VerticalComMpc>>();
  }

 protected:
  std::any AllocateScratch() const override { return std::make_shared<VerticalComMpc>(params_.mpc); }

 private:
  EventStatus Update(const LeafContext& context, Eigen::VectorXd* next) const;
  VerticalComMpcSystemParams params_;
  int state_port_, target_port_;
};

}  // namespace rome
