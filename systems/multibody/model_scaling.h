#pragma once
// Model mismatch: a copy of a MultibodyModel with its masses, inertias and friction coefficients scaled, for a plant
// that differs from the model its controller uses.

#include "systems/multibody/multibody_model.h"

namespace rome {

/// A copy of `model` whose bodies' masses and inertias are mass_scale times the model's (a uniform change of density:
/// COMs and principal axes unchanged, total_mass() scaled by the same factor) and whose contacts' friction
/// coefficients are friction_scale times the model's. Rotor (reflected) inertias, torque limits, springs and geometry
/// are unchanged. Throws std::invalid_argument naming the robot, the argument and the value unless both are in
/// (0, 100] (ours).
MultibodyModel ScaleMassAndFriction(const MultibodyModel& model, double mass_scale, double friction_scale = 1.0);

}  // namespace rome
