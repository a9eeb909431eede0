#include "diagrams/stepping_stones/stepping_stones_feasibility.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rome {

namespace {

bool IsBase(const MultibodyModel& model, int body) {
  const int parent = model.body(body).parent;
  return parent < 0 || model.body(parent).is_virtual;
}

[[noreturn]] void Refuse(const std::ostringstream& out) { throw std::invalid_argument(out.str()); }

}  // namespace

LegReach CalcLegReach(const MultibodyModel& model, int contact) {
  const ContactInfo& c = model.contacts().at(contact);
  LegReach leg;
  for (const Eigen::Vector3d& p : c.points) leg.reach_m = std::max(leg.reach_m, p.norm());
  int body = c.body;
  if (IsBase(model, body)) {  // a contact on the base itself: its "hip" is the base frame's origin
    leg.hip_body = body;
    return leg;
  }
  // Up the chain to the hip: every joint below the hip adds its offset (and a prismatic joint its travel).
  while (!IsBase(model, model.body(body).parent)) {
    const MultibodyBody& b = model.body(body);
    leg.reach_m += b.X_parent_joint.translation().norm();
    if (b.joint_type == MultibodyJointType::kPrismatic)
      leg.reach_m += std::max(std::abs(model.position_lower_limits()[b.v_index]),
                              std::abs(model.position_upper_limits()[b.v_index]));
    body = b.parent;
  }
  const MultibodyBody& hip = model.body(body);
  if (hip.joint_type == MultibodyJointType::kPrismatic)
    leg.reach_m += std::max(std::abs(model.position_lower_limits()[hip.v_index]),
                            std::abs(model.position_upper_limits()[hip.v_index]));
  leg.hip_body = body;
  leg.hip_in_base = hip.X_parent_joint.translation();
  return leg;
}

void CheckSteppingStonesRobot(const MultibodyModel& model) {
  const std::string robot = "robot '" + model.name() + "' (" + model.sidecar_path() + ")";
  if (!model.is_planar())
    throw std::invalid_argument(
        "stepping-stones diagram: " + robot + " has a " + ToString(model.floating_base()) +
        " floating base; the diagram walks planar robots only (sidecar \"floating_base\": \"planar\")");
  for (const char* foot : {"left_foot", "right_foot"}) {
    const auto& contacts = model.contacts();
    if (std::none_of(contacts.begin(), contacts.end(), [&](const ContactInfo& c) { return c.name == foot; }))
      throw std::invalid_argument("stepping-stones diagram: " + robot + " has no contact named '" + foot +
                                  "'; the diagram needs 'left_foot' and 'right_foot'");
  }
  if (model.nu() == 0) throw std::invalid_argument("stepping-stones diagram: " + robot + " has no actuators");
}

void CheckSteppingStonesFeasible(const MultibodyModel& model, const Terrain& terrain,
                                 const SteppingStonesDiagramParams& params,
                                 const SteppingStonesFeasibilityParams& margins) {
  CheckSteppingStonesRobot(model);
  if (!(margins.leg_reach_fraction > 0.0) || !(margins.sole_margin_m >= 0.0) ||
      !std::isfinite(margins.leg_reach_fraction + margins.sole_margin_m))
    throw std::invalid_argument(
        "SteppingStonesFeasibilityParams: leg_reach_fraction must be positive and sole_margin_m >= 0, got " +
        std::to_string(margins.leg_reach_fraction) + " and " + std::to_string(margins.sole_margin_m) + " m");
  const std::string robot = "robot '" + model.name() + "'";
  std::ostringstream out;
  const double walking = params.supervisor.walking_com_height_m, fall = params.supervisor.min_com_height_m;
  if (!(walking > fall)) {
    out << "SteppingStonesDiagramParams: supervisor.walking_com_height_m = " << walking
        << " m must be above supervisor.min_com_height_m = " << fall
        << " m (the fall height): the run would end as a fall at once";
    Refuse(out);
  }
  const double weight_N = model.total_mass() * model.gravity().norm();
  for (const auto& [name, force] :
       {std::pair<const char*, double>{"controller.min_normal_force_N", params.controller.min_normal_force_N},
        {"clf_controller.contact.min_normal_force_N", params.clf_controller.contact.min_normal_force_N}})
    if (!(force < weight_N)) {
      out << "SteppingStonesDiagramParams: " << name << " = " << force << " N must be below the weight of " << robot
          << ", " << weight_N << " N (" << model.total_mass()
          << " kg): one stance foot cannot push that hard for a whole step";
      Refuse(out);
    }
  const LegReach left = CalcLegReach(model, model.ContactIndex("left_foot")),
                 right = CalcLegReach(model, model.ContactIndex("right_foot"));
  const double reach =
      margins.leg_reach_fraction * (left.reach_m + right.reach_m + (left.hip_in_base - right.hip_in_base).norm());
  const double rise_limit = walking - fall;
  const double sole = SoleLength(model), min_length = sole > 0.0 ? sole + 2.0 * margins.sole_margin_m : 0.0;
  const std::vector<SteppingStone>& stones = terrain.stones();
  if (stones.size() < 2) {
    out << "terrain: has " << stones.size() << " stone" << (stones.size() == 1 ? "" : "s")
        << "; a walk needs at least 2 (the one it starts on and one to step to)";
    Refuse(out);
  }
  const size_t last = std::min(stones.size() - 1, static_cast<size_t>(std::max(params.supervisor.max_steps, 0)));
  for (size_t k = 0; k <= last; ++k) {
    const SteppingStone& s = stones[k];
    if (s.length_m < min_length) {
      out << "terrain: stone " << k << " (x = " << s.x_center_m << " m) is " << s.length_m
          << " m long, shorter than the sole of " << robot << ", " << min_length << " m (toe to heel"
          << (margins.sole_margin_m > 0 ? ", plus the margins" : "") << "): the foot cannot stand on it";
      Refuse(out);
    }
    if (k == 0) continue;
    const SteppingStone& p = stones[k - 1];
    const double dx = s.x_center_m - p.x_center_m, dz = s.top_height_m - p.top_height_m, step = std::hypot(dx, dz);
    if (step > reach) {
      out << "terrain: the step from stone " << k - 1 << " (x = " << p.x_center_m << " m) to stone " << k
          << " (x = " << s.x_center_m << " m) spans " << step << " m centre to centre; the legs of " << robot
          << " reach at most " << reach << " m (" << left.reach_m << " + " << right.reach_m << " m from hip to foot"
          << (margins.leg_reach_fraction != 1.0 ? ", times leg_reach_fraction" : "") << ")";
      Refuse(out);
    }
    if (std::abs(dz) >= rise_limit) {
      out << "terrain: stone " << k << " is " << std::abs(dz) << " m " << (dz > 0 ? "above" : "below") << " stone "
          << k - 1 << "; the stepping-stones supervisor takes rises and drops below " << rise_limit
          << " m (supervisor.walking_com_height_m " << walking << " m - min_com_height_m " << fall
          << " m: the COM, at the walking height above the lower stone, would be below the fall height above the "
             "higher)";
      Refuse(out);
    }
  }
}

}  // namespace rome
