// Python bindings of the planners (systems/planners): the momentum-regulation planner and the vertical-COM MPC of the
// stepping-stones paper, the spring-mass jump and landing planners of the hopping paper and the footed H-LIP
// transition QP of the walking paper. Their results come back as dicts of numbers and numpy arrays.
#include <cmath>
#include <string>
#include <utility>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "systems/planners/footed_hlip_transition_planner.h"
#include "systems/planners/momentum_regulation_planner.h"
#include "systems/planners/momentum_regulation_planner_system.h"
#include "systems/planners/spring_mass_hop_planner.h"
#include "systems/planners/vertical_com_mpc.h"
#include "systems/planners/vertical_com_mpc_system.h"

namespace py = pybind11;

namespace rome::python {
namespace {

py::dict MomentumPlanToDict(const MomentumRegulationPlan& p) {
  py::dict d;
  d["ok"] = p.ok();
  d["status"] = p.status;
  d["L_des"] = p.L_des;
  d["L_pre_impact"] = p.L_pre_impact;
  d["u_des"] = p.u_des;
  d["time_to_impact"] = p.time_to_impact;
  d["time_to_impact_raw"] = p.time_to_impact_raw;
  d["slope_adjusted_height"] = p.slope_adjusted_height;
  d["post_impact_height"] = p.post_impact_height;
  d["pre_impact_position"] = p.pre_impact_position;
  return d;
}

void BindMomentumRegulation(py::module_& m) {
  ParamsClass<MomentumRegulationPlannerParams>(m, "MomentumRegulationPlannerParams",
                                               "Momentum regulation of the stepping-stones paper, Sec. IV.")
      .Field("target_orbital_energy", &MomentumRegulationPlannerParams::target_orbital_energy, "[m^2/s^2] E*")
      .Field("impact_fraction", &MomentumRegulationPlannerParams::impact_fraction, "[-] epsilon")
      .Field("gravity", &MomentumRegulationPlannerParams::gravity, "[m/s^2]")
      .Field("min_time_to_impact_s", &MomentumRegulationPlannerParams::min_time_to_impact_s)
      .Field("max_time_to_impact_s", &MomentumRegulationPlannerParams::max_time_to_impact_s)
      .Field("min_pre_impact_vertical_velocity_mps",
             &MomentumRegulationPlannerParams::min_pre_impact_vertical_velocity_mps,
             "[m/s] u_des is at least this (-inf: the paper's unbounded Eq. (26))");
  ParamsClass<MomentumRegulationInput>(m, "MomentumRegulationInput",
                                       "The planner's input (relative to the stance foot).")
      .Field("p_com_x", &MomentumRegulationInput::p_com_x, "[m]")
      .Field("p_com_z", &MomentumRegulationInput::p_com_z, "[m]")
      .Field("pdot_com_x", &MomentumRegulationInput::pdot_com_x, "[m/s]")
      .Field("L_y", &MomentumRegulationInput::L_y, "[m^2/s] about the stance foot")
      .Field("step_length", &MomentumRegulationInput::step_length, "[m]")
      .Field("step_height", &MomentumRegulationInput::step_height, "[m]")
      .Field("pre_impact_com_height", &MomentumRegulationInput::pre_impact_com_height, "[m]");
  py::class_<MomentumRegulationPlanner>(m, "MomentumRegulationPlanner", "Eq. (23)-(27) of the stepping-stones paper.")
      .def((InitFromArguments<MomentumRegulationPlanner, MomentumRegulationPlannerParams>()),
           py::arg("params") = MomentumRegulationPlannerParams{})
      .def_property_readonly("params", &MomentumRegulationPlanner::params)
      .def(
          "plan",
          [](const MomentumRegulationPlanner& planner, const MomentumRegulationInput& in) {
            return MomentumPlanToDict(planner.Plan(in));
          },
          py::arg("input"))
      .def("desired_post_impact_momentum", &MomentumRegulationPlanner::DesiredPostImpactMomentum,
           py::arg("step_length"), py::arg("step_height"), py::arg("pre_impact_com_height"))
      .def_static(
          "predict_pre_impact_momentum",
          [](double p_com_x, double L_y, double z0_hat, double pre_impact_position, double gravity) {
            bool clamped = false;
            const double L = MomentumRegulationPlanner::PredictPreImpactMomentum(
                p_com_x, L_y, z0_hat, pre_impact_position, gravity, &clamped);
            return py::make_tuple(L, clamped);
          },
          py::arg("p_com_x"), py::arg("L_y"), py::arg("z0_hat"), py::arg("pre_impact_position"), py::arg("gravity"),
          "Eq. (25): (L at the pre-impact position, clamped)")
      .def_static("impact_map", &MomentumRegulationPlanner::ImpactMap, py::arg("p_com_x_pre"), py::arg("L_pre"),
                  py::arg("pdot_com_x_pre"), py::arg("pdot_com_z_pre"), py::arg("step_length"), py::arg("step_height"),
                  "Eq. (17): [x+, L+]");
  py::class_<MomentumRegulationPlannerSystem, LeafSystem, Holder<MomentumRegulationPlannerSystem>>(
      m, "MomentumRegulationPlannerSystem",
      "MomentumRegulationPlanner as a block (systems/planners/momentum_regulation_planner_system.h). Inputs "
      "com_state [p^x, p^z (m), pdot^x, pdot^z (m/s)], angular_momentum [L_y (m^2/s)], step [l, h] (m), "
      "pre_impact_com_height (m); outputs u_des, L_des, predicted_pre_impact_momentum, time_to_impact, "
      "slope_adjusted_height, vertical_com_target [z (m), u_des (m/s), T_s (s)], status.")
      .def(py::init([](std::string name, const MomentumRegulationPlannerParams& params) {
             return FromArguments([&] { return new MomentumRegulationPlannerSystem(std::move(name), params); });
           }),
           py::arg("name") = "momentum_planner", py::arg("params") = MomentumRegulationPlannerParams{})
      .def_property_readonly("params", [](const MomentumRegulationPlannerSystem& s) { return s.planner().params(); })
      .def(
          "calc_plan",
          [](const MomentumRegulationPlannerSystem& s, const LeafContext& context) {
            return MomentumPlanToDict(s.CalcPlan(context));
          },
          py::arg("context"), "The plan for the inputs in the block's context, as MomentumRegulationPlanner.plan.");
}

/// VerticalComMpc.solve's arguments: every one finite, the horizon >= 0 (the C++ Solve raises a horizon below
/// min_horizon_s to it, which is right for a stance that ends late, but from Python a negative horizon is a mistake).
void CheckMpcArguments(const VerticalComMpc& mpc, double p_z, double pdot_z, double p_final, double v_final,
                       double horizon_s) {
  const std::pair<const char*, double> args[] = {
      {"p_z", p_z}, {"pdot_z", pdot_z}, {"p_final", p_final}, {"v_final", v_final}, {"horizon_s", horizon_s}};
  for (const auto& [name, value] : args)
    if (!std::isfinite(value))
      throw py::value_error(std::string("VerticalComMpc.solve: ") + name + " = " + Number(value) + " is not finite");
  if (horizon_s < 0.0)
    throw py::value_error("VerticalComMpc.solve: horizon_s = " + Number(horizon_s) +
                          " s must be >= 0 (a horizon below " +
                          "min_horizon_s = " + Number(mpc.params().min_horizon_s) + " s is raised to it)");
}

void BindVerticalComMpc(py::module_& m) {
  py::enum_<VerticalComMpcParams::TerminalCondition>(m, "VerticalComMpcTerminalCondition")
      .value("equality", VerticalComMpcParams::TerminalCondition::kEquality)
      .value("weighted_cost", VerticalComMpcParams::TerminalCondition::kWeightedCost);
  ParamsClass<VerticalComMpcParams>(m, "VerticalComMpcParams",
                                    "Vertical-COM MPC, Eq. (28) of the stepping-stones paper.")
      .Field("horizon_steps", &VerticalComMpcParams::horizon_steps)
      .Field("gravity", &VerticalComMpcParams::gravity, "[m/s^2]")
      .Field("max_acceleration", &VerticalComMpcParams::max_acceleration, "[m/s^2] u_k <= a_max (inf: none)")
      .Field("terminal_condition", &VerticalComMpcParams::terminal_condition)
      .Field("terminal_position_weight", &VerticalComMpcParams::terminal_position_weight)
      .Field("terminal_velocity_weight", &VerticalComMpcParams::terminal_velocity_weight)
      .Field("min_horizon_s", &VerticalComMpcParams::min_horizon_s)
      .Field("relax_terminal_on_infeasible", &VerticalComMpcParams::relax_terminal_on_infeasible);
  py::class_<VerticalComMpc>(m, "VerticalComMpc",
                             "min sum u_k^2 over the double integrator, u_k >= -g, z_0 and z_N fixed (Eq. (28)).")
      .def((InitFromArguments<VerticalComMpc, VerticalComMpcParams>()), py::arg("params") = VerticalComMpcParams{})
      .def(
          "solve",
          [](VerticalComMpc& mpc, double p_z, double pdot_z, double p_final, double v_final, double horizon_s) {
            CheckMpcArguments(mpc, p_z, pdot_z, p_final, v_final, horizon_s);
            const QpStatus status = mpc.Solve(p_z, pdot_z, p_final, v_final, horizon_s);
            py::dict d;
            d["status"] = std::string(to_string(status));
            d["terminal_relaxed"] = mpc.terminal_relaxed();
            d["dt"] = mpc.dt();
            d["inputs"] = mpc.inputs();
            d["positions"] = mpc.positions();
            d["velocities"] = mpc.velocities();
            return d;
          },
          py::arg("p_z"), py::arg("pdot_z"), py::arg("p_final"), py::arg("v_final"), py::arg("horizon_s"));
  ParamsClass<VerticalComMpcSystemParams>(m, "VerticalComMpcSystemParams",
                                          "VerticalComMpcSystem (systems/planners/vertical_com_mpc_system.h).")
      .Field("mpc", &VerticalComMpcSystemParams::mpc)
      .Field("control_period_s", &VerticalComMpcSystemParams::control_period_s, "[s] re-solve period")
      .Field("hold_plan_below_horizon_s", &VerticalComMpcSystemParams::hold_plan_below_horizon_s, "[s] 0: off")
      .Field("resolve_at_events", &VerticalComMpcSystemParams::resolve_at_events);
  py::class_<VerticalComMpcSystem, LeafSystem, Holder<VerticalComMpcSystem>>(
      m, "VerticalComMpcSystem",
      "VerticalComMpc re-solved periodically (Eq. (28)). Inputs com_vertical_state [p^z (m), pdot^z (m/s)], target "
      "[p_f (m), v_f (m/s), T_s (s)]; outputs com_height_desired [p, pdot, pddot] (the plan at the current time), "
      "planned_inputs (N, m/s^2), qp_failures, qp_status, terminal_relaxations. Discrete state: [t_plan, p_plan, "
      "v_plan, dt, last status, failures, solves, relaxations, u_0..u_N-1].")
      .def(py::init([](std::string name, const VerticalComMpcSystemParams& params) {
             return FromArguments([&] { return new VerticalComMpcSystem(std::move(name), params); });
           }),
           py::arg("name") = "vertical_com_mpc", py::arg("params") = VerticalComMpcSystemParams{})
      .def_property_readonly("params", &VerticalComMpcSystem::params)
      .def_property_readonly("horizon_steps", &VerticalComMpcSystem::horizon_steps);
}

py::dict PlanToDict(const SpringMassPlan& p) {
  py::dict d;
  d["success"] = p.success();
  d["status"] = std::string(ToString(p.status));
  d["message"] = p.message;
  d["iterations"] = p.iterations;
  d["cost"] = p.cost;
  d["duration"] = p.duration;
  d["max_violation"] = p.max_violation;
  d["times"] = p.times;
  d["states"] = p.states;
  d["inputs"] = p.inputs;
  d["leg_force"] = p.leg_force;
  return d;
}

void BindSpringMassPlanners(py::module_& m) {
  ParamsClass<SpringMassJumpParams>(m, "SpringMassJumpParams", "Jump NLP of the hopping paper, Sec. III-C.")
      .Field("apex_rise", &SpringMassJumpParams::apex_rise, "[m] H")
      .Field("num_intervals", &SpringMassJumpParams::num_intervals)
      .Field("min_duration", &SpringMassJumpParams::min_duration, "[s]")
      .Field("max_duration", &SpringMassJumpParams::max_duration, "[s]")
      .Field("min_leg_length", &SpringMassJumpParams::min_leg_length, "[m]")
      .Field("max_leg_length", &SpringMassJumpParams::max_leg_length, "[m]")
      .Field("max_leg_speed", &SpringMassJumpParams::max_leg_speed, "[m/s]")
      .Field("max_leg_acceleration", &SpringMassJumpParams::max_leg_acceleration, "[m/s^2]")
      .Field("initial_guess_duration", &SpringMassJumpParams::initial_guess_duration, "[s]");
  ParamsClass<SpringMassLandingParams>(m, "SpringMassLandingParams", "Landing NLP of the hopping paper, Eq. (16).")
      .Field("rest_height", &SpringMassLandingParams::rest_height, "[m]")
      .Field("num_intervals", &SpringMassLandingParams::num_intervals)
      .Field("min_duration", &SpringMassLandingParams::min_duration, "[s]")
      .Field("max_duration", &SpringMassLandingParams::max_duration, "[s]")
      .Field("min_force_fraction", &SpringMassLandingParams::min_force_fraction)
      .Field("max_spring_compression", &SpringMassLandingParams::max_spring_compression, "[m]")
      .Field("spring_rate_weight", &SpringMassLandingParams::spring_rate_weight, "[1/s^2]");
  py::class_<SpringMassJumpPlanner>(m, "SpringMassJumpPlanner",
                                    "Stance from rest to lift-off with apex rise H (Eq. (14)-(15)); Ipopt.")
      .def((InitFromArguments<SpringMassJumpPlanner, SpringMassParams, SpringMassJumpParams>()),
           py::arg("rom") = SpringMassParams{}, py::arg("params") = SpringMassJumpParams{})
      .def(
          "solve", [](const SpringMassJumpPlanner& p, const Eigen::Vector4d& z0) { return PlanToDict(p.Solve(z0)); },
          py::arg("z0"), "dict: success, status, duration, times, states (4 x N+1), inputs, leg_force");
  py::class_<SpringMassLandingPlanner>(m, "SpringMassLandingPlanner",
                                       "Landing from a post-impact state to rest (Eq. (16)); Ipopt.")
      .def((InitFromArguments<SpringMassLandingPlanner, SpringMassParams, SpringMassLandingParams>()),
           py::arg("rom") = SpringMassParams{}, py::arg("params") = SpringMassLandingParams{})
      .def(
          "solve", [](SpringMassLandingPlanner& p, const Eigen::Vector4d& z0) { return PlanToDict(p.Solve(z0)); },
          py::arg("z0"));
}

void BindFootedHlip(py::module_& m) {
  ParamsClass<FootedHlipTransitionParams>(m, "FootedHlipTransitionParams",
                                          "Lateral transition QP of the walking paper, Eq. (11)-(15).")
      .Field("mass", &FootedHlipTransitionParams::mass, "[kg]")
      .Field("gravity", &FootedHlipTransitionParams::gravity, "[m/s^2]")
      .Field("foot_width_left_of_ankle", &FootedHlipTransitionParams::foot_width_left_of_ankle, "[m] W1")
      .Field("foot_width_right_of_ankle", &FootedHlipTransitionParams::foot_width_right_of_ankle, "[m] W2")
      .Field("max_ankle_roll_torque", &FootedHlipTransitionParams::max_ankle_roll_torque, "[N m]")
      .Field("normal_force_pivots", &FootedHlipTransitionParams::normal_force_pivots);
  using Data = FootedHlipTransitionData;
  ParamsClass<Data>(m, "FootedHlipTransitionData", "The transition's timing, forces and boundary states.")
      .Field("node_times", &Data::node_times, "[s] N strictly increasing")
      .Field("single_support", &Data::single_support, "N-1 intervals: True = SSP")
      .Field("stance_left", &Data::stance_left)
      .Field("left_normal_force", &Data::left_normal_force, "[N] N")
      .Field("right_normal_force", &Data::right_normal_force, "[N] N")
      .Field("left_foot_y", &Data::left_foot_y, "[m]")
      .Field("right_foot_y", &Data::right_foot_y, "[m]")
      .Field("z0", &Data::z0, "[m]")
      .Field("node_heights", &Data::node_heights, "[m] N or empty")
      .Field("initial_state", &Data::initial_state, "[y (m), ydot (m/s)]")
      .Field("final_state", &Data::final_state, "[y (m), ydot (m/s)]");
  py::class_<FootedHlipTransitionPlanner>(m, "FootedHlipTransitionPlanner", "min sum u_L^2 + u_R^2, Eq. (15).")
      .def((InitFromArguments<FootedHlipTransitionPlanner, FootedHlipTransitionParams>()),
           py::arg("params") = FootedHlipTransitionParams{})
      .def(
          "solve",
          [](const FootedHlipTransitionPlanner& planner, const Data& data) {
            const FootedHlipTransitionPlan p = planner.Solve(data);
            py::dict d;
            d["success"] = p.success();
            d["status"] = std::string(to_string(p.status));
            d["message"] = p.message;
            d["left_torque"] = p.left_torque;
            d["right_torque"] = p.right_torque;
            d["states"] = p.states;
            d["interval_stiffness"] = p.interval_stiffness;
            d["interval_pivot"] = p.interval_pivot;
            d["interval_height"] = p.interval_height;
            d["cost"] = p.cost;
            return d;
          },
          py::arg("data"));
}

}  // namespace

void BindPlanners(py::module_& m) {
  BindMomentumRegulation(m);
  BindVerticalComMpc(m);
  BindSpringMassPlanners(m);
  BindFootedHlip(m);
}

}  // namespace rome::python
