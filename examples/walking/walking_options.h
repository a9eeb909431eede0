#pragma once
// The walking example's command line: its options, parsed into the library's parameter structs. Parsing only checks
// the form of a value (a number, a list of numbers, one of the listed words); the ranges are the library's Validate()
// (WalkingGait, StandToWalkParams, WalkingDiagramParams, WalkingRunParams), called by ValidateWalkingOptions.
#include <cstdint>
#include <string>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_run.h"
#include "examples/common/cli.h"

namespace rome::examples {

struct WalkingOptions {
  std::string scenario = "stand-to-walk";  ///< stand-to-walk | gait-change | periodic | gait-sequence | walk-to-stand
  WalkingGait gait_a, gait_b;
  std::vector<WalkingGait> gaits;       ///< gait-sequence: --gaits
  int steps = 10;                       ///< periodic single supports per gait after each transition
  std::uint32_t seed = 1;               ///< seed of the NLP initial guesses
  std::uint32_t perturbation_seed = 1;  ///< seed of the perturbations' random draws (--perturbation-seed)
  PlantKind plant = PlantKind::kHybrid;
  std::string feasibility = "torque";  ///< torque | strict | off: what the plan's feasibility check refuses
  bool check_only = false;             ///< plan and check, no simulation
  StandToWalkParams stand;             ///< its sole is set from the robot (SoleOf) before planning
  WalkingDiagramParams diagram;
  WalkingRunParams run;  ///< start time and velocity set for the periodic scenario
};

/// The library parameter each option sets, as the Validate() messages name it ({parameter, option}), so that an error
/// names the option (CommandLine::NameTheOption).
extern const std::vector<std::pair<std::string, std::string>> kWalkingParameterOptions;
/// Declares the options (with --scenario-file), their defaults and help.
void DeclareWalkingOptions(CommandLine& cli);
/// The options' values in the structs above. Throws std::invalid_argument naming the option for a value of the wrong
/// form; ranges are left to ValidateWalkingOptions.
WalkingOptions ParseWalkingOptions(const CommandLine& cli);
/// The library's Validate() of every struct (a gait names its flag), and --steps in [1, 1000].
void ValidateWalkingOptions(const WalkingOptions& options);

}  // namespace rome::examples
