#pragma once
// SteppingLinearInvertedPendulum: the walking reduced-order model of the stepping-stones paper — the LIP flow
// Eq. (12) in single support, and the impact map Eq. (17) when the COM reaches the pre-impact position
// p_com^x = ε l_des (Sec. IV-1), with the pre-impact vertical COM velocity u_des as the discrete input.
// Used to test planners on the ROM (a "ROM orbit") and as a fast preview model.
//
// continuous state (2): [x (m), L (m²/s)] relative to the current stance foot (see linear_inverted_pendulum.h)
// discrete state (3):   [stance foot x (m), stance foot z (m) in the world, number of steps taken]
// inputs:  step (2)                      = [l_des (m), h_des (m)]: next foothold relative to the stance foot.
//          impact_vertical_velocity (1)  = u_des = ṗ_com^{z−} (m/s), read only at impact.
// outputs: state (2)          = [x (m), L (m²/s)]
//          com_state (4)      = [p^x, p^z (m), ṗ^x, ṗ^z (m/s)] relative to the stance foot, on the virtual slope:
//                               p^z = (h/l) x + z0, ṗ^x = L / z0, ṗ^z = (h/l) ṗ^x. Reads input 'step'.
//          stance_foot (2)    = world position of the stance foot (m)
//          orbital_energy (1) = Eq. (16) (m²/s²)
// guard:   "touchdown": x − ε l crosses 0 rising.
// reset:   Eq. (17): x⁺ = x⁻ − l,  L⁺ = L⁻ + l u_des − h ẋ⁻ (ẋ⁻ = L⁻/z0); stance foot += (l, h).
// The LIP height z0 above the virtual slope is a constant of the model (it does not change across steps).

#include <string>

#include "framework/system.h"
#include "systems/rom/linear_inverted_pendulum.h"

namespace rome {

struct SteppingLinearInvertedPendulumParams {
  LinearInvertedPendulumParams lip{};
  /// [-] ε: impact when x = ε l_des (Sec. IV-1, p_comf^{x,d} = ε l_des). Paper: ε = 0.6 (Sec. VI, Fig. 6).
  double impact_fraction = 0.6;
  double initial_x = -0.15;  ///< [m]
  double initial_L = 0.5;    ///< [m²/s]
};

class SteppingLinearInvertedPendulum final : public LeafSystem {
 public:
  explicit SteppingLinearInvertedPendulum(std::string name = "stepping_lip",
                                          SteppingLinearInvertedPendulumParams params = {});
  const LinearInvertedPendulum& lip() const { return lip_; }
  const SteppingLinearInvertedPendulumParams& params() const { return params_; }

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  /// Reads and checks the 'step' input.
  Eigen::Vector2d Step(const LeafContext& context) const;
  SteppingLinearInvertedPendulumParams params_;
  LinearInvertedPendulum lip_;
  int step_port_ = -1, u_port_ = -1;
};

}  // namespace rome
