#pragma once
// PlantKind: which ContactPlant a diagram simulates, chosen by one builder argument (sim-to-sim).
//   kHybrid: HybridContactPlant, event-accurate rigid contact (continuous state, guards on CVODE's rootfinder);
//   kBullet: BulletWorldPlant, Bullet's btMultiBodyDynamicsWorld stepped at a fixed period (discrete state).
// Both declare ContactPlant's ports (contact_plant.h) and announce contact-mode changes through the same guard names,
// so a diagram builds either through MakeContactPlant and connects it the same way. What differs is only what the
// plant holds: read q and v through the plant's "q", "v" or "state" outputs, never its context's continuous state.

#include <memory>
#include <string>

#include "systems/plants/bullet_world_plant.h"
#include "systems/plants/hybrid_contact_plant.h"

namespace rome {

enum class PlantKind { kHybrid, kBullet };

/// "hybrid" or "bullet".
const char* ToString(PlantKind kind);

/// Parses "hybrid" or "bullet". Otherwise throws std::invalid_argument, one line naming `source` (the flag or parameter
/// the value came from, e.g. "--plant") and the value: "--plant 'foo': unknown plant (expected hybrid or bullet)".
PlantKind ParsePlantKind(const std::string& value, const std::string& source = "plant");

/// The plant of `kind`, built with `hybrid` (kHybrid) or `bullet` (kBullet) parameters; the other set is ignored.
std::unique_ptr<ContactPlant> MakeContactPlant(PlantKind kind, std::string name,
                                               std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph,
                                               Terrain terrain, const HybridContactPlantParams& hybrid,
                                               const BulletWorldPlantParams& bullet);

}  // namespace rome
