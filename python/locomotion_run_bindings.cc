// Python bindings of the walking and hopping runs (diagrams/walking/walking_run.h, diagrams/hopping/hopping_run.h):
// plan → build → run, as the walking and hopping programs do, with the results as dicts (the programs' JSON metrics).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "diagrams/hopping/hopping_run.h"
#include "systems/plants/plant_kind.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "python/bindings.h"
#include "python/params.h"

namespace py = pybind11;

namespace rome::python {
namespace {

py::object JsonToPython(const std::string& json_text) { return py::module_::import("json").attr("loads")(json_text); }

/// Per control tick of a walking run: the COM and its plan, the plant's and the plan's normal forces (N x 3, N x 3,
/// N x 2, N x 2), the plant's mode and the steps so far.
struct WalkingSeries {
  std::vector<double> t, mode, steps;
  std::vector<double> com, com_reference, force, force_reference;

  void Record(const WalkingRunSample& s) {
    if (!s.tick) return;
    t.push_back(s.t);
    mode.push_back(s.mode);
    steps.push_back(s.steps);
    for (int i = 0; i < 3; ++i) com.push_back(s.com[i]), com_reference.push_back(s.reference.com_position[i]);
    const Eigen::VectorXd& f = *s.contact_forces;  // [F_left; F_right], world, N
    const int half = static_cast<int>(f.size()) / 2;
    force.push_back(f[half - 1]), force.push_back(f[f.size() - 1]);  // the normal (z) rows of the left and right foot
    force_reference.push_back(s.reference.normal_force[0]), force_reference.push_back(s.reference.normal_force[1]);
  }
  static py::array_t<double> Array(const std::vector<double>& v, py::ssize_t columns) {
    const auto rows = static_cast<py::ssize_t>(v.size()) / columns;
    py::array_t<double> a = columns > 1 ? py::array_t<double>({rows, columns}) : py::array_t<double>(rows);
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
  }
  py::dict ToDict() const {
    py::dict d;
    d["time"] = Array(t, 1);
    d["mode"] = Array(mode, 1);
    d["steps"] = Array(steps, 1);
    d["com"] = Array(com, 3);
    d["com_reference"] = Array(com_reference, 3);
    d["normal_force"] = Array(force, 2);
    d["normal_force_reference"] = Array(force_reference, 2);
    return d;
  }
};

/// Plan → build → RunWalking as examples/walking does for its stand-to-walk, gait-change and periodic scenarios.
py::object RunWalkingFromPython(const std::string& robot, const WalkingGait& gait, int steps,
                                const std::string& scenario, unsigned seed, WalkingRunParams run,
                                const WalkingGait& gait_b, bool record, const WalkingDiagramParams& diagram_params,
                                const std::string& plant) {
  if (scenario != "stand-to-walk" && scenario != "periodic" && scenario != "gait-change")
    throw py::value_error("run_walking: scenario must be 'stand-to-walk', 'gait-change' or 'periodic', got '" +
                          scenario + "'");
  if (steps < 1 || steps > 1000)
    throw py::value_error("run_walking: steps = " + std::to_string(steps) + " is outside [1, 1000]");
  if (scenario == "periodic") {
    run.start_time_s = 0.5 * gait.dsp_duration_s;
    run.start_at_rest = false;
  }
  const PlantKind plant_kind = ParsePlantKind(plant, "run_walking: plant");
  run.Validate();
  diagram_params.Validate();
  gait.Validate("run_walking: gait");
  if (scenario == "gait-change") gait_b.Validate("run_walking: gait_b");
  auto model =
      std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(robot, {.euler_floating_base = true}));
  CheckWalkingRobot(*model);  // a robot the diagram cannot use is bad input (ValueError), as in examples/walking
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, diagram_params);
  stand.change_check = WalkingChangeFeasibilityCheck(model, diagram_params);  // as examples/walking
  const int planned = steps + run.trailing_steps;
  WalkingPlan plan;
  if (scenario == "periodic")
    plan = BuildPeriodicWalkingPlan(gait, planned, seed, nullptr, stand);
  else if (scenario == "gait-change")
    plan = BuildGaitChangePlan(gait, gait_b, steps, seed, nullptr, nullptr, stand, planned);
  else
    plan = BuildStandToWalkPlan(gait, planned, seed, nullptr, nullptr, stand);
  const WalkingDiagram d = BuildWalkingDiagram(model, plan, diagram_params, plant_kind);
  WalkingFeasibilityParams feasibility;  // as examples/walking's default --feasibility torque
  feasibility.enforce_sole_wrench = feasibility.enforce_joint_limits = false;
  const WalkingFeasibilityReport f =
      CheckWalkingPlanFeasibility(*model, d.plan, diagram_params, WalkingRunEndTime(d.plan, run), feasibility);
  if (!f.problem.empty()) throw py::value_error("run_walking: " + f.problem);  // the program's exit 1
  WalkingSeries series;
  WalkingRunObserver observer;
  if (record) observer = [&series](const Context&, const WalkingRunSample& s) { series.Record(s); };
  const WalkingRunResult r = RunWalking(d, run, observer);
  py::dict result(JsonToPython(r.ToJson()));
  result["wall_s"] = r.wall_s;
  result["simulated_s"] = r.simulated_s;
  if (record) result["series"] = series.ToDict();
  return result;
}

/// Planners → build → RunHopping as examples/hopping does (Cassie, the hybrid plant).
py::object RunHoppingFromPython(int hops, double apex_rise_m, const std::string& leg_stiffness,
                                const HoppingRunParams& run, HoppingDiagramParams diagram_params,
                                const std::string& plant) {
  const PlantKind plant_kind = ParsePlantKind(plant, "run_hopping: plant");
  diagram_params.reference.hops = hops;
  diagram_params.Validate();
  run.Validate();
  auto model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar("robots/cassie/cassie.rome.json", {.euler_floating_base = true}));
  SpringMassJumpParams jump;
  jump.apex_rise = apex_rise_m;
  auto planners = std::make_unique<SpringMassHopPlanners>(*model, ParseLegStiffnessVariant(leg_stiffness), jump,
                                                          SpringMassLandingParams{});
  HoppingDiagram d =
      BuildHoppingDiagram(model, planners->leg_length, planners->jump, planners->landing, diagram_params, plant_kind);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  const HoppingRunResult r = RunHopping(d, sim, run, planners.get());
  return JsonToPython(HoppingSummaryJson(d, r, planners.get()));
}

}  // namespace

void BindWalkingDiagramParams(py::module_& m) {
  ParamsClass<SwingFootTrajectoryParams>(m, "SwingFootTrajectoryParams",
                                         "The walking swing foot's path (systems/planners/walking_output_reference.h).")
      .Field("apex_height_m", &SwingFootTrajectoryParams::apex_height_m, "[m]")
      .Field("touchdown_velocity_mps", &SwingFootTrajectoryParams::touchdown_velocity_mps, "[m/s]")
      .Field("ankle_height_m", &SwingFootTrajectoryParams::ankle_height_m, "[m] set from the robot's sole")
      .Field("pitch_max_rad", &SwingFootTrajectoryParams::pitch_max_rad, "[rad]");
  using C = CentroidalMomentumCompensationParams;
  ParamsClass<C>(m, "CentroidalMomentumCompensationParams",
                 "The walking plan's COM shift for the legs' angular momentum (centroidal_momentum_compensation.h).")
      .Field("sample_period_s", &C::sample_period_s, "[s]")
      .Field("iterations", &C::iterations);
  using W = WalkingDiagramParams;
  ParamsClass<W>(m, "WalkingDiagramParams",
                 "The walking diagram's blocks (diagrams/walking/walking_diagram.h); perturbations keep their C++ "
                 "default (none).")
      .Field("plant", &W::plant, "HybridContactPlantParams")
      .Field("bullet_plant", &W::bullet_plant, "BulletWorldPlantParams")
      .Field("controller", &W::controller, "ClfQpParams")
      .Field("swing", &W::swing)
      .Field("compensate_centroidal_momentum", &W::compensate_centroidal_momentum)
      .Field("compensation", &W::compensation)
      .Field("swing_foot_weight", &W::swing_foot_weight, "[-]")
      .Field("swing_foot_orientation_weight", &W::swing_foot_orientation_weight, "[-]")
      .Field("force_band_lead_periods", &W::force_band_lead_periods, "[controller update periods]")
      .cls()
      .def("validate", &W::Validate);
}

void BindHoppingDiagramParams(py::module_& m) {
  using O = HoppingOutputParams;
  ParamsClass<O>(m, "HoppingOutputParams", "The hopping CLF-QP's output weights and flight gains (hopping_outputs.h).")
      .Field("momentum_weight", &O::momentum_weight, "[-]")
      .Field("leg_length_weight", &O::leg_length_weight, "[-]")
      .Field("com_weight", &O::com_weight, "[-]")
      .Field("pelvis_weight", &O::pelvis_weight, "[-]")
      .Field("motor_weight", &O::motor_weight, "[-]")
      .Field("motor_kp", &O::motor_kp)
      .Field("motor_kd", &O::motor_kd)
      .Field("jump_tracks_momentum", &O::jump_tracks_momentum);
  using R = HoppingReferenceParams;
  ParamsClass<R>(m, "HoppingReferenceParams", "The hopping reference's timing and feedback (hopping_reference.h).")
      .Field("update_period_s", &R::update_period_s, "[s]")
      .Field("settle_time_s", &R::settle_time_s, "[s]")
      .Field("rest_time_s", &R::rest_time_s, "[s]")
      .Field("rest_max_speed", &R::rest_max_speed, "[m/s]")
      .Field("max_rest_time_s", &R::max_rest_time_s, "[s]")
      .Field("hops", &R::hops, "run_hopping's hops argument sets it")
      .Field("landing_blend_s", &R::landing_blend_s, "[s]")
      .Field("landing_fallback_s", &R::landing_fallback_s, "[s]")
      .Field("max_plan_nodes", &R::max_plan_nodes)
      .Field("jump_momentum_gain", &R::jump_momentum_gain)
      .Field("flight_hip_pitch_follow", &R::flight_hip_pitch_follow)
      .Field("landing_deflection_feedback", &R::landing_deflection_feedback)
      .Field("jump_force_feedback", &R::jump_force_feedback, "[-]")
      .Field("jump_force_integral_per_s", &R::jump_force_integral_per_s, "[1/s]")
      .Field("jump_force_correction_max_m", &R::jump_force_correction_max_m, "[m]");
  using H = HoppingDiagramParams;
  ParamsClass<H>(m, "HoppingDiagramParams",
                 "The hopping diagram's blocks (diagrams/hopping/hopping_diagram.h); perturbations and the robot's "
                 "joint and link names keep their C++ defaults.")
      .Field("plant", &H::plant, "HybridContactPlantParams")
      .Field("bullet_plant", &H::bullet_plant, "BulletWorldPlantParams")
      .Field("controller", &H::controller, "ClfQpParams")
      .Field("outputs", &H::outputs)
      .Field("reference", &H::reference)
      .Field("log_period_s", &H::log_period_s, "[s]")
      .Field("landing_u_regularization_scale", &H::landing_u_regularization_scale, "[-]")
      .cls()
      .def("validate", &H::Validate);
}

void BindLocomotionRuns(py::module_& m) {
  BindWalkingDiagramParams(m);
  BindHoppingDiagramParams(m);
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
      py::arg("gait_b") =
          WalkingGait{.step_length_m = 0.40, .ssp_duration_s = 0.40, .dsp_duration_s = 0.10, .step_width_m = 0.25},
      py::arg("record") = false, py::arg("diagram") = WalkingDiagramParams{}, py::arg("plant") = "hybrid",
      "Plans (stand-to-walk, gait-change from `gait` to `gait_b`, or periodic), builds the walking diagram with "
      "`diagram` on the `plant` ('hybrid' or 'bullet'), refuses "
      "(ValueError) a plan over a torque limit as the walking program does (CheckWalkingPlanFeasibility), and runs it "
      "(RunWalking). Returns the walking program's summary metrics as a dict (success, steps_completed, ...), "
      "plus wall_s and simulated_s; with record=True also 'series': per control tick time, mode, steps, com and "
      "com_reference (N x 3, m), normal_force and normal_force_reference (N x 2, N; left, right).");
  m.def("run_hopping", &RunHoppingFromPython, py::arg("hops") = 1,
        py::arg("apex_rise_m") = SpringMassJumpParams{}.apex_rise, py::arg("leg_stiffness") = "identified",
        py::arg("run") = HoppingRunParams{}, py::arg("diagram") = HoppingDiagramParams{}, py::arg("plant") = "hybrid",
        "Builds Cassie's hopping diagram with the spring-mass planners, `diagram` (its reference's hops set from "
        "`hops`) and the `plant` ('hybrid' or 'bullet'), and runs it (RunHopping). Returns the hopping program's "
        "summary as a dict (success, hopped, air_time_s, ...).");
}

}  // namespace rome::python
