#pragma once
// Whether the walking diagram (walking_diagram.h) can use a robot, checked before any plan is built: a robot it cannot
// use is bad input (exit 1 in the walking example), not a failed run.

#include "systems/multibody/multibody_model.h"

namespace rome {

/// Throws std::invalid_argument naming the robot, what it has and what the diagram needs, unless `model` has a spatial
/// floating base (the plans are 3D), flat contacts named "left_foot" and "right_foot" (the footed H-LIP and the force
/// matching need a sole; SoleOf checks the ankle over it) and actuators.
void CheckWalkingRobot(const MultibodyModel& model);

}  // namespace rome
