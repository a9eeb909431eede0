#pragma once
// The stepping_stones example's command line: its options, and the scenario (diagram parameters, terrain, controller,
// plant) they describe. Each error names the option and the value.

#include <string>
#include <utility>
#include <vector>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "examples/common/cli.h"

namespace rome::examples {

struct SteppingStonesScenario {
  SteppingStonesDiagramParams params;
  Terrain terrain;
  SteppingStonesControllerFactory controller;  ///< empty: the task-space QP
  PlantKind plant = PlantKind::kHybrid;
  int steps = 0;
};

/// Declares every option of the example (with its default and help text) on `cli`.
void DeclareSteppingStonesOptions(CommandLine& cli);
/// The diagram parameter each option sets, as SteppingStonesDiagramParams::Validate names it ({parameter, option}),
/// so that an error names the option (CommandLine::NameTheOption).
extern const std::vector<std::pair<std::string, std::string>> kSteppingStonesParameterOptions;
/// The scenario of a parsed command line; also checks the output options (CommandLine::CheckOutputs).
SteppingStonesScenario SteppingStonesScenarioFromCommandLine(const CommandLine& cli);

}  // namespace rome::examples
