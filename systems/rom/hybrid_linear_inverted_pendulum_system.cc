#include "systems/rom/hybrid_linear_inverted_pendulum_system.h"

#include <cmath>
#include <sstream>

namespace rome {

HybridLinearInvertedPendulumSystem::HybridLinearInvertedPendulumSystem(std::string name,
                                                                       HybridLinearInvertedPendulumSystemParams params)
    : LeafSystem(std::move(name)), params_(params), hlip_(params.hlip) {
  if (!(params_.mass > 0) || !(params_.initial_stance_side == 1.0 || params_.initial_stance_side == -1.0)) {
    std::ostringstream msg;
    msg << "parameters mass must be > 0 kg and initial_stance_side +1 or -1, got " << params_.mass << " and "
        << params_.initial_stance_side;
    ThrowError(msg.str());
  }
  const HybridLinearInvertedPendulumParams& h = hlip_.params();
  DeclareModes({"single_support", "double_support"},
               params_.start_in_single_support ? single_support_mode() : double_support_mode());
  step_port_ = DeclareInputPort("step", 1);
  if (params_.footed) torque_port_ = DeclareInputPort("ankle_roll_torque", {"left", "right"});
  DeclareContinuousState(Eigen::VectorXd(params_.initial_state));
  const double first_switch = params_.start_in_single_support ? h.ssp_duration : h.dsp_duration;
  DeclareDiscreteState(Eigen::Vector4d(first_switch, params_.initial_stance_foot_y, params_.initial_stance_side, 0.0));
  DeclareOutputPort(
      "state", {"y", "ydot"}, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); },
      Feedthrough::None());
  DeclareOutputPort(
      "com_y", {"y", "ydot"},
      [](const LeafContext& c, Eigen::VectorXd* y) {
        *y = c.continuous_state();
        (*y)(0) += c.discrete_state()(1);
      },
      Feedthrough::None());
  DeclareGuard(
      "domain_switch", kAllModes, [](const LeafContext& c) { return c.time() - c.discrete_state()(0); },
      CrossingDirection::kRising,
      [this, h](const LeafContext& c, int, State* next) {
        const bool to_single = c.mode() == double_support_mode() || h.dsp_duration == 0.0;
        if (!to_single) {  // Eq. (6)
          next->mode = double_support_mode();
          next->discrete(0) += h.dsp_duration;
          return EventStatus::Succeeded();
        }
        const double w = EvalInput(c, step_port_)[0];
        if (!std::isfinite(w)) return EventStatus::Failed("input 'step' is not finite at the DSP→SSP switch");
        next->continuous(0) -= w;  // Eq. (7)
        next->discrete(0) += h.ssp_duration;
        next->discrete(1) += w;
        next->discrete(2) = -next->discrete(2);
        next->discrete(3) += 1;
        next->mode = single_support_mode();
        return EventStatus::Succeeded();
      });
}

void HybridLinearInvertedPendulumSystem::DoCalcTimeDerivatives(const LeafContext& context,
                                                               Eigen::VectorXd* xdot) const {
  const Eigen::VectorXd& x = context.continuous_state();
  const bool single = context.mode() == single_support_mode();
  double accel = single ? hlip_.lambda() * hlip_.lambda() * x(0) : 0.0;
  if (params_.footed) {
    const Eigen::VectorXd& u = EvalInput(context, torque_port_);
    const double mz = params_.mass * hlip_.params().z0;
    if (single) {
      accel += (context.discrete_state()(2) > 0 ? u(0) : u(1)) / mz;
    } else {
      accel += (u(0) + u(1)) / mz;
    }
  }
  (*xdot)(0) = x(1);
  (*xdot)(1) = accel;
}

}  // namespace rome
