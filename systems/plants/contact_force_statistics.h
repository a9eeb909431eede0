#pragma once
// ContactForceStatistics: checks the plant's own contact forces (not a controller's plan) against unilateral contact
// and the friction cone, sample by sample. Record() it from a simulator monitor to check every integrator step:
//   sim.set_monitor([&](const Context& c) { stats.Record(plant, diagram.GetSubsystemContext(plant, c)); return ...; });
// A sample violates contact when, for some contact active in the plant's mode, F_n < −tolerance or
// |F_t| > μ F_n + tolerance (μ: the contact's model friction coefficient; F_t: the world x-y force).

#include <limits>
#include <string>

#include "systems/plants/contact_plant.h"

namespace rome {

struct ContactForceStatistics {
  double tolerance_N = 1e-6;  ///< [N] allowed violation (integration and round-off), ours
  double min_normal_force_N = std::numeric_limits<double>::infinity();  ///< [N] smallest F_n of an active contact
  double max_friction_ratio = 0.0;    ///< [-] largest |F_t| / F_n of an active contact with F_n > 0
  double max_cone_excess_N = 0.0;     ///< [N] largest |F_t| − μ F_n (≤ 0 inside the cone; 0 if never positive)
  long samples = 0;                   ///< samples with at least one active contact
  long violations = 0;                ///< samples that violated unilateral contact or the friction cone
  std::string first_violation;        ///< "t = … s: contact 'left_foot' F_n = … N, |F_t|/F_n = …" of the first one

  void Record(const ContactPlant& plant, const LeafContext& plant_context);
};

}  // namespace rome
