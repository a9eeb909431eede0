#pragma once
// What the stepping-stones plan asks of friction on a periodic course (every step the same l, h), computed before a
// run. The plan is the reduced-order model's: the COM follows the LIP of Eq. (12) horizontally (p̈^x = g p^x / ẑ0,
// about the stance foot) from the post-impact state of the E* orbit (p^{x+} = (ε − 1) l, L⁺ = L_des) to ε l, and the
// vertical-COM plan of Eq. (28) (VerticalComMpc) vertically, from the post-impact height p_comf^{z,d} − h and
// ṗ^{z+} = (h/l) ṗ^{x+} (the virtual slope) to [p_comf^{z,d}, u_des] in T̂_s (Eq. (18), (25)-(27): the planner's own
// MomentumRegulationPlanner). In single stance the stance foot's contact is the only force on the robot besides
// gravity, so the multibody model's inverse dynamics of any posture that moves the COM this way gives the contact
// force F = m (p̈_com + g e_z) (Newton's law for the whole body), and
//   |F_t| / F_n = |p̈^x| / (g + p̈^z),
// independent of the posture (F_n <= 0 asks for infinity: the foot would have to pull). This is a measurement of the
// plan, not a feasibility limit of the closed loop: nothing in the controller tracks the LIP's horizontal acceleration,
// and the plant walks periodic gaits whose plan asks more than μ here (docs/design-notes.md, "Stepping stones: what
// limits AMBER's speed").

#include "systems/planners/momentum_regulation_planner.h"
#include "systems/planners/vertical_com_mpc.h"

namespace rome {

struct PlanFrictionNeed {
  double max_ratio = 0.0;                  ///< [-] largest |F_t|/F_n over the step (infinity if F_n <= 0)
  double time_of_max_s = 0.0;              ///< [s] after the step's start (the impact)
  double min_normal_force_fraction = 0.0;  ///< [-] smallest F_n / (m g) = 1 + p̈^z / g over the step
  double step_duration_s = 0.0;            ///< [s] T̂_s from the post-impact state
  double u_des_mps = 0.0;                  ///< [m/s] the planned pre-impact vertical COM velocity, Eq. (18)
  double mean_speed_mps = 0.0;             ///< [m/s] l / T̂_s
};

/// The friction need (see the top of this file) of one step of the periodic gait on steps (step_length_m,
/// step_height_m) with pre-impact COM height pre_impact_com_height_m above the stance foot, sampled at `samples`
/// evenly spaced times in the step. Throws std::invalid_argument naming the value if l <= 0, samples < 1, the
/// planner's post-impact state is not finite, or the vertical-COM QP fails.
PlanFrictionNeed CalcPeriodicPlanFrictionNeed(double step_length_m, double step_height_m,
                                              double pre_impact_com_height_m,
                                              const MomentumRegulationPlannerParams& planner,
                                              const VerticalComMpcParams& mpc, int samples = 400);

}  // namespace rome
