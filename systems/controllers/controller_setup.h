#pragma once
// Set-up shared by the whole-body QP controllers (TaskSpaceQpController, ClfQpController): torque limits, actuators
// held at zero torque while a contact is active (a passive stance ankle), and the mode input check. Errors name the
// controller (system), the parameter and the value.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/contact_dynamics.h"

namespace rome {

/// `limits` if given (size checked against nu), else the model's torque limits; every entry must be ≥ 0.
Eigen::VectorXd ResolveTorqueLimits(const MultibodyModel& model, const Eigen::VectorXd& limits, const std::string& system);

/// Per mode: the actuators forced to u = 0 because `contact` of a {contact, joint} pair is active in that mode.
std::vector<std::vector<int>> ZeroTorqueActuatorsPerMode(const MultibodyModel& model, const std::vector<ContactSet>& mode_contacts,
                                                         const std::vector<std::pair<std::string, std::string>>& zero_torque_in_contact,
                                                         const std::string& system);

/// `mode` if it indexes `num_modes` modes, else std::runtime_error "system 'name': input port 'mode' has value ...".
int CheckedModeIndex(int mode, int num_modes, const std::string& system);

}  // namespace rome
