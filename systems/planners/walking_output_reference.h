#pragma once
// WalkingOutputReference: the desired values of the walking paper's CLF-QP outputs, Eq. (16) in DSP and Eq. (17) in
// SSP, on the global clock (spec §5.1 [R]):
//   COM: the composed aSLIP + H-LIP reference (input 'com', from WalkingTrajectorySource);
//   pelvis roll, pitch, yaw: 0 (upright, zero yaw);
//   each foot's ankle position and orientation while it swings: x, y minimum-jerk from its position at the planned
//   lift-off (its foothold at the end of the previous segment) to the foothold at the end of the SSP; z = ankle
//   height + a quintic with 0 and zero velocity at lift-off, the apex height with zero velocity at mid-SSP and 0 with
//   the touchdown velocity at T_SSP; after T_SSP (a late touchdown) it keeps descending at that velocity. Orientation:
//   zero roll and yaw; pitch (toe down, about the world y axis) θ = pitch_max · h / apex with h the ankle's height
//   above its standing height (ours: the foot pitches with the folding shank, so the swing ankle bends less toward its
//   dorsiflexion limit; level at lift-off and touchdown; 0 gives the flat foot of spec §5.1 [R]). Outside its swing a
//   foot's rows hold its foothold, flat (the controller ignores them there).
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
  /// [rad] the swing foot's toe-down pitch at the apex, in [0, 1) (ours; docs/design-notes.md, "swing foot pitch"):
  /// the toe sinks about toe length · pitch_max below the level sole there, so pitch_max must stay below
  /// apex_height_m / toe length (0.44 rad on the exoskeleton: 0.08 m over 0.18 m); 0.25 keeps 3.8 cm there, room for
  /// the tracking error of the first swing from standing
  double pitch_max_rad = 0.25;
};

class WalkingOutputReference final : public LeafSystem {
 public:
  static constexpr int kNumOutputs = 18;
  WalkingOutputReference(std::string name, WalkingPlan plan, SwingFootTrajectoryParams params = {});
  const SwingFootTrajectoryParams& params() const { return params_; }
  /// Ankle position, velocity, acceleration [m, m/s, m/s²] of foot `foot` (0 left, 1 right) at global time t.
  void SwingFoot(int foot, double t, Eigen::Ref<Eigen::Vector3d> p, Eigen::Ref<Eigen::Vector3d> v,
                 Eigen::Ref<Eigen::Vector3d> a) const;
  /// The foot's toe-down pitch θ, θ̇, θ̈ [rad, rad/s, rad/s²] about the world y axis at global time t (0 outside its
  /// swing and after T_SSP), from SwingFoot's height: θ = pitch_max · (z − ankle_height) / apex_height.
  void SwingFootPitch(int foot, double t, double* pitch, double* rate, double* acceleration) const;

 private:
  WalkingPlan plan_;
  SwingFootTrajectoryParams params_;
};

}  // namespace rome
