// Python bindings of the walking and hopping runs (diagrams/walking/walking_run.h, diagrams/hopping/hopping_run.h):
// plan → build → run, as the walking and hopping programs do, with the results as dicts (the programs' JSON metrics).
#include <memory>
#include <string>

#include <pybind11/stl.h>

#include "diagrams/hopping/hopping_run.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "python/bindings.h"
#include "python/params.h"

namespace py = pybind11;

namespace rome::python {
namespace {

py::object JsonToPython(const std::string& json_text) { return py::module_::import("json").attr("loads")(json_text); }

/// Plan → build → RunWalking as examples/walking does for its stand-to-walk and periodic scenarios.
py::object RunWalkingFromPython(const std::string& robot, const WalkingGait& gait, int steps,
                                const std::string& scenario, unsigned seed, WalkingRunParams run) {
  if (scenario != "stand-to-walk" && scenario != "periodic")
    throw py::value_error("run_walking: scenario must be 'stand-to-walk' or 'periodic', got '" + scenario + "'");
  if (steps < 1 || steps > 1000)
    throw py::value_error("run_walking: steps = " + std::to_string(steps) + " is outside [1, 1000]");
  if (scenario == "periodic") {
    run.start_time_s = 0.5 * gait.dsp_duration_s;
    run.start_at_rest = false;
  }
  run.Validate();
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(robot));
  CheckWalkingRobot(*model);  // a robot the diagram cannot use is bad input (ValueError), as in examples/walking
  const WalkingDiagramParams diagram_params;
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, diagram_params);
  const int planned = steps + run.trailing_steps;
  const WalkingPlan plan = scenario == "periodic" ? BuildPeriodicWalkingPlan(gait, planned, seed, nullptr, stand)
                                                  : BuildStandToWalkPlan(gait, planned, seed, nullptr, nullptr, stand);
  const WalkingDiagram d = BuildWalkingDiagram(model, plan, diagram_params);
  WalkingFeasibilityParams feasibility;  // as examples/walking's default --feasibility torque
  feasibility.enforce_sole_wrench = feasibility.enforce_joint_limits = false;
  const WalkingFeasibilityReport f =
      CheckWalkingPlanFeasibility(*model, d.plan, diagram_params, WalkingRunEndTime(d.plan, run), feasibility);
  if (!f.problem.empty()) throw py::value_error("run_walking: " + f.problem);  // the program's exit 1
  const WalkingRunResult r = RunWalking(d, run);
  py::dict result(JsonToPython(r.ToJson()));
  result["wall_s"] = r.wall_s;
  result["simulated_s"] = r.simulated_s;
  return result;
}

/// Planners → build → RunHopping as examples/hopping does (Cassie, the hybrid plant).
py::object RunHoppingFromPython(int hops, double apex_rise_m, const std::string& leg_stiffness,
                                const HoppingRunParams& run) {
  run.Validate();
  auto model =
      std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar("robots/cassie/cassie.rome.json"));
  SpringMassJumpParams jump;
  jump.apex_rise = apex_rise_m;
  HoppingDiagramParams diagram_params;
  diagram_params.reference.hops = hops;
  auto planners = std::make_unique<SpringMassHopPlanners>(*model, ParseLegStiffnessVariant(leg_stiffness), jump,
                                                          SpringMassLandingParams{});
  HoppingDiagram d =
      BuildHoppingDiagram(model, planners->leg_length, planners->jump, planners->landing, diagram_params);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  const HoppingRunResult r = RunHopping(d, sim, run, planners.get());
  return JsonToPython(HoppingSummaryJson(d, r, planners.get()));
}

}  // namespace

void BindLocomotionRuns(py::module_& m) {
  ParamsClass<WalkingGait>(m, "WalkingGait",
                           "A periodic walking gait (diagrams/walking/walking_diagram.h), gait A by default.")
      .Field("step_length_m", &WalkingGait::step_length_m)
      .Field("ssp_duration_s", &WalkingGait::ssp_duration_s)
      .Field("dsp_duration_s", &WalkingGait::dsp_duration_s)
      .Field("step_width_m", &WalkingGait::step_width_m)
      .cls()
      .def("validate", &WalkingGait::Validate, py::arg("who") = "WalkingGait");
  ParamsClass<WalkingRunParams>(m, "WalkingRunParams", "What a walking run measures and judges (walking_run.h).")
      .Field("end_time_s", &WalkingRunParams::end_time_s, "[s] NaN: the plan's end less trailing_steps steps")
      .Field("trailing_steps", &WalkingRunParams::trailing_steps)
      .Field("foothold_tolerance_m", &WalkingRunParams::foothold_tolerance_m)
      .Field("tick_period_s", &WalkingRunParams::tick_period_s)
      .Field("band_settle_s", &WalkingRunParams::band_settle_s)
      .Field("band_slack_mg", &WalkingRunParams::band_slack_mg)
      .Field("convergence_from_step", &WalkingRunParams::convergence_from_step)
      .cls()
      .def("validate", &WalkingRunParams::Validate);
  ParamsClass<HoppingRunParams>(m, "HoppingRunParams", "What a hopping run measures and judges (hopping_run.h).")
      .Field("duration_s", &HoppingRunParams::duration_s, "[s] 0: until stop_after_last_touchdown_s after the last hop")
      .Field("stop_after_last_touchdown_s", &HoppingRunParams::stop_after_last_touchdown_s)
      .Field("rest_check_delay_s", &HoppingRunParams::rest_check_delay_s)
      .Field("rest_max_speed", &HoppingRunParams::rest_max_speed)
      .Field("min_com_rise_fraction", &HoppingRunParams::min_com_rise_fraction)
      .Field("sample_period_s", &HoppingRunParams::sample_period_s)
      .Field("landing_grf_skip_s", &HoppingRunParams::landing_grf_skip_s)
      .cls()
      .def("validate", &HoppingRunParams::Validate);
  m.def(
      "run_walking", &RunWalkingFromPython, py::arg("robot") = "robots/exoskeleton/exoskeleton.rome.json",
      py::arg("gait") = WalkingGait{}, py::arg("steps") = 10, py::arg("scenario") = "stand-to-walk",
      py::arg("seed") = 1u, py::arg("run") = WalkingRunParams{},
      "Plans (stand-to-walk or periodic), builds the walking diagram, refuses (ValueError) a plan over a torque limit "
      "as the walking program does (CheckWalkingPlanFeasibility), and runs it (RunWalking). Returns the walking "
      "program's summary metrics as a dict (success, steps_completed, ...), plus wall_s and simulated_s.");
  m.def("run_hopping", &RunHoppingFromPython, py::arg("hops") = 1,
        py::arg("apex_rise_m") = SpringMassJumpParams{}.apex_rise, py::arg("leg_stiffness") = "identified",
        py::arg("run") = HoppingRunParams{},
        "Builds Cassie's hopping diagram with the spring-mass planners and runs it (RunHopping). Returns the hopping "
        "program's "
        "summary as a dict (success, hopped, air_time_s, ...).");
}

}  // namespace rome::python
