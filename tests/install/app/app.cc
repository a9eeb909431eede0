// Builds the stepping-stones diagram from an installed ROME, with the robot found in the installed data folder
// (a relative path that does not exist from the current folder), and walks 3 steps on flat ground.
#include <iostream>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"

int main() {
  using namespace rome;
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 3;
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 6), params, ClfQpControllerFactory(params));
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  const SimulatorStatus status = sim.AdvanceTo(10.0);
  std::cout << status.ToString() << "\n";
  return status.kind() == SimulatorStatus::Kind::kSuccess ? 0 : 3;
}
