#include "systems/controllers/controller_setup.h"

#include <chrono>
#include <stdexcept>

namespace rome {

Eigen::VectorXd ResolveTorqueLimits(const MultibodyModel& model, const Eigen::VectorXd& limits,
                                    const std::string& system) {
  const Eigen::VectorXd u_max = limits.size() == 0 ? model.torque_limits() : limits;
  if (u_max.size() != model.nu())
    throw std::runtime_error("system '" + system + "': params.torque_limits has size " + std::to_string(u_max.size()) +
                             "; robot '" + model.name() + "' has nu = " + std::to_string(model.nu()));
  for (int j = 0; j < model.nu(); ++j)
    if (!(u_max[j] >= 0.0))
      throw std::runtime_error("system '" + system + "': torque limit of actuator '" + model.actuators()[j].joint +
                               "' is " + std::to_string(u_max[j]) + " N m; it must be >= 0");
  return u_max;
}

std::vector<std::vector<int>> ZeroTorqueActuatorsPerMode(
    const MultibodyModel& model, const std::vector<ContactSet>& mode_contacts,
    const std::vector<std::pair<std::string, std::string>>& zero_torque_in_contact, const std::string& system) {
  std::vector<std::vector<int>> zero(mode_contacts.size());
  for (const auto& [contact, joint] : zero_torque_in_contact) {
    int c = -1;
    try {
      c = model.ContactIndex(contact);
    } catch (const std::exception&) {
      throw std::runtime_error("system '" + system + "': params.zero_torque_in_contact names contact '" + contact +
                               "', which robot '" + model.name() + "' does not have");
    }
    int actuator = -1;
    for (int j = 0; j < model.nu(); ++j)
      if (model.actuators()[j].joint == joint) actuator = j;
    if (actuator < 0)
      throw std::runtime_error("system '" + system + "': params.zero_torque_in_contact names joint '" + joint +
                               "', which is not an actuated joint of robot '" + model.name() + "'");
    for (size_t m = 0; m < mode_contacts.size(); ++m)
      if (mode_contacts[m] & ContactBit(c)) zero[m].push_back(actuator);
  }
  return zero;
}

void QpControllerSystem::DeclareQpPortsAndUpdates(int failures_offset, int status_offset, int solve_time_offset,
                                                  double period_s, bool resolve_at_events, const EventTrigger& trigger,
                                                  UpdateFunction update) {
  auto scalar = [](int offset) {
    return [offset](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[offset]; };
  };
  DeclareOutputPort("qp_failures", 1, scalar(failures_offset), Feedthrough::None());
  DeclareOutputPort("qp_status", 1, scalar(status_offset), Feedthrough::None());
  DeclareOutputPort("solve_time_s", 1, scalar(solve_time_offset), Feedthrough::None());
  auto timed = [update = std::move(update), solve_time_offset](const LeafContext& c, Eigen::VectorXd* next) {
    const auto start = std::chrono::steady_clock::now();
    const EventStatus status = update(c, next);
    (*next)[solve_time_offset] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return status;
  };
  DeclarePeriodicDiscreteUpdate(period_s, 0.0, timed);
  if (resolve_at_events)
    DeclareEventUpdate("resolve_qp", trigger, [timed](const LeafContext& c, const EventRecord&, State* next) {
      return timed(c, &next->discrete);
    });
}

int CheckedModeIndex(int mode, int num_modes, const std::string& system) {
  if (mode < 0 || mode >= num_modes)
    throw std::runtime_error("system '" + system + "': input port 'mode' has value " + std::to_string(mode) +
                             "; expected a mode index in [0, " + std::to_string(num_modes) + ")");
  return mode;
}

}  // namespace rome
