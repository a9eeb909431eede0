#pragma once
// SpringMassSystem: the spring-mass hopping ROM of the hopping paper (Sec. III-B) as a framework block.
//
// continuous state (4): z = [x (m), ẋ (m/s), L (m), L̇ (m/s)]   (conventions in spring_mass_model.h)
// input:   leg_length_acceleration (1) = v = L̈ (m/s²)
// outputs: state (4)      = z
//          leg_force (1)  = F (N), total over the n_legs legs = the ROM's vertical ground reaction;
//                           max(0, n_legs (K(L) s + D(L) ṡ)): the feet cannot pull, so F = 0 in flight
//          energy (3)     = [kinetic ½ m ẋ², potential m g x, spring ½ n_legs K(L) s² (0 when s < 0)] (J)
// flow:    ẍ = F/m − g, L̈ = v (Sec. III-B). No allocation in the flow or the outputs.
// A non-finite initial_state, or a leg length L <= 0 in it, is refused by the constructor (an error naming the
// system, the element and its value).

#include <string>

#include "framework/system.h"
#include "systems/rom/spring_mass_model.h"

namespace rome {

struct SpringMassSystemParams {
  SpringMassParams model{};
  Eigen::Vector4d initial_state = Eigen::Vector4d(0.78, 0.0, 0.8, 0.0);  ///< z(0) [m, m/s, m, m/s] (ours)
};

class SpringMassSystem final : public LeafSystem {
 public:
  explicit SpringMassSystem(std::string name = "spring_mass", SpringMassSystemParams params = {});
  const SpringMassModel& model() const { return model_; }
  /// F clipped at 0 (unilateral contact), as on the leg_force port.
  double ContactForce(const Eigen::Vector4d& z) const;

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  SpringMassModel model_;
  int input_port_ = -1;
};

}  // namespace rome
