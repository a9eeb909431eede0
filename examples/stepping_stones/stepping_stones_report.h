#pragma once
// What the stepping_stones example writes from a run (RunSteppingStones): the JSON summary, the PNG plots and the
// closing lines on stdout.

#include <string>

#include <nlohmann/json.hpp>

#include "diagrams/stepping_stones/stepping_stones_run.h"
#include "examples/stepping_stones/stepping_stones_options.h"

namespace rome::examples {

/// The summary: the result's figures, its step records, the integrator's counters, the stones and the scenario's
/// energy, epsilon, terrain and seed.
nlohmann::json SteppingStonesSummary(const SteppingStonesResult& r, const SteppingStonesScenario& scenario,
                                     const CommandLine& cli);

/// Writes com_height.png, phase_portrait.png (p_com^x, L_y against the LIP orbit of E*), gait_tiles.png (stick
/// figures every 0.1 s over the stones) and the paper's Fig. 5: outputs.png (torso pitch and COM height, desired
/// against actual; ż against u_des(t)), pre_impact_vz.png and pre_impact_vz.csv (per step, the plant's pre-impact ż
/// against the planner's u_des) into `dir` from the diagram's log; a plot that cannot be drawn is a warning.
void WriteSteppingStonesPlots(const SteppingStonesDiagram& d, const Context& context,
                              const SteppingStonesScenario& scenario, const std::string& energy_label,
                              const std::string& dir);

/// The closing lines: status, steps, speed, failures, contact forces and the result line. Returns the exit code: 0
/// success, 3 a failed run, 128 + signal when interrupted.
int PrintSteppingStonesReport(const SteppingStonesResult& r, const SteppingStonesScenario& scenario);

}  // namespace rome::examples
