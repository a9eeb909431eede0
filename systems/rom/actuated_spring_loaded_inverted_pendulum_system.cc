#include "systems/rom/actuated_spring_loaded_inverted_pendulum_system.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace rome {

ActuatedSpringLoadedInvertedPendulumSystem::ActuatedSpringLoadedInvertedPendulumSystem(
    std::string name, ActuatedSpringLoadedInvertedPendulumSystemParams params)
    : LeafSystem(std::move(name)), params_(std::move(params)) {
  const ActuatedSpringLoadedInvertedPendulumParams& p = params_.aslip;
  if (!(p.mass > 0) || !(p.gravity > 0) || !(p.spring_scale > 0)) {
    std::ostringstream msg;
    msg << "parameters mass, gravity and spring_scale must be > 0, got " << p.mass << ", " << p.gravity << ", "
        << p.spring_scale;
    ThrowError(msg.str());
  }
  const std::vector<std::string> modes = {"double_support", "left_stance", "right_stance"};
  int mode = -1;
  for (int i = 0; i < 3; ++i) {
    if (modes[i] == params_.initial_mode) mode = i;
  }
  if (mode < 0) {
    ThrowError("parameter initial_mode must be 'double_support', 'left_stance' or 'right_stance', got '" +
               params_.initial_mode + "'");
  }
  DeclareModes(modes, mode);
  ldd_port_ = DeclareInputPort("leg_length_acceleration", {"left", "right"});
  if (params_.footed) torque_port_ = DeclareInputPort("ankle_torque", {"left", "right"});
  foothold_port_ = DeclareInputPort("next_foothold", 1);
  DeclareContinuousState(Eigen::VectorXd(params_.initial_state));
  DeclareDiscreteState(Eigen::Vector3d(params_.initial_left_foot_x, params_.initial_right_foot_x, 0.0));

  DeclareOutputPort(
      "state", {"x", "z", "xdot", "zdot", "L_left", "L_right", "Ldot_left", "Ldot_right"},
      [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  DeclareOutputPort(
      "com", {"x", "z", "xdot", "zdot"},
      [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state().head<4>(); }, Feedthrough::None());
  DeclareOutputPort(
      "grf", {"left_x", "left_z", "right_x", "right_z"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const ActuatedSpringLoadedInvertedPendulumContact contact = Contact(c);
        const Eigen::VectorXd u = Input(c);
        y->setZero();
        for (int leg = 0; leg < 2; ++leg) {
          if (!contact.in_contact(leg)) continue;
          const double torque = params_.footed ? u(2 + leg) : 0.0;
          const ActuatedSpringLoadedInvertedPendulumLeg<double> g =
              AslipLegState<double>(params_.aslip, c.continuous_state(), leg, contact.foot_x(leg), torque);
          (*y)(2 * leg) = g.grf_x;
          (*y)(2 * leg + 1) = g.grf_z;
        }
      },
      params_.footed ? Feedthrough::From({torque_port_}) : Feedthrough::None());
  DeclareOutputPort(
      "foot_x", {"left", "right"}, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().head<2>(); },
      Feedthrough::None());

  for (int stance = 0; stance < 2; ++stance) {
    const int swing = 1 - stance;
    DeclareGuard(
        "touchdown", stance == 0 ? left_stance_mode() : right_stance_mode(),
        [this, swing](const LeafContext& c) {
          const Eigen::VectorXd& x = c.continuous_state();
          const double x_next = EvalInput(c, foothold_port_)[0];
          return x(4 + swing) - std::hypot(x(0) - x_next, x(1));
        },
        CrossingDirection::kRising,
        [this, swing](const LeafContext& c, int, State* next) {
          const double x_next = EvalInput(c, foothold_port_)[0];
          if (!std::isfinite(x_next)) return EventStatus::Failed("input 'next_foothold' is not finite at touchdown");
          next->discrete(swing) = x_next;  // Appendix 2: the mass velocity is continuous (identity in Cartesian form)
          next->discrete(2) += 1;
          next->mode = double_support_mode();
          return EventStatus::Succeeded();
        });
  }
  DeclareGuard(
      "liftoff", double_support_mode(), 2,
      [this](const LeafContext& c, Eigen::Ref<Eigen::VectorXd> w) {
        const Eigen::VectorXd u = Input(c);
        for (int leg = 0; leg < 2; ++leg) {
          const double torque = params_.footed ? u(2 + leg) : 0.0;
          w(leg) =
              AslipLegState<double>(params_.aslip, c.continuous_state(), leg, c.discrete_state()(leg), torque).grf_z;
        }
      },
      CrossingDirection::kFalling,
      [this](const LeafContext&, int component, State* next) {
        // The leg whose vertical GRF reached 0 lifts off; the other one stands.
        next->mode = component == 0 ? right_stance_mode() : left_stance_mode();
        return EventStatus::Succeeded();
      });
}

ActuatedSpringLoadedInvertedPendulumContact ActuatedSpringLoadedInvertedPendulumSystem::Contact(
    const LeafContext& context) const {
  ActuatedSpringLoadedInvertedPendulumContact contact;
  contact.left = context.mode() != right_stance_mode();
  contact.right = context.mode() != left_stance_mode();
  contact.left_foot_x = context.discrete_state()(0);
  contact.right_foot_x = context.discrete_state()(1);
  return contact;
}

Eigen::VectorXd ActuatedSpringLoadedInvertedPendulumSystem::Input(const LeafContext& context) const {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(params_.footed ? 4 : 2);
  u.head<2>() = EvalInput(context, ldd_port_);
  if (params_.footed) u.tail<2>() = EvalInput(context, torque_port_);
  return u;
}

void ActuatedSpringLoadedInvertedPendulumSystem::DoCalcTimeDerivatives(const LeafContext& context,
                                                                       Eigen::VectorXd* xdot) const {
  *xdot = AslipDynamics<double>(params_.aslip, Contact(context), context.continuous_state(), Input(context));
}

}  // namespace rome
