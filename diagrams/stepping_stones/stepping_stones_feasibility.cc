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

// The plan's friction need on the periodic course of steps (l, h) (see CheckSteppingStonesFeasible).
void CheckPlanFriction(const MultibodyModel& model, double l, double h, const SteppingStonesDiagramParams& params,
                       double fraction) {
  double mu = std::numeric_limits<double>::infinity();
  for (const char* foot : {"left_foot", "right_foot"})
    mu = std::min(mu, model.contacts().at(model.ContactIndex(foot)).friction_coefficient);
  // The posture NLP aims the pre-impact COM at the walking height above the lower of the two stones.
  const double pre_impact_height = params.supervisor.walking_com_height_m + std::min(h, 0.0);
  MomentumRegulationPlannerParams planner = params.planner;
  planner.target_orbital_energy = params.target_orbital_energy;
  planner.impact_fraction = params.impact_fraction;
  const PlanFrictionNeed need = CalcPeriodicPlanFrictionNeed(l, h, pre_impact_height, planner, params.mpc.mpc);
  if (need.max_ratio <= fraction * mu) return;
  // The need grows with E* (a shorter step with a larger u_des): bisect for the largest E* that stays inside.
  double lo = 0.0, hi = params.target_orbital_energy;
  PlanFrictionNeed inside{};
  for (int i = 0; i < 30; ++i) {
    planner.target_orbital_energy = 0.5 * (lo + hi);
    const PlanFrictionNeed n = CalcPeriodicPlanFrictionNeed(l, h, pre_impact_height, planner, params.mpc.mpc);
    if (n.max_ratio <= fraction * mu) {
      lo = planner.target_orbital_energy;
      inside = n;
    } else {
      hi = planner.target_orbital_energy;
    }
  }
  std::ostringstream out;
  out.precision(3);
  out << "robot '" << model.name() << "' at E* " << params.target_orbital_energy << " m^2/s^2, epsilon "
      << params.impact_fraction << " on " << l << " m steps (rise " << h << " m): the plan needs |F_t|/F_n "
      << need.max_ratio << " at " << need.time_of_max_s << " s of the " << need.step_duration_s << " s step (F_n "
      << need.min_normal_force_fraction << " m g at least, u_des " << need.u_des_mps << " m/s); the feet have mu " << mu
      << (fraction != 1.0 ? " (times plan_friction_fraction)" : "") << "; ";
  if (lo > 0.0)
    out << "E* up to " << lo << " m^2/s^2 stays inside (" << inside.mean_speed_mps << " m/s)";
  else
    out << "no E* > 0 stays inside at this epsilon";
  Refuse(out);
}

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
      !(margins.plan_friction_fraction > 0.0) ||
      !std::isfinite(margins.leg_reach_fraction + margins.sole_margin_m + margins.plan_friction_fraction))
    throw std::invalid_argument(
        "SteppingStonesFeasibilityParams: leg_reach_fraction and plan_friction_fraction must be positive and "
        "sole_margin_m >= 0, got " +
        std::to_string(margins.leg_reach_fraction) + ", " + std::to_string(margins.plan_friction_fraction) + " and " +
        std::to_string(margins.sole_margin_m) + " m");
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
  // A periodic course: every walked step has the first step's length and rise.
  const double l = stones[1].x_center_m - stones[0].x_center_m, h = stones[1].top_height_m - stones[0].top_height_m;
  bool periodic = l > 0.0;
  for (size_t k = 2; k <= last && periodic; ++k)
    periodic = std::abs(stones[k].x_center_m - stones[k - 1].x_center_m - l) <= 1e-9 &&
               std::abs(stones[k].top_height_m - stones[k - 1].top_height_m - h) <= 1e-9;
  if (periodic) CheckPlanFriction(model, l, h, params, margins.plan_friction_fraction);
}

}  // namespace rome
