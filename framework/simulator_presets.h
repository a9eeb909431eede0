#pragma once
// Named SimulatorConfig presets, for diagrams that share integrator settings.

#include "framework/simulator.h"

namespace rome {

/// ARKODE's explicit Bogacki-Shampine 3(2), each control interval started with the step size the error test asked for
/// at the end of the previous one (SimulatorConfig::restart_with_last_step). For fixed-rate control loops whose
/// zero-order hold restarts the integrator every sample on a flow that is not stiff at those step sizes; measured on
/// the 2 kHz hopping loop (diagrams/hopping, HoppingSimulatorConfig) and the 1 kHz walking loop
/// (WalkingSimulatorConfig).
inline SimulatorConfig ExplicitRestartingSimulatorConfig(double relative_tolerance = 1e-5,
                                                         double absolute_tolerance = 1e-7) {
  SimulatorConfig c;
  c.scheme = IntegrationScheme::kExplicitRungeKutta;
  c.explicit_rk_method = ExplicitRungeKuttaMethod::kBogackiShampine32;
  c.restart_with_last_step = true;
  c.relative_tolerance = relative_tolerance;
  c.absolute_tolerance = absolute_tolerance;
  return c;
}

}  // namespace rome
