#pragma once
// WalkingTrajectorySource: a WalkingPlan (composed aSLIP + H-LIP orbits, spec §4) as a trajectory-source block on the
// global clock (spec [R]: COM references are indexed by global time; the plant's domain follows its own events).
//
// inputs:  none
// outputs: com (9)                    = [x, y, z (m), ẋ, ẏ, ż (m/s), ẍ, ÿ, z̈ (m/s²)] world
//          footholds (4)              = [left x, left y, right x, right y] (m) at the end of the current segment
//          normal_force_reference (2) = [F_L, F_R] (N), the aSLIP's vertical GRFs (Eq. (25)'s F^z_aSLIP) at
//                                       t + normal_force_lead_s (the other outputs are at t)
//          domain (typed WalkingDomain) = the planned domain
// Home: systems/planners, as WalkingPlan: a block that plays any WalkingPlan, for any biped with such a plan.
#include <string>

#include "framework/system.h"
#include "systems/planners/walking_plan.h"

namespace rome {

class WalkingTrajectorySource final : public LeafSystem {
 public:
  /// Throws (naming this system) if the plan is empty or normal_force_lead_s is not in [0, 0.1] s.
  /// normal_force_lead_s [s]: the normal_force_reference port reads the plan this far ahead. A controller that samples
  /// it at t and holds its torque until t + T (zero-order hold) meets, with a lead of T, the force the plan asks at the
  /// end of the hold rather than at its start (WalkingDiagramParams::force_band_lead_periods).
  WalkingTrajectorySource(std::string name, WalkingPlan plan, double normal_force_lead_s = 0.0);
  const WalkingPlan& plan() const { return plan_; }
  double normal_force_lead_s() const { return normal_force_lead_s_; }

 private:
  WalkingPlan plan_;
  double normal_force_lead_s_ = 0.0;
};

}  // namespace rome
