#pragma once
// ContactForceStatistics: checks the plant's own contact forces (not a controller's plan) against unilateral contact
// and the friction cone, sample by sample. Record() it from a simulator monitor to check every integrator step:
//   sim.set_monitor([&](const Context& c) { stats.Record(plant, diagram.GetSubsystemContext(plant, c)); return ...; });
// A sample violates contact when, for some contact active in the plant's mode, F_n < −tolerance or
// |F_t| > μ F_n (1 + relative_tolerance) + tolerance (μ: the contact's model friction coefficient; F_t: the world x-y
// force). The relative term is round-off: Bullet clamps friction at μ F_n, and a sliding foot's sum over its points
// comes out up to ~1e-8 μ F_n above the cone (measured: 6e-9 at F_n = 181 N). A sample also violates contact when
// the plant reports an active contact sliding (ContactPlant::SlipDistance > 0: BulletWorldPlant, whose clamped friction
// keeps the force in the cone while a foot slides).

#include <limits>
#include <string>

#include "systems/plants/contact_plant.h"

namespace rome {

struct ContactForceStatistics {
  double tolerance_N = 1e-6;         ///< [N] allowed violation (integration and round-off), ours
  double relative_tolerance = 1e-6;  ///< [-] allowed friction excess as a fraction of μ F_n (round-off), ours
  double min_normal_force_N = std::numeric_limits<double>::infinity();  ///< [N] smallest F_n of an active contact
  double max_friction_ratio = 0.0;  ///< [-] largest |F_t| / F_n of an active contact with F_n > 0
  double max_cone_excess_N = 0.0;   ///< [N] largest |F_t| − μ F_n (≤ 0 inside the cone; 0 if never positive)
  long samples = 0;                 ///< samples with at least one active contact
  long violations = 0;              ///< samples that violated unilateral contact or the friction cone
  std::string first_violation;      ///< "t = … s: contact 'left_foot' F_n = … N, |F_t|/F_n = …" of the first one

  void Record(const ContactPlant& plant, const LeafContext& plant_context);
  /// The rule above for one contact force (normal F_n [N], tangential magnitude |F_t| [N], friction coefficient μ).
  bool Violates(double normal_N, double tangential_N, double mu) const;
};

}  // namespace rome
