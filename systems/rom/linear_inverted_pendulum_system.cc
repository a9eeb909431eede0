#include "systems/rom/linear_inverted_pendulum_system.h"

namespace rome {

LinearInvertedPendulumSystem::LinearInvertedPendulumSystem(std::string name, LinearInvertedPendulumSystemParams params)
    : LeafSystem(std::move(name)), lip_(params.lip) {
  DeclareContinuousState(Eigen::Vector2d(params.initial_x, params.initial_L));
  DeclareOutputPort(
      "state", 2, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  DeclareOutputPort(
      "orbital_energy", 1,
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        (*y)[0] = lip_.OrbitalEnergy(c.continuous_state().head<2>());
      },
      Feedthrough::None());
}

void LinearInvertedPendulumSystem::DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  // Eq. (12).
  xdot->head<2>() = lip_.Derivative(context.continuous_state().head<2>());
}

}  // namespace rome
