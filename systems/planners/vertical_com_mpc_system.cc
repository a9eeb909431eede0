#include "systems/planners/vertical_com_mpc_system.h"

#include <cmath>

namespace rome {

VerticalComMpcSystem::VerticalComMpcSystem(std::string name, VerticalComMpcSystemParams params)
    : LeafSystem(std::move(name)), params_(params) {
  if (!(params_.control_period_s > 0 && std::isfinite(params_.control_period_s)))
    ThrowError("parameter control_period_s must be positive (s), got " + std::to_string(params_.control_period_s));
  if (!(params_.hold_plan_below_horizon_s >= 0 && std::isfinite(params_.hold_plan_below_horizon_s)))
    ThrowError("parameter hold_plan_below_horizon_s must be finite and >= 0 (s), got " +
               std::to_string(params_.hold_plan_below_horizon_s));
  VerticalComMpc check(params_.mpc);  // validates the MPC parameters at construction
  const int N = params_.mpc.horizon_steps;
  state_port_ = DeclareInputPort("com_vertical_state", 2);
  target_port_ = DeclareInputPort("target", 3);
  Eigen::VectorXd xd = Eigen::VectorXd::Zero(kInputs + N);
  xd[kPlanDt] = params_.mpc.min_horizon_s / N;
  xd[kLastStatus] = static_cast<double>(QpStatus::kInvalidInput);  // no solve yet
  DeclareDiscreteState(xd);
  DeclarePeriodicDiscreteUpdate(params_.control_period_s, 0.0,
                                [this](const LeafContext& c, Eigen::VectorXd* next) { return Update(c, next); });
  if (params_.resolve_at_events)
    DeclareEventUpdate(
        "resolve_mpc", EventTrigger::AnyGuard(),
        [this](const LeafContext& c, const EventRecord&, State* next) { return Update(c, &next->discrete); });
  DeclareOutputPort(
      "com_height_desired", 3,
      [N](const LeafContext& c, Eigen::VectorXd* y) {
        const Eigen::VectorXd& xd = c.discrete_state();
        *y = VerticalComMpc::EvaluatePlan(xd[kPlanPosition], xd[kPlanVelocity], xd.segment(kInputs, N), xd[kPlanDt],
                                          c.time() - xd[kPlanTime]);
      },
      Feedthrough::None());
  DeclareOutputPort(
      "planned_inputs", N,
      [N](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment(kInputs, N); },
      Feedthrough::None());
  DeclareOutputPort(
      "qp_failures", 1, [](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[kFailures]; },
      Feedthrough::None());
  DeclareOutputPort(
      "terminal_relaxations", 1,
      [](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[kRelaxations]; },
      Feedthrough::None());
  DeclareOutputPort(
      "qp_status", 1, [](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[kLastStatus]; },
      Feedthrough::None());
}

EventStatus VerticalComMpcSystem::Update(const LeafContext& context, Eigen::VectorXd* next) const {
  VerticalComMpc& mpc = *context.scratch<std::shared_ptr<VerticalComMpc>>();
  const Eigen::VectorXd& z = EvalInput(context, state_port_);
  const Eigen::VectorXd& target = EvalInput(context, target_port_);
  if (params_.hold_plan_below_horizon_s > 0 && mpc.has_plan() && target[2] < params_.hold_plan_below_horizon_s)
    return EventStatus::Succeeded();  // hold: the previous plan continues in time
  const QpStatus status = mpc.Solve(z[0], z[1], target[0], target[1], target[2]);
  Eigen::VectorXd& xd = *next;
  xd[kLastStatus] = static_cast<double>(status);
  xd[kSolves] += 1;
  if (status != QpStatus::kOptimal) {
    xd[kFailures] += 1;  // keep the previous plan (documented fallback)
    return EventStatus::Succeeded();
  }
  if (mpc.terminal_relaxed()) xd[kRelaxations] += 1;
  xd[kPlanTime] = context.time();
  xd[kPlanPosition] = z[0];
  xd[kPlanVelocity] = z[1];
  xd[kPlanDt] = mpc.dt();
  xd.segment(kInputs, mpc.horizon_steps()) = mpc.inputs();
  return EventStatus::Succeeded();
}

}  // namespace rome
