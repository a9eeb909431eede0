#pragma once
// What the stepping-stones diagram can walk, checked before a simulation: a robot it can use, and a course whose steps
// the robot's legs can span, whose rises and drops the supervisor's walking and fall heights allow, and whose stones
// hold the robot's sole. An input that fails here is bad input (exit 1 in the examples), not a failed run. Each limit
// comes from the robot model or from the diagram's parameters; the margins are in SteppingStonesFeasibilityParams.
// Every check is a necessary condition only: a course that passes may still fail in the simulation.

#include "diagrams/stepping_stones/stepping_stones_diagram.h"

namespace rome {

/// Margins of the feasibility checks (ours).
struct SteppingStonesFeasibilityParams {
  /// [-] Fraction of the legs' kinematic reach (LegReach of both feet plus the distance between the hip joints) that
  /// one step, stone centre to stone centre, may span. 1: the geometric bound itself (no step beyond it can be stood).
  double leg_reach_fraction = 1.0;
  /// [m] Length a stone must have beyond the sole at each end (line/flat feet; the diagram aims the sole's midpoint at
  /// the stone's centre). 0: the whole sole just fits.
  double sole_margin_m = 0.0;
};

/// The kinematic reach of the leg that carries contact `contact` of `model`: the longest distance its contact points
/// can be from the leg's hip joint (the joint below the base body, the torso), bounded by the sum of the segment
/// lengths from the hip joint to the contact's body (a prismatic joint adds its largest travel) plus the farthest
/// contact point. [m]; infinity if a prismatic joint on the way has no finite limit.
struct LegReach {
  double reach_m = 0.0;
  int hip_body = -1;                                      ///< the body whose inboard joint is the hip joint
  Eigen::Vector3d hip_in_base = Eigen::Vector3d::Zero();  ///< the hip joint's origin in the base body's frame [m]
};
LegReach CalcLegReach(const MultibodyModel& model, int contact);

/// Throws std::invalid_argument naming the robot and what the diagram needs if the stepping-stones diagram cannot use
/// `model`: a planar floating base, contacts named "left_foot" and "right_foot" of point or line type, and actuators.
void CheckSteppingStonesRobot(const MultibodyModel& model);

/// Throws std::invalid_argument, one line naming the stone(s), the value and the limit with where it comes from, if the
/// robot cannot walk the first params.supervisor.max_steps steps of `terrain` (stone k to stone k + 1) with `params`:
///  * fewer than 2 stones;
///  * a step longer (centre to centre) than leg_reach_fraction × (both legs' reach + the hips' distance);
///  * a rise or drop of at least supervisor.walking_com_height_m − supervisor.min_com_height_m: the posture NLP aims
///  the
///    COM at the walking height above the lower stone, so above the higher one it would be below the fall height;
///  * a walking height at or below the fall height (the run would end as a fall at once);
///  * a stone shorter than the robot's sole plus 2 sole_margin_m (line/flat feet);
///  * a smallest stance normal force (controller.min_normal_force_N, clf_controller.contact.min_normal_force_N) at or
///    above the robot's weight: one stance foot cannot push that hard for a whole step.
/// Calls CheckSteppingStonesRobot first.
void CheckSteppingStonesFeasible(const MultibodyModel& model, const Terrain& terrain,
                                 const SteppingStonesDiagramParams& params,
                                 const SteppingStonesFeasibilityParams& margins = {});

}  // namespace rome
