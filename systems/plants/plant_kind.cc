#include "systems/plants/plant_kind.h"

#include <stdexcept>

namespace rome {

const char* ToString(PlantKind kind) {
  switch (kind) {
    case PlantKind::kHybrid: return "hybrid";
    case PlantKind::kBullet: return "bullet";
  }
  return "unknown";
}

PlantKind ParsePlantKind(const std::string& value, const std::string& source) {
  for (const PlantKind kind : {PlantKind::kHybrid, PlantKind::kBullet})
    if (value == ToString(kind)) return kind;
  throw std::invalid_argument(source + " '" + value + "': unknown plant (expected hybrid or bullet)");
}

std::unique_ptr<ContactPlant> MakeContactPlant(PlantKind kind, std::string name,
                                               std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph,
                                               Terrain terrain, const HybridContactPlantParams& hybrid,
                                               const BulletWorldPlantParams& bullet) {
  if (kind == PlantKind::kBullet)
    return std::make_unique<BulletWorldPlant>(std::move(name), std::move(model), std::move(graph), std::move(terrain),
                                              bullet);
  return std::make_unique<HybridContactPlant>(std::move(name), std::move(model), std::move(graph), std::move(terrain),
                                              hybrid);
}

}  // namespace rome
