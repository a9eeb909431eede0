// Python bindings of the stepping-stones diagram and its run (diagrams/stepping_stones/stepping_stones_run.h):
// terrains, the diagram's parameters as Python objects, and RunSteppingStones with its result as a dict.
#include <cmath>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "diagrams/stepping_stones/stepping_stones_feasibility.h"
#include "diagrams/stepping_stones/stepping_stones_run.h"
#include "python/bindings.h"
#include "python/params.h"

namespace py = pybind11;

namespace rome::python {
namespace {

void BindTerrain(py::module_& m) {
  py::class_<SteppingStone>(m, "SteppingStone")
      .def(py::init<>())
      .def_readwrite("x_center_m", &SteppingStone::x_center_m)
      .def_readwrite("top_height_m", &SteppingStone::top_height_m)
      .def_readwrite("length_m", &SteppingStone::length_m)
      .def("__repr__", [](const SteppingStone& s) {
        return "SteppingStone(x_center_m=" + std::to_string(s.x_center_m) +
               ", top_height_m=" + std::to_string(s.top_height_m) + ", length_m=" + std::to_string(s.length_m) + ")";
      });
  py::class_<Terrain>(m, "Terrain", "Flat ground or a row of stepping stones along x (systems/plants/terrain.h).")
      .def_static("flat", &Terrain::Flat, py::arg("height_m") = 0.0)
      .def_static("stones", &Terrain::Stones, py::arg("stones"))
      .def_static("from_csv", &Terrain::FromCsv, py::arg("path"), py::arg("default_length_m"))
      .def("stone_list", &Terrain::stones);
  ParamsClass<RandomSteppingStonesParams>(m, "RandomSteppingStonesParams", "Random stones as in the paper's Sec. VI-C.")
      .Field("num_stones", &RandomSteppingStonesParams::num_stones)
      .Field("min_gap_m", &RandomSteppingStonesParams::min_gap_m)
      .Field("max_gap_m", &RandomSteppingStonesParams::max_gap_m)
      .Field("max_rise_m", &RandomSteppingStonesParams::max_rise_m)
      .Field("stone_length_m", &RandomSteppingStonesParams::stone_length_m)
      .Field("seed", &RandomSteppingStonesParams::seed);
  m.def("periodic_stepping_stones", &PeriodicSteppingStones, py::arg("step_length_m"), py::arg("step_height_m"),
        py::arg("num_stones"), py::arg("stone_length_m") = 0.1,
        "Stones step_length_m apart, each step_height_m above the previous, the first at x = 0.");
  m.def("random_stepping_stones", &RandomSteppingStones, py::arg("params"));
}

void BindParams(py::module_& m) {
  ParamsClass<SteppingStonesSupervisorParams>(m, "SteppingStonesSupervisorParams",
                                              "The supervisor's parameters (stepping_stones_supervisor.h).")
      .Field("update_period_s", &SteppingStonesSupervisorParams::update_period_s, "[s]")
      .Field("impact_fraction", &SteppingStonesSupervisorParams::impact_fraction, "epsilon [-]")
      .Field("max_steps", &SteppingStonesSupervisorParams::max_steps, "the run ends after this many steps")
      .Field("min_com_height_m", &SteppingStonesSupervisorParams::min_com_height_m,
             "[m] fall threshold above the stance foot")
      .Field("nominal_step_duration_s", &SteppingStonesSupervisorParams::nominal_step_duration_s, "[s]")
      .Field("walking_com_height_m", &SteppingStonesSupervisorParams::walking_com_height_m, "[m]")
      .Field("max_com_foot_distance_m", &SteppingStonesSupervisorParams::max_com_foot_distance_m,
             "[m] long steps lower the pre-impact COM to stay this close to both feet (inf: no cap)");
  ParamsClass<SteppingStonesDiagramParams> p(
      m, "SteppingStonesDiagramParams",
      "The stepping-stones diagram's parameters (stepping_stones_diagram.h); keyword constructor.");
  p.Field("robot_sidecar", &SteppingStonesDiagramParams::robot_sidecar)
      .Field("target_orbital_energy", &SteppingStonesDiagramParams::target_orbital_energy, "E* [m^2/s^2]")
      .Field("impact_fraction", &SteppingStonesDiagramParams::impact_fraction, "epsilon [-]")
      .Field("log_period_s", &SteppingStonesDiagramParams::log_period_s, "[s]")
      .Field("initial_com_x_m", &SteppingStonesDiagramParams::initial_com_x_m, "[m]")
      .Field("supervisor", &SteppingStonesDiagramParams::supervisor)
      .Field("planner", &SteppingStonesDiagramParams::planner,
             "the momentum-regulation planner's parameters (Eq. (25)-(27); u_des bound: AMBER -1.5 m/s, planar "
             "Cassie -1 m/s); its E* and epsilon are taken from this object's target_orbital_energy and "
             "impact_fraction");
  p.cls()
      .def_static("for_robot", &SteppingStonesDiagramParams::ForRobot, py::arg("sidecar"),
                  "The defaults adapted to the robot of `sidecar`.")
      .def("validate", &SteppingStonesDiagramParams::Validate);
}

py::dict StepDict(const StepRecord& s) {
  py::dict d;
  d["start_time_s"] = s.start_time_s;
  d["duration_s"] = s.duration_s;
  d["step_length_m"] = s.step_length_m;
  d["step_height_m"] = s.step_height_m;
  d["pre_impact_com_vz_mps"] = s.pre_impact_com_vz_mps;
  d["u_des_mps"] = s.u_des_mps;
  d["post_impact_momentum"] = s.post_impact_momentum;
  d["L_des"] = s.L_des;
  d["foothold_error_m"] = s.foothold_error_m;
  d["stone"] = s.stone;
  d["planned_stone"] = s.planned_stone;
  d["posture_ok"] = s.posture_ok;
  return d;
}

py::dict ResultDict(const SteppingStonesResult& r) {
  py::dict d;
  d["success"] = r.success;
  d["fell"] = r.fell;
  d["status"] = r.status;
  d["status_kind"] = r.status.kind_name();
  d["message"] = r.status.message;
  py::list steps;
  for (const StepRecord& s : r.steps) steps.append(StepDict(s));
  d["steps"] = steps;
  d["steps_completed"] = r.steps.size();
  d["mean_forward_speed_mps"] = r.mean_forward_speed_mps();
  d["u_squared_integral_N2m2s"] = r.u_squared_integral_N2m2s;
  d["u_squared_integral_per_step"] = r.u_squared_integral_per_step();
  d["tracking_rms"] = py::dict(py::arg("torso_pitch_rad") = r.tracking_torso_pitch_rms_rad,
                               py::arg("com_height_m") = r.tracking_com_height_rms_m,
                               py::arg("swing_foot_m") = r.tracking_swing_foot_rms_m);
  d["sim_time_s"] = r.sim_time_s;
  d["wall_time_s"] = r.wall_time_s;
  d["x_start_m"] = r.x_start_m;
  d["x_end_m"] = r.x_end_m;
  d["max_foothold_error_m"] = r.max_foothold_error_m;
  d["qp_failures"] = r.qp_failures;
  d["nlp_failures"] = r.nlp_failures;
  d["controller"] = r.controller_kind;
  d["max_friction_ratio"] = r.contact.max_friction_ratio;
  d["contact_violations"] = r.contact.violations;
  d["integrator"] = py::dict(py::arg("steps") = r.integrator.steps, py::arg("rhs_evaluations") = r.integrator.rhs_evals,
                             py::arg("root_evaluations") = r.integrator.root_evals,
                             py::arg("guard_events") = r.integrator.guard_events,
                             py::arg("discrete_samples") = r.integrator.discrete_samples);
  return d;
}

/// Build → initial state → RunSteppingStones, as examples/stepping_stones does (SteppingStonesSimulatorConfig).
py::dict RunSteppingStonesFromPython(const Terrain& terrain, const SteppingStonesDiagramParams& params,
                                     const std::string& controller, double max_time_s) {
  SteppingStonesControllerFactory factory;
  if (controller == "clf-qp")
    factory = ClfQpControllerFactory(params);
  else if (controller != "tsc-qp")
    throw py::value_error("run_stepping_stones: controller must be 'tsc-qp' or 'clf-qp', got '" + controller + "'");
  // What the diagram cannot walk is bad input (ValueError) before the simulation, as in examples/stepping_stones.
  CheckSteppingStonesFeasible(MultibodyModel::LoadFromSidecar(params.robot_sidecar, {.euler_floating_base = true}),
                              terrain, params);
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params, factory);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  sim.Initialize();
  SteppingStonesRunOptions options;
  options.max_time_s = max_time_s;
  return ResultDict(RunSteppingStones(d, sim, options));
}

}  // namespace

void BindSteppingStones(py::module_& m) {
  BindTerrain(m);
  BindParams(m);
  m.def("run_stepping_stones", &RunSteppingStonesFromPython, py::arg("terrain"),
        py::arg("params") = SteppingStonesDiagramParams{}, py::arg("controller") = "tsc-qp",
        py::arg("max_time_s") = std::nan(""),
        "Builds the stepping-stones diagram for `terrain`, starts it standing on the first stone and runs it to the "
        "supervisor's "
        "verdict (RunSteppingStones). Returns the result as a dict (success, status_kind, steps, "
        "mean_forward_speed_mps, ...).");
}

}  // namespace rome::python
