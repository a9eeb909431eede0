// Python bindings of the aSLIP of the walking paper (systems/rom/actuated_spring_loaded_inverted_pendulum*.h): its
// parameters and its hybrid block (double support, left and right stance).
#include <cstdint>
#include <functional>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "systems/planners/aslip_periodic_gait_planner.h"
#include "systems/planners/aslip_transition_planner.h"
#include "systems/planners/gait_graph.h"
#include "systems/rom/actuated_spring_loaded_inverted_pendulum_system.h"

namespace py = pybind11;

namespace rome::python {
namespace {

// An aSLIP plan (periodic gait or transition) as a dict; ground_reactions(p) gives phase p's 4 x N forces [N].
py::dict AslipPlanToDict(const CollocationResult& collocation, double max_constraint_violation, double mean_height,
                         const std::function<Eigen::MatrixXd(int)>& ground_reactions) {
  py::dict d;
  d["success"] = collocation.success();
  d["status"] = std::string(ToString(collocation.nlp.status));
  d["message"] = collocation.nlp.message;
  d["iterations"] = collocation.nlp.iterations;
  d["cost"] = collocation.nlp.cost;
  d["max_constraint_violation"] = max_constraint_violation;
  d["mean_height"] = mean_height;
  py::list phases;
  for (int p = 0; p < static_cast<int>(collocation.phases.size()); ++p) {
    const CollocationPhaseSolution& s = collocation.phases[p];
    py::dict phase;
    phase["name"] = s.name;
    phase["start_time"] = s.start_time;
    phase["duration"] = s.duration;
    phase["times"] = s.times;
    phase["states"] = s.states;
    phase["inputs"] = s.inputs;
    phase["ground_reactions"] = ground_reactions(p);
    phases.append(phase);
  }
  d["phases"] = phases;
  return d;
}

void BindPeriodicGaitPlanner(py::module_& m) {
  using P = AslipPeriodicGaitParams;
  ParamsClass<P>(
      m, "AslipPeriodicGaitParams",
      "Periodic aSLIP walking gait, walking paper Eq. (4)-(5) (systems/planners/aslip_periodic_gait_planner.h).")
      .Field("aslip", &P::aslip)
      .Field("step_length", &P::step_length, "[m] l")
      .Field("ssp_duration", &P::ssp_duration, "[s]")
      .Field("dsp_duration", &P::dsp_duration, "[s]")
      .Field("nodes_per_domain", &P::nodes_per_domain)
      .Field("friction_coefficient", &P::friction_coefficient, "[-] mu")
      .Field("height_min", &P::height_min, "[m]")
      .Field("height_max", &P::height_max, "[m]")
      .Field("max_leg_length_acceleration", &P::max_leg_length_acceleration, "[m/s^2]")
      .Field("smooth_touchdown", &P::smooth_touchdown)
      .Field("max_iterations", &P::max_iterations);
  py::class_<AslipPeriodicGaitPlanner>(
      m, "AslipPeriodicGaitPlanner",
      "One step (SSP then DSP) of the point-foot aSLIP by trapezoidal collocation on Ipopt. State [x, z, xdot, zdot, "
      "L_0, L_1, Ldot_0, Ldot_1], input [Lddot_0, Lddot_1]; leg 0 stands at x = 0 in SSP, leg 1 lands at x = l.")
      .def((InitFromArguments<AslipPeriodicGaitPlanner, P>()), py::arg("params") = P{})
      .def_property_readonly("params", &AslipPeriodicGaitPlanner::params)
      .def(
          "solve",
          [](const AslipPeriodicGaitPlanner& planner, std::uint32_t seed) {
            // The GIL stays held: it serialises the Ipopt solves (Ipopt 3.11 is not thread-safe).
            const AslipPeriodicGait gait = planner.Solve(seed);
            return AslipPlanToDict(gait.collocation, gait.max_constraint_violation, gait.mean_height, [&](int p) {
              return gait.GroundReactions(planner.params().aslip, planner.params().step_length, p);
            });
          },
          py::arg("seed") = 1,
          "Solves from the random initial guess of `seed` -> dict (success, status, message, iterations, cost, "
          "max_constraint_violation, mean_height, phases: [{name, start_time, duration, times, states (8 x N), "
          "inputs (2 x N), ground_reactions (4 x N: [G_0x, G_0z, G_1x, G_1z] N)}]).");
}

void BindTransitionPlanner(py::module_& m) {
  using P = AslipTransitionParams;
  ParamsClass<P>(m, "AslipTransitionParams",
                 "Transitional footed aSLIP (DSP then SSP), walking paper Eq. (9)-(10) "
                 "(systems/planners/aslip_transition_planner.h).")
      .Field("bounds", &P::bounds, "model, bounds, N, mu and tolerances shared with the periodic NLP")
      .Field("min_dsp_duration", &P::min_dsp_duration, "[s]")
      .Field("max_dsp_duration", &P::max_dsp_duration, "[s]")
      .Field("min_ssp_duration", &P::min_ssp_duration, "[s]")
      .Field("max_ssp_duration", &P::max_ssp_duration, "[s]")
      .Field("max_ankle_torque", &P::max_ankle_torque, "[N m] u_y,max")
      .Field("torque_cost_scale", &P::torque_cost_scale, "[N m] u_s of Eq. (9)")
      .Field("zero_final_ankle_torque", &P::zero_final_ankle_torque)
      .Field("max_ssp_ankle_torque", &P::max_ssp_ankle_torque, "[N m] (< 0: max_ankle_torque)")
      .Field("min_dsp_stance_force_fraction", &P::min_dsp_stance_force_fraction, "[-] of m g")
      .Field("max_vertical_force_fraction", &P::max_vertical_force_fraction, "[-] of m g (0: no bound)");
  using D = AslipTransitionData;
  ParamsClass<D>(m, "AslipTransitionData", "Boundary states and foot positions of one aSLIP transition.")
      .Field("initial_state", &D::initial_state, "[x, z, xdot, zdot, L_L, L_R, Ldot_L, Ldot_R] at the DSP's start")
      .Field("final_state", &D::final_state, "the same at the SSP's end (pre-impact)")
      .Field("left_foot_x", &D::left_foot_x, "[m]")
      .Field("right_foot_x", &D::right_foot_x, "[m]")
      .Field("lifting_leg", &D::lifting_leg, "0 = left, 1 = right");
  py::class_<AslipTransitionPlanner>(
      m, "AslipTransitionPlanner",
      "The transition NLP by trapezoidal collocation on Ipopt: a DSP on both feet, the lifting leg's vertical force 0 "
      "at its end, then an SSP on the other foot, from data.initial_state to data.final_state.")
      .def((InitFromArguments<AslipTransitionPlanner, P>()), py::arg("params") = P{})
      .def_property_readonly("params", &AslipTransitionPlanner::params)
      .def_static(
          "standing_state",
          [](const ActuatedSpringLoadedInvertedPendulumParams& aslip, double z, double left_foot_x,
             double right_foot_x) {
            return FromArguments(
                [&] { return AslipTransitionPlanner::StandingState(aslip, z, left_foot_x, right_foot_x); });
          },
          py::arg("aslip"), py::arg("z"), py::arg("left_foot_x") = 0.0, py::arg("right_foot_x") = 0.0,
          "Standing at rest in DSP at COM height z [m], each leg carrying m g / 2 -> state (8).")
      .def(
          "solve",
          [](const AslipTransitionPlanner& planner, const D& data) {
            // The GIL stays held: it serialises the Ipopt solves (Ipopt 3.11 is not thread-safe).
            const AslipTransition transition = FromArguments([&] { return planner.Solve(data); });
            return AslipPlanToDict(
                transition.collocation, transition.max_constraint_violation, transition.mean_height,
                [&](int p) { return transition.GroundReactions(planner.params().bounds.aslip, data, p); });
          },
          py::arg("data"),
          "-> dict (success, status, message, iterations, cost, max_constraint_violation, mean_height, phases: "
          "[{name ('dsp', 'ssp'), start_time, duration, times, states (8 x N), inputs (4 x N: [Lddot_L, Lddot_R, u_L, "
          "u_R]), ground_reactions (4 x N: [G_Lx, G_Lz, G_Rx, G_Rz] N)}]).");
}

void BindGaitGraph(py::module_& m) {
  using P = GaitGraphParams;
  ParamsClass<P>(
      m, "GaitGraphParams",
      "A grid of gaits (L m, T_SSP s, T_DSP s, W m) for chains of transitions (systems/planners/gait_graph.h).")
      .Field("min", &P::min, "(m, s, s, m)")
      .Field("max", &P::max, "(m, s, s, m)")
      .Field("spacing", &P::spacing, "(m, s, s, m)")
      .Field("reach", &P::reach, "(m, s, s, m) largest change per axis along one edge")
      .Field("step_cost_weight", &P::step_cost_weight, "[-]")
      .Field("within_box", &P::within_box)
      .Field("max_failed_transitions", &P::max_failed_transitions)
      .cls()
      .def("validate", [](const P& p) { p.Validate(); });
  py::class_<GaitGraph>(m, "GaitGraph",
                        "Edges join gaits that differ by at most `reach` per axis; cost 1 + step_cost_weight "
                        "sum |dg_i| / reach_i.")
      .def((InitFromArguments<GaitGraph, const P&, const GaitVector&, const GaitVector&>()), py::arg("params"),
           py::arg("start"), py::arg("goal"))
      .def_property_readonly("num_nodes", &GaitGraph::num_nodes)
      .def(
          "node", [](const GaitGraph& g, int i) { return FromArguments([&] { return g.node(i); }); }, py::arg("i"))
      .def_property_readonly("start", &GaitGraph::start)
      .def_property_readonly("goal", &GaitGraph::goal)
      .def("neighbours", &GaitGraph::Neighbours, py::arg("i"), py::arg("j"))
      .def("edge_cost", &GaitGraph::EdgeCost, py::arg("i"), py::arg("j"))
      .def("mark_infeasible", &GaitGraph::MarkInfeasible, py::arg("i"), py::arg("j"))
      .def("shortest_path", &GaitGraph::ShortestPath, "node indices start -> goal; empty when none")
      .def(
          "shortest_feasible_chain",
          [](GaitGraph& g, const std::function<bool(int, const GaitVector&, const GaitVector&)>& try_transition) {
            const GaitChain chain = g.ShortestFeasibleChain(try_transition);
            py::dict d;
            d["found"] = chain.found;
            d["gaits"] = chain.gaits;
            d["transitions_tried"] = chain.transitions_tried;
            d["transitions_failed"] = chain.transitions_failed;
            d["message"] = chain.message;
            return d;
          },
          py::arg("try_transition"),
          "The lazy search: try_transition(depth, from_gait, to_gait) -> bool plans one transition (e.g. an NLP). "
          "-> dict (found, gaits, transitions_tried, transitions_failed, message).");
}

}  // namespace

void BindActuatedSpringLoadedInvertedPendulum(py::module_& m) {
  using P = ActuatedSpringLoadedInvertedPendulumParams;
  ParamsClass<P>(m, "ActuatedSpringLoadedInvertedPendulumParams",
                 "aSLIP constants (walking paper, Appendix 3): K(L)/c = k4 L^4 + k2 L^2 + k1 L + k0 [N/m], "
                 "D(L)/c = d4 L^4 + d2 L^2 + d1 L + d0 [N s/m].")
      .Field("mass", &P::mass, "[kg]")
      .Field("gravity", &P::gravity, "[m/s^2]")
      .Field("spring_scale", &P::spring_scale, "[-] c")
      .Field("k4", &P::k4)
      .Field("k2", &P::k2)
      .Field("k1", &P::k1)
      .Field("k0", &P::k0)
      .Field("d4", &P::d4)
      .Field("d2", &P::d2)
      .Field("d1", &P::d1)
      .Field("d0", &P::d0)
      .Field("heel_length", &P::heel_length, "[m]")
      .Field("toe_length", &P::toe_length, "[m]");
  using S = ActuatedSpringLoadedInvertedPendulumSystemParams;
  ParamsClass<S>(m, "ActuatedSpringLoadedInvertedPendulumSystemParams",
                 "Parameters of ActuatedSpringLoadedInvertedPendulumSystem.")
      .Field("aslip", &S::aslip)
      .Field("footed", &S::footed)
      .Field("initial_state", &S::initial_state, "[x, z, xdot, zdot, L_L, L_R, Ldot_L, Ldot_R]")
      .Field("initial_mode", &S::initial_mode, "'double_support', 'left_stance' or 'right_stance'")
      .Field("initial_left_foot_x", &S::initial_left_foot_x, "[m]")
      .Field("initial_right_foot_x", &S::initial_right_foot_x, "[m]");
  py::class_<ActuatedSpringLoadedInvertedPendulumSystem, LeafSystem,
             Holder<ActuatedSpringLoadedInvertedPendulumSystem>>(
      m, "ActuatedSpringLoadedInvertedPendulumSystem",
      "The aSLIP as a hybrid block. Inputs leg_length_acceleration (2, m/s^2), ankle_torque (2, N m, footed only), "
      "next_foothold (1, m); outputs state (8), com (4), grf (4, N), foot_x (2, m).")
      .def(py::init([](std::string name, const S& p) {
             return FromArguments([&] { return new ActuatedSpringLoadedInvertedPendulumSystem(std::move(name), p); });
           }),
           py::arg("name") = "aslip", py::arg("params") = S{});
  BindPeriodicGaitPlanner(m);
  BindTransitionPlanner(m);
  BindGaitGraph(m);
}

}  // namespace rome::python
