#include "diagrams/walking/walking_robot_check.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rome {

void CheckWalkingRobot(const MultibodyModel& model) {
  const std::string robot = "walking diagram: robot '" + model.name() + "'";
  if (model.floating_base() != FloatingBaseType::kSpatial)
    throw std::invalid_argument(
        robot + " has a " + std::string(ToString(model.floating_base())) +
        " floating base; the walking diagram needs a spatial one (a 3D biped such as robots/exoskeleton)");
  for (const char* foot : {"left_foot", "right_foot"}) {
    const auto& contacts = model.contacts();
    const auto it =
        std::find_if(contacts.begin(), contacts.end(), [&](const ContactInfo& c) { return c.name == foot; });
    if (it == contacts.end())
      throw std::invalid_argument(robot + " has no contact named '" + foot +
                                  "'; the walking diagram needs 'left_foot' and 'right_foot'");
    if (it->type != ContactType::kFlat)
      throw std::invalid_argument(robot + ": contact '" + foot + "' is a " +
                                  (it->type == ContactType::kPoint ? "point" : "line") +
                                  " contact; the walking diagram needs flat feet (a sole of corner points)");
  }
  if (model.nu() == 0) throw std::invalid_argument(robot + " has no actuators");
}

}  // namespace rome
