#include "systems/rom/stepping_linear_inverted_pendulum.h"

#include <cmath>
#include <string>

namespace rome {

SteppingLinearInvertedPendulum::SteppingLinearInvertedPendulum(std::string name,
                                                               SteppingLinearInvertedPendulumParams params)
    : LeafSystem(std::move(name)), params_(params), lip_(params.lip) {
  if (!(params_.impact_fraction > 0 && params_.impact_fraction <= 1)) {
    ThrowError("parameter impact_fraction (ε) must be in (0, 1], got " + std::to_string(params_.impact_fraction));
  }
  step_port_ = DeclareInputPort("step", 2);
  u_port_ = DeclareInputPort("impact_vertical_velocity", 1);
  DeclareContinuousState(Eigen::Vector2d(params_.initial_x, params_.initial_L));
  DeclareDiscreteState(Eigen::Vector3d::Zero());
  DeclareOutputPort(
      "state", 2, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  DeclareOutputPort(
      "com_state", 4,
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const Eigen::Vector2d step = Step(c);
        const double slope = step[1] / step[0], x = c.continuous_state()[0],
                     xdot = lip_.ForwardVelocity(c.continuous_state()[1]);
        *y << x, slope * x + lip_.z0(), xdot, slope * xdot;
      },
      Feedthrough::From({step_port_}));
  DeclareOutputPort(
      "stance_foot", 2, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().head<2>(); },
      Feedthrough::None());
  DeclareOutputPort(
      "orbital_energy", 1,
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        (*y)[0] = lip_.OrbitalEnergy(c.continuous_state().head<2>());
      },
      Feedthrough::None());
  DeclareGuard(
      "touchdown", /*mode=*/0,
      [this](const LeafContext& c) { return c.continuous_state()[0] - params_.impact_fraction * Step(c)[0]; },
      CrossingDirection::kRising,
      [this](const LeafContext& c, int, State* next) {
        const Eigen::Vector2d step = Step(c);
        const double l = step[0], h = step[1];
        const double u = EvalInput(c, u_port_)[0];
        if (!std::isfinite(u))
          return EventStatus::Failed("input 'impact_vertical_velocity' is not finite at touchdown");
        const double L_minus = next->continuous[1];
        // Eq. (17).
        next->continuous[0] -= l;
        next->continuous[1] = L_minus + l * u - h * lip_.ForwardVelocity(L_minus);
        next->discrete[0] += l;
        next->discrete[1] += h;
        next->discrete[2] += 1;
        return EventStatus::Succeeded();
      });
}

Eigen::Vector2d SteppingLinearInvertedPendulum::Step(const LeafContext& context) const {
  const Eigen::VectorXd& step = EvalInput(context, step_port_);
  if (!(step[0] > 0 && std::isfinite(step[0]) && std::isfinite(step[1]))) {
    ThrowError("input 'step' must hold a positive finite step length l_des and a finite h_des, got [" +
               std::to_string(step[0]) + ", " + std::to_string(step[1]) + "]");
  }
  return step.head<2>();
}

void SteppingLinearInvertedPendulum::DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  xdot->head<2>() = lip_.Derivative(context.continuous_state().head<2>());  // Eq. (12)
}

}  // namespace rome
