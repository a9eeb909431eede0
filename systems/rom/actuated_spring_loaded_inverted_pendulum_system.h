#pragma once
// ActuatedSpringLoadedInvertedPendulumSystem: the aSLIP of the walking paper (point-foot or footed) as a hybrid
// framework block with its SSP and DSP domains (Sec. III-A, IV-A, Appendix; dynamics in
// actuated_spring_loaded_inverted_pendulum.h).
//
// continuous state (8): [x, z (m), ẋ, ż (m/s), L_L, L_R (m), L̇_L, L̇_R (m/s)]
// discrete state (3):   [left foot pivot x (m), right foot pivot x (m), number of touchdowns]
// modes:   "double_support", "left_stance", "right_stance"
// inputs:  leg_length_acceleration (2) = [L̈_L, L̈_R] (m/s²), the virtual input of Eq. (4)/(9)
//          ankle_torque (2)             = [u_L, u_R] (N m), footed model only (Eq. (9)-(10))
//          next_foothold (1)            = x of the swing foot's landing point (m), read by the touchdown guard
// outputs: state (8)  = the continuous state
//          com (4)    = [x, z, ẋ, ż]
//          grf (4)    = [G_Lx, G_Lz, G_Rx, G_Rz] (N), zero for a leg off the ground (reads ankle_torque if footed)
//          foot_x (2) = [left, right] pivot x (m)
// guards:  "touchdown" (single support): the swing leg's rest length reaches the distance to the next foothold,
//          L_sw − |p − (x_next, 0)| crosses 0 rising (so s = 0 at touchdown, spec §2.1 [R]). Reset (Appendix 2):
//          the Cartesian state is unchanged; the foot pivot moves to x_next; mode → double_support.
//          "liftoff" (double support): a leg's vertical GRF G_iz crosses 0 falling (spec §1.2, no impact);
//          mode → stance of the other leg.
#include <string>

#include "framework/system.h"
#include "systems/rom/actuated_spring_loaded_inverted_pendulum.h"

namespace rome {

struct ActuatedSpringLoadedInvertedPendulumSystemParams {
  ActuatedSpringLoadedInvertedPendulumParams aslip{};
  bool footed = false;  ///< declares the ankle_torque input (footed aSLIP, Sec. IV-A)
  Eigen::Matrix<double, 8, 1> initial_state =
      (Eigen::Matrix<double, 8, 1>() << 0, 0.9, 0, 0, 0.97, 0.97, 0, 0).finished();
  std::string initial_mode = "double_support";
  double initial_left_foot_x = 0.0;   ///< [m]
  double initial_right_foot_x = 0.0;  ///< [m]
};

class ActuatedSpringLoadedInvertedPendulumSystem final : public LeafSystem {
 public:
  explicit ActuatedSpringLoadedInvertedPendulumSystem(std::string name = "aslip",
                                                      ActuatedSpringLoadedInvertedPendulumSystemParams params = {});
  const ActuatedSpringLoadedInvertedPendulumSystemParams& params() const { return params_; }
  int double_support_mode() const { return 0; }
  int left_stance_mode() const { return 1; }
  int right_stance_mode() const { return 2; }
  /// Contact flags and pivots of the context's mode.
  ActuatedSpringLoadedInvertedPendulumContact Contact(const LeafContext& context) const;

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  Eigen::VectorXd Input(const LeafContext& context) const;
  ActuatedSpringLoadedInvertedPendulumSystemParams params_;
  int ldd_port_ = -1, torque_port_ = -1, foothold_port_ = -1;
};

}  // namespace rome
