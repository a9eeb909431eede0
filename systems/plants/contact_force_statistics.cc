#include "systems/plants/contact_force_statistics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rome {

void ContactForceStatistics::Record(const ContactPlant& plant, const LeafContext& context) {
  const ContactSet active = plant.active_contacts(context.mode());
  if (active == 0) return;
  const Eigen::VectorXd& forces = plant.EvalOutput(context, "contact_forces");
  const MultibodyModel& model = plant.model();
  bool violated = false;
  ++samples;
  for (int c = 0; c < model.num_contacts(); ++c) {
    if (!(active & ContactBit(c))) continue;
    const Eigen::Vector3d f = forces.segment<3>(3 * c);
    const double fn = f.z(), ft = f.head<2>().norm(), mu = model.contacts()[c].friction_coefficient;
    min_normal_force_N = std::min(min_normal_force_N, fn);
    if (fn > 0) max_friction_ratio = std::max(max_friction_ratio, ft / fn);
    max_cone_excess_N = std::max(max_cone_excess_N, ft - mu * fn);
    if (Violates(fn, ft, mu)) {
      if (!violated && violations == 0) {
        std::ostringstream os;
        os << "t = " << context.time() << " s: contact '" << model.contacts()[c].name << "' F_n = " << fn
           << " N, |F_t| = " << ft << " N (mu = " << mu << ")";
        first_violation = os.str();
      }
      violated = true;
    }
  }
  for (int c = 0; c < model.num_contacts() && !violated; ++c) {
    if (!(active & ContactBit(c))) continue;
    const double slid = plant.SlipDistance(context, c);
    if (slid > 0.0) {
      if (violations == 0) {
        std::ostringstream os;
        os << "t = " << context.time() << " s: contact '" << model.contacts()[c].name << "' slid " << slid
           << " m with its force inside the cone";
        first_violation = os.str();
      }
      violated = true;
    }
  }
  if (violated) ++violations;
}

bool ContactForceStatistics::Violates(double normal_N, double tangential_N, double mu) const {
  // Written so that NaN forces count as violations.
  return !(normal_N >= -tolerance_N) ||
         !(tangential_N <= mu * std::max(normal_N, 0.0) * (1 + relative_tolerance) + tolerance_N);
}

}  // namespace rome
