#pragma once
// WalkingOutputReference: the desired values of the walking paper's CLF-QP outputs, Eq. (16) in DSP and Eq. (17) in
// SSP, on the global clock (spec §5.1 [R]):
//   COM: the composed aSLIP + H-LIP reference (input 'com', from WalkingTrajectorySource);
//   pelvis roll, pitch, yaw: 0 (upright, zero yaw);
//   each foot's ankle position and orientation while it swings: x, y minimum-jerk from its position at the planned
//   lift-off (its foothold at the end of the previous segment) to the foothold at the end of the SSP; z = ankle
//   height + a quintic with 0 and zero velocity at lift-off, the apex height with zero velocity at mid-SSP and 0 with
//   the touchdown velocity at T_SSP; after T_SSP (a late touchdown) it keeps descending at that velocity. Orientation
//   0 (flat, zero yaw). Outside its swing a foot's rows hold its foothold (the controller ignores them there).
//
// inputs:  com (9)      [p; ṗ; p̈] of the COM reference (m, m/s, m/s²)
// outputs: desired (54) [y_d; ẏ_d; ÿ_d] for the outputs, in this order (18 rows each):
//          com x, y, z (m); pelvis roll, pitch, yaw (rad); left ankle x, y, z (m); left foot rotation vector (3, rad);
//          right ankle x, y, z (m); right foot rotation vector (3, rad)
// Home: systems/planners, as WalkingPlan: it serves any flat-footed biped tracking a WalkingPlan.
#include <string>

#include "framework/system.h"
#include "systems/planners/walking_plan.h"

namespace rome {

struct SwingFootTrajectoryParams {
  double apex_height_m = 0.08;          ///< [m] sole clearance at mid-SSP (spec [R])
  double touchdown_velocity_mps = 0.1;  ///< [m/s] downward sole speed at T_SSP, > 0 (spec [R]); a late foot keeps it
  double ankle_height_m = 0.08;         ///< [m] ankle above the sole (the exoskeleton's model; set from the robot)
};

class WalkingOutputReference final : public LeafSystem {
 public:
  static constexpr int kNumOutputs = 18;
  WalkingOutputReference(std::string name, WalkingPlan plan, SwingFootTrajectoryParams params = {});
  const SwingFootTrajectoryParams& params() const { return params_; }
  /// Ankle position, velocity, acceleration [m, m/s, m/s²] of foot `foot` (0 left, 1 right) at global time t.
  void SwingFoot(int foot, double t, Eigen::Ref<Eigen::Vector3d> p, Eigen::Ref<Eigen::Vector3d> v,
                 Eigen::Ref<Eigen::Vector3d> a) const;

 private:
  WalkingPlan plan_;
  SwingFootTrajectoryParams params_;
};

}  // namespace rome
