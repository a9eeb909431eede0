#pragma once
// HybridLinearInvertedPendulumSystem: the lateral H-LIP of the walking paper (Sec. III-B, Eq. (6)-(7)) as a hybrid
// framework block with time-based domain switching, optionally footed (Sec. IV-B: ankle roll torques).
//
// continuous state (2): [y (m), ẏ (m/s)], y relative to the stance foot (+y = left); in DSP still relative to the
//                       old stance foot (Eq. (7) convention)
// discrete state (4):   [time of the next domain switch (s), stance foot y in the world (m),
//                        stance side (+1 left, −1 right), number of steps]
// modes:   "single_support", "double_support"
// inputs:  step (1)              = w (m), signed offset from the old to the new stance foot, read at DSP→SSP
//          ankle_roll_torque (2) = [u_L, u_R] (N m), footed only; SSP uses the stance foot's torque
// outputs: state (2)  = [y, ẏ]
//          com_y (2)  = [stance foot y + y, ẏ] in the world
// flow:    SSP ÿ = λ² y (+ u_stance/(m z0)),  DSP ÿ = 0 (+ (u_L + u_R)/(m z0))
// guard:   "domain_switch": t − t_switch crosses 0 rising. SSP→DSP (Eq. (6)): identity, t_switch += T_DSP.
//          DSP→SSP (Eq. (7)): y⁺ = y⁻ − w, stance foot += w, side flips, t_switch += T_SSP.
//          With T_DSP = 0 the SSP→DSP→SSP switch happens in one reset.
#include <string>

#include "framework/system.h"
#include "systems/rom/hybrid_linear_inverted_pendulum.h"

namespace rome {

struct HybridLinearInvertedPendulumSystemParams {
  HybridLinearInvertedPendulumParams hlip{};
  bool footed = false;  ///< declares the ankle_roll_torque input (footed H-LIP, Sec. IV-B)
  double mass = 76.0;   ///< [kg] m of the footed model (the aSLIP mass, spec §2.3)
  Eigen::Vector2d initial_state = Eigen::Vector2d(0.0, 0.0);  ///< [m, m/s]
  bool start_in_single_support = true;
  double initial_stance_foot_y = 0.0;  ///< [m]
  double initial_stance_side = 1.0;    ///< +1 left, −1 right
};

class HybridLinearInvertedPendulumSystem final : public LeafSystem {
 public:
  explicit HybridLinearInvertedPendulumSystem(std::string name = "hlip",
                                              HybridLinearInvertedPendulumSystemParams params = {});
  const HybridLinearInvertedPendulum& hlip() const { return hlip_; }
  int single_support_mode() const { return 0; }
  int double_support_mode() const { return 1; }

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  HybridLinearInvertedPendulumSystemParams params_;
  HybridLinearInvertedPendulum hlip_;
  int step_port_ = -1, torque_port_ = -1;
};

}  // namespace rome
