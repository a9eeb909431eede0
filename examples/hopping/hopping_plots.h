#pragma once
// The hopping example's PNG plots (the paper's Fig. 6 from a run): robot vs ROM normal GRF shaded by domain (the ROM's
// line broken where it has no plan), COM height, shin spring torque above the GRF (two panels), centroidal pitch
// momentum, pelvis pitch, desired vs actual outputs in Jump and Landing (leg length, COM x, pelvis pitch), energies
// robot vs ROM, and hop tiles. Needs RunHopping's samples with
// HoppingRunParams::record_plot_samples.
#include <string>

#include "diagrams/hopping/hopping_run.h"

namespace rome::examples {

/// Writes the ten PNGs into `folder`; a plot that fails is reported on stderr ("hopping: plot FILE: reason") and the
/// others are still written.
void WriteHoppingPlots(const MultibodyModel& model, const HoppingRunResult& run, const std::string& folder);

}  // namespace rome::examples
