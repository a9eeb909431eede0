// LinearInvertedPendulumSystem: the numerically integrated Eq. (12) (framework Simulator, CVODE) against the
// closed-form flow Eq. (13); orbital energy output conserved.
#include "systems/rom/linear_inverted_pendulum_system.h"

#include <gtest/gtest.h>

#include <cmath>

#include "framework/simulator.h"

namespace rome {
namespace {

TEST(LinearInvertedPendulumSystem, SimulatedFlowMatchesClosedForm) {
  LinearInvertedPendulumSystemParams params;
  params.lip.z0 = 0.8;
  params.initial_x = -0.15;
  params.initial_L = 0.45;
  LinearInvertedPendulumSystem system("lip", params);
  SimulatorConfig config;
  config.relative_tolerance = 1e-12;
  config.absolute_tolerance = 1e-13;
  Simulator sim(system, config);
  const Eigen::Vector2d x0(params.initial_x, params.initial_L);
  const double E0 = system.lip().OrbitalEnergy(x0);
  double worst_state = 0, worst_energy = 0;
  for (int k = 1; k <= 40; ++k) {
    const double t = 0.025 * k;
    ASSERT_TRUE(sim.AdvanceTo(t).ok());
    const Eigen::Vector2d expected = system.lip().Flow(x0, t);
    const Eigen::VectorXd& state = system.EvalOutput(sim.get_context(), "state");
    worst_state = std::max(worst_state, (state - expected).norm() / (1 + expected.norm()));
    worst_energy = std::max(worst_energy, std::abs(system.EvalOutput(sim.get_context(), "orbital_energy")[0] - E0));
  }
  EXPECT_LT(worst_state, 1e-9);
  EXPECT_LT(worst_energy, 1e-9);
  std::printf("LIP flow vs CVODE over 1 s: max relative state error %.3e, max energy drift %.3e m^2/s^2\n", worst_state,
              worst_energy);
}

}  // namespace
}  // namespace rome
