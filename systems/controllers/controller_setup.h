#pragma once
// Set-up shared by the whole-body QP controllers (TaskSpaceQpController, ClfQpController): torque limits, actuators
// held at zero torque while a contact is active (a passive stance ankle), and the mode input check. Errors name the
// controller (system), the parameter and the value.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "framework/system.h"
#include "systems/multibody/contact_dynamics.h"

namespace rome {

/// `limits` if given (size checked against nu), else the model's torque limits; every entry must be ≥ 0.
Eigen::VectorXd ResolveTorqueLimits(const MultibodyModel& model, const Eigen::VectorXd& limits,
                                    const std::string& system);

/// Per mode: the actuators forced to u = 0 because `contact` of a {contact, joint} pair is active in that mode.
std::vector<std::vector<int>> ZeroTorqueActuatorsPerMode(
    const MultibodyModel& model, const std::vector<ContactSet>& mode_contacts,
    const std::vector<std::pair<std::string, std::string>>& zero_torque_in_contact, const std::string& system);

/// Base of the whole-body QP controllers: the seam's status ports and the update schedule they share.
class QpControllerSystem : public LeafSystem {
 protected:
  using LeafSystem::LeafSystem;
  using UpdateFunction = std::function<EventStatus(const LeafContext&, Eigen::VectorXd*)>;
  /// Declares the outputs qp_failures, qp_status and solve_time_s (discrete-state entries at the given offsets), the
  /// periodic update every `period_s` and, if `resolve_at_events`, the event update "resolve_qp" at `trigger`. Both run
  /// `update` and write its wall time [s] (steady_clock) into the solve_time_s entry.
  void DeclareQpPortsAndUpdates(int failures_offset, int status_offset, int solve_time_offset, double period_s,
                                bool resolve_at_events, const EventTrigger& trigger, UpdateFunction update);
};

/// `mode` if it indexes `num_modes` modes, else std::runtime_error "system 'name': input port 'mode' has value ...".
int CheckedModeIndex(int mode, int num_modes, const std::string& system);

}  // namespace rome
