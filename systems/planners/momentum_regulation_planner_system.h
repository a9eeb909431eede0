#pragma once
// MomentumRegulationPlannerSystem: MomentumRegulationPlanner (stepping-stones paper, Eq. (17)-(18), (25)-(27))
// as a framework block. Stateless; every output is recomputed from the inputs (direct feedthrough).
// General, not the stepping-stones diagram's own: it knows only the LIP state about a stance foot and a foothold,
// no robot and no contact mode, so any planar biped's diagram can use it.
//
// inputs:  com_state (4)              = [p^x, p^z (m), ṗ^x, ṗ^z (m/s)] COM relative to the stance foot
//          angular_momentum (1)       = L_y (m²/s), mass-normalised, about the stance foot (Eq. (7))
//          step (2)                   = [l_des, h_des] (m) next foothold relative to the stance foot
//          pre_impact_com_height (1)  = p_comf^{z,d} (m) desired pre-impact COM height (from Eq. (21))
// outputs: u_des (1)                  = desired pre-impact vertical COM velocity (m/s), Eq. (26)
//          L_des (1)                  = desired post-impact momentum (m²/s)
//          predicted_pre_impact_momentum (1) = L̂⁻ (m²/s), Eq. (25)
//          time_to_impact (1)         = T̂_s (s), Eq. (27), clamped to the params' [min, max]
//          slope_adjusted_height (1)  = ẑ0 (m), Eq. (27)
//          vertical_com_target (3)    = [p_comf^{z,d} (m), u_des (m/s), T̂_s (s)]: the 'target' input of
//          VerticalComMpcSystem status (1)                 = MomentumRegulationPlan::status bits (0 = ok)
// Bad inputs (l_des <= 0, ẑ0 <= 0, non-finite values) throw std::runtime_error naming this system.

#include <string>

#include "framework/system.h"
#include "systems/planners/momentum_regulation_planner.h"

namespace rome {

class MomentumRegulationPlannerSystem final : public LeafSystem {
 public:
  explicit MomentumRegulationPlannerSystem(std::string name = "momentum_planner",
                                           MomentumRegulationPlannerParams params = {});
  const MomentumRegulationPlanner& planner() const { return planner_; }
  /// The plan for the inputs in `context`.
  MomentumRegulationPlan CalcPlan(const LeafContext& context) const;

 private:
  MomentumRegulationPlanner planner_;
  int com_port_, momentum_port_, step_port_, height_port_;
};

}  // namespace rome
