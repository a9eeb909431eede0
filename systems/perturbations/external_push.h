#pragma once
// ExternalPush: a constant force on a point of a named body over a time window, as the generalized force it exerts.
//
// inputs:  state (2 nv)        plant [q; v] (MultibodyModel coordinates)
// outputs: tau_external (nv)   generalized force [N or N m per coordinate], τ_ext = J_p(q)ᵀ F for
//                              start_time_s <= t < start_time_s + duration_s, 0 otherwise; feeds a plant's
//                              tau_external input (HybridContactPlantParams::external_force_input)
// discrete state (1): phase, 0 before the push, 1 during it, 2 after it. It changes only at t = start_time_s and
//   t = start_time_s + duration_s (periodic updates with offset start_time_s and period duration_s), so an integrator
//   restarts exactly at both ends of the push and the impulse J = F duration_s is applied exactly.
// J_p is the Jacobian of the world velocity of the point p_body (body frame) of the body (multibody_kinematics.h), so
// the force does the work Fᵀ ṗ and changes the linear momentum of a free-floating robot by ∫F dt = F duration_s.

#include <memory>
#include <string>

#include <Eigen/Core>

#include "framework/system.h"
#include "systems/multibody/multibody_model.h"

namespace rome {

struct ExternalPushParams {
  std::string body = "torso";                                 ///< URDF link name (MultibodyModel::BodyIndex)
  Eigen::Vector3d point_in_body_m = Eigen::Vector3d::Zero();  ///< [m] where the force acts, in the link's frame
  double start_time_s = 1.0;                                  ///< [s] (ours)
  double duration_s = 0.1;                                    ///< [s] (ours)
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();          ///< [N] world axes, constant over the push

  /// Impulse of the push, F duration_s [N s].
  Eigen::Vector3d impulse_Ns() const { return force_N * duration_s; }
  /// Throws std::invalid_argument naming the field and value: start_time_s in [0, 1e6] s, duration_s in (0, 1e6] s,
  /// finite force with |F| <= 1e6 N, finite point with |p| <= 100 m (ranges ours).
  void Validate() const;
};

class ExternalPush final : public LeafSystem {
 public:
  /// Throws, naming the system and the body, if `model` has no link params.body, and as params.Validate().
  ExternalPush(std::string name, std::shared_ptr<const MultibodyModel> model, ExternalPushParams params);
  const ExternalPushParams& params() const { return params_; }

  struct Scratch;

 private:
  std::any AllocateScratch() const override;

  std::shared_ptr<const MultibodyModel> model_;
  ExternalPushParams params_;
  int body_ = -1;
  Eigen::Vector3d point_in_body_ = Eigen::Vector3d::Zero();  ///< params' point, in the body's frame (merged links)
};

}  // namespace rome
