#include "systems/rom/spring_mass_system.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rome {

SpringMassSystem::SpringMassSystem(std::string name, SpringMassSystemParams params)
    : LeafSystem(std::move(name)), model_(params.model) {
  static constexpr const char* kElements[4] = {"x [m]", "xdot [m/s]", "L [m]", "Ldot [m/s]"};
  for (int i = 0; i < 4; ++i) {
    if (std::isfinite(params.initial_state[i]) && (i != 2 || params.initial_state[i] > 0.0)) continue;
    std::ostringstream msg;
    msg << "params.initial_state[" << i << "] (" << kElements[i] << ") = " << params.initial_state[i] << " must be "
        << (i == 2 ? "finite and > 0" : "finite");
    ThrowError(msg.str());
  }
  DeclareContinuousState(Eigen::VectorXd(params.initial_state));
  input_port_ = DeclareInputPort("leg_length_acceleration", 1);
  DeclareOutputPort(
      "state", 4, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  DeclareOutputPort(
      "leg_force", 1,
      [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = ContactForce(c.continuous_state().head<4>()); },
      Feedthrough::None());
  DeclareOutputPort(
      "energy", 3,
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const Eigen::Vector4d z = c.continuous_state().head<4>();
        const SpringMassEnergy e = model_.Energy(z);
        (*y)[0] = e.kinetic;
        (*y)[1] = e.potential;
        (*y)[2] = z(2) - z(0) > 0.0 ? e.spring : 0.0;
      },
      Feedthrough::None());
}

double SpringMassSystem::ContactForce(const Eigen::Vector4d& z) const { return std::max(0.0, model_.LegForce(z)); }

void SpringMassSystem::DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  const Eigen::Vector4d z = context.continuous_state().head<4>();
  const double v = EvalInput(context, input_port_)[0];
  // Sec. III-B with a unilateral foot: ẍ = F/m − g, F ≥ 0.
  (*xdot)(0) = z(1);
  (*xdot)(1) = ContactForce(z) / model_.params().mass - model_.params().gravity;
  (*xdot)(2) = z(3);
  (*xdot)(3) = v;
}

}  // namespace rome
