#pragma once
// The perturbation options every example that simulates a robot can take (systems/perturbations/), and the
// PerturbationParams they describe. Each error names the option and the value.

#include <string>
#include <utility>
#include <vector>

#include "examples/common/cli.h"
#include "systems/multibody/multibody_model.h"
#include "systems/perturbations/perturbation_params.h"

namespace rome::examples {

/// Declares --push-body, --push-time, --push-duration, --push-force, --push-impulse, --mass-scale, --friction-scale,
/// --stone-height-error, --sensor-noise, --latency, --torque-noise (the seed is the example's --seed).
void DeclarePerturbationOptions(CommandLine& cli);
/// The perturbations of a parsed command line for `model` (the controller's: the pushed link must exist; "base" is
/// the link of the floating base's last coordinate). `seed`: the example's seed. `period_s`: the controller's sample
/// period (noise and latency are sampled at it; --latency must be a whole number of periods).
PerturbationParams PerturbationsFromCommandLine(const CommandLine& cli, const MultibodyModel& model, std::uint64_t seed,
                                                double period_s);

/// The perturbations of an example on flat ground (walking, hopping): PerturbationsFromCommandLine, with its errors in
/// the command line's terms, and a one-line error "PROGRAM: --stone-height-error ..." (there are no stones).
PerturbationParams FlatGroundPerturbationsFromCommandLine(const CommandLine& cli, const std::string& program,
                                                          const MultibodyModel& model, std::uint64_t seed,
                                                          double period_s);

/// PerturbationParams' fields and the options that set them ({parameter, option}, CommandLine::NameTheOption).
extern const std::vector<std::pair<std::string, std::string>> kPerturbationParameterOptions;

}  // namespace rome::examples
