#pragma once
// The walking example's printed report and JSON summary: the plans' NLP reports, the plan's inverse dynamics against
// the torque limits, and the run's metrics (WalkingRunResult::ToJson) with the effective scenario.
#include <string>

#include <nlohmann/json.hpp>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_run.h"

namespace rome::examples {

/// Prints the start gait and lead-in the plan went through.
void PrintPlanReport(const WalkingPlanReport& nlp, const StandToWalkParams& stand);
/// CheckWalkingPlanTorques on the diagram's plan up to t_stop: printed, and as the summary's "plan_inverse_dynamics"
/// (null, with a printed warning, if it cannot be computed).
nlohmann::json PlanTorqueReport(const WalkingDiagram& d, const WalkingDiagramParams& params, double t_stop);
/// The summary: the run's metrics, the NLP reports ("nlp", "lead_in", "lead_in_tried", "start_gait"), the momentum
/// compensation, `plan_torques`, the plant and the effective scenario (`scenario`: every option's value).
nlohmann::json WalkingSummary(const WalkingRunResult& run, const WalkingDiagram& d, const WalkingPlanReport& nlp,
                              const std::string& scenario_name, const StandToWalkParams& stand, double compensation_s,
                              const nlohmann::json& plan_torques, PlantKind plant, const nlohmann::json& scenario);
/// The closing lines on stdout.
void PrintRunResult(const WalkingRunResult& run, PlantKind plant);

}  // namespace rome::examples
