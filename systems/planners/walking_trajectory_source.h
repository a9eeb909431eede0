#pragma once
// WalkingTrajectorySource: a WalkingPlan (composed aSLIP + H-LIP orbits, spec §4) as a trajectory-source block on the
// global clock (spec [R]: COM references are indexed by global time; the plant's domain follows its own events).
//
// inputs:  none
// outputs: com (9)                    = [x, y, z (m), ẋ, ẏ, ż (m/s), ẍ, ÿ, z̈ (m/s²)] world
//          footholds (4)              = [left x, left y, right x, right y] (m) at the end of the current segment
//          normal_force_reference (2) = [F_L, F_R] (N), the aSLIP's vertical GRFs (Eq. (25)'s F^z_aSLIP)
//          domain (typed WalkingDomain) = the planned domain
// Home: systems/planners, as WalkingPlan: a block that plays any WalkingPlan, for any biped with such a plan.
#include <string>

#include "framework/system.h"
#include "systems/planners/walking_plan.h"

namespace rome {

class WalkingTrajectorySource final : public LeafSystem {
 public:
  /// Throws (naming this system) if the plan is empty.
  WalkingTrajectorySource(std::string name, WalkingPlan plan);
  const WalkingPlan& plan() const { return plan_; }

 private:
  WalkingPlan plan_;
};

}  // namespace rome
