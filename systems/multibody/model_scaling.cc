#include "systems/multibody/model_scaling.h"

#include <sstream>
#include <stdexcept>

#include "systems/multibody/model_loader.h"

namespace rome {

MultibodyModel ScaleMassAndFriction(const MultibodyModel& model, double mass_scale, double friction_scale) {
  return MultibodyModelLoader::Scale(model, mass_scale, friction_scale);
}

MultibodyModel MultibodyModelLoader::Scale(const MultibodyModel& model, double mass_scale, double friction_scale) {
  auto check = [&model](const char* what, double value) {
    if (value > 0.0 && value <= 100.0) return;
    std::ostringstream out;
    out << "ScaleMassAndFriction: robot '" << model.name() << "': " << what << " = " << value << " is outside (0, 100]";
    throw std::invalid_argument(out.str());
  };
  check("mass_scale", mass_scale);
  check("friction_scale", friction_scale);
  MultibodyModel out = model;
  auto bodies = std::make_shared<std::vector<MultibodyBody>>(*model.bodies_);
  out.total_mass_ = 0.0;
  for (MultibodyBody& b : *bodies) {
    b.mass *= mass_scale;
    b.inertia *= mass_scale;
    b.principal_moments *= mass_scale;
    out.total_mass_ += b.mass;
  }
  out.bodies_ = std::move(bodies);
  for (ContactInfo& c : out.contacts_) c.friction_coefficient *= friction_scale;
  return out;
}

}  // namespace rome
