#pragma once
// LinearInvertedPendulumSystem: the LIP flow Eq. (12) of the stepping-stones paper as a framework block
// (continuous only, no impacts; see SteppingLinearInvertedPendulum for the walking ROM with impacts).
//
// continuous state (2): [x (m), L (m²/s)] relative to the stance foot (conventions in linear_inverted_pendulum.h)
// outputs: state (2)           = [x (m), L (m²/s)]
//          orbital_energy (1)  = E = ẋ² − λ² x² (m²/s²), Eq. (16)
// flow:    ẋ = L / z0, L̇ = g x, Eq. (12)

#include <string>

#include "framework/system.h"
#include "systems/rom/linear_inverted_pendulum.h"

namespace rome {

struct LinearInvertedPendulumSystemParams {
  LinearInvertedPendulumParams lip{};
  double initial_x = -0.15;  ///< [m] (Fig. 1(c) of the paper starts at x0 = −0.15 m)
  double initial_L = 0.5;    ///< [m²/s]
};

class LinearInvertedPendulumSystem final : public LeafSystem {
 public:
  explicit LinearInvertedPendulumSystem(std::string name = "lip", LinearInvertedPendulumSystemParams params = {});
  const LinearInvertedPendulum& lip() const { return lip_; }

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  LinearInvertedPendulum lip_;
};

}  // namespace rome
