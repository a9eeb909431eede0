// Python bindings of the reduced-order models (systems/rom): the LIP of the stepping-stones paper and its stepping
// block, the (footed) H-LIP of the walking paper and its block, and the spring-mass hopping model and its block.
// The LinearInvertedPendulumSystem itself is bound in block_bindings.cc.
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "systems/rom/hybrid_linear_inverted_pendulum_system.h"
#include "systems/rom/spring_mass_system.h"
#include "systems/rom/stepping_linear_inverted_pendulum.h"

namespace py = pybind11;

namespace rome::python {
namespace {

void BindLinearInvertedPendulum(py::module_& m) {
  ParamsClass<LinearInvertedPendulumParams>(m, "LinearInvertedPendulumParams",
                                            "LIP constants (linear_inverted_pendulum.h).")
      .Field("z0", &LinearInvertedPendulumParams::z0, "[m] COM height above the virtual slope")
      .Field("gravity", &LinearInvertedPendulumParams::gravity, "[m/s^2]");
  py::class_<LinearInvertedPendulum>(
      m, "LinearInvertedPendulum",
      "The LIP of the stepping-stones paper, Eq. (12)-(16): state [x (m), L (m^2/s)] about the stance foot.")
      .def((InitFromArguments<LinearInvertedPendulum, LinearInvertedPendulumParams>()),
           py::arg("params") = LinearInvertedPendulumParams{})
      .def_property_readonly("params", &LinearInvertedPendulum::params)
      .def_property_readonly("lambda_", &LinearInvertedPendulum::lambda, "[1/s] sqrt(g / z0)")
      .def("derivative", &LinearInvertedPendulum::Derivative, py::arg("state"))
      .def("transition_matrix", &LinearInvertedPendulum::TransitionMatrix, py::arg("t"))
      .def("flow", &LinearInvertedPendulum::Flow, py::arg("state"), py::arg("t"), "Eq. (13): the state after t seconds")
      .def(
          "time_to_reach",
          [](const LinearInvertedPendulum& lip, double x_des, const Eigen::Vector2d& state) -> py::object {
            const TimeToImpact t = lip.TimeToReach(x_des, state);
            if (t.ok()) return py::float_(t.time_s);
            return py::none();
          },
          py::arg("x_des"), py::arg("state"), "Eq. (14)-(15): first t >= 0 with x(t) = x_des, or None")
      .def("orbital_energy", &LinearInvertedPendulum::OrbitalEnergy, py::arg("state"), "Eq. (16) [m^2/s^2]")
      .def("momentum_on_orbit", &LinearInvertedPendulum::MomentumOnOrbit, py::arg("orbital_energy"), py::arg("x"));

  ParamsClass<SteppingLinearInvertedPendulumParams>(m, "SteppingLinearInvertedPendulumParams",
                                                    "Parameters of SteppingLinearInvertedPendulum.")
      .Field("lip", &SteppingLinearInvertedPendulumParams::lip)
      .Field("impact_fraction", &SteppingLinearInvertedPendulumParams::impact_fraction, "[-] epsilon")
      .Field("initial_x", &SteppingLinearInvertedPendulumParams::initial_x, "[m]")
      .Field("initial_L", &SteppingLinearInvertedPendulumParams::initial_L, "[m^2/s]");
  py::class_<SteppingLinearInvertedPendulum, LeafSystem, Holder<SteppingLinearInvertedPendulum>>(
      m, "SteppingLinearInvertedPendulum",
      "LIP flow Eq. (12) and impact map Eq. (17) of the stepping-stones paper. Inputs: step [l, h] (m), "
      "impact_vertical_velocity (m/s). Outputs: state, com_state, stance_foot, orbital_energy.")
      .def(py::init([](std::string name, const SteppingLinearInvertedPendulumParams& p) {
             return FromArguments([&] { return new SteppingLinearInvertedPendulum(std::move(name), p); });
           }),
           py::arg("name") = "stepping_lip", py::arg("params") = SteppingLinearInvertedPendulumParams{})
      .def_property_readonly("lip", &SteppingLinearInvertedPendulum::lip);
}

void BindHybridLinearInvertedPendulum(py::module_& m) {
  ParamsClass<HybridLinearInvertedPendulumParams>(m, "HybridLinearInvertedPendulumParams",
                                                  "H-LIP constants (hybrid_linear_inverted_pendulum.h).")
      .Field("z0", &HybridLinearInvertedPendulumParams::z0, "[m]")
      .Field("ssp_duration", &HybridLinearInvertedPendulumParams::ssp_duration, "[s]")
      .Field("dsp_duration", &HybridLinearInvertedPendulumParams::dsp_duration, "[s]")
      .Field("gravity", &HybridLinearInvertedPendulumParams::gravity, "[m/s^2]");
  py::class_<HybridLinearInvertedPendulum>(m, "HybridLinearInvertedPendulum",
                                           "The H-LIP of the walking paper (Sec. III): step-to-step dynamics.")
      .def((InitFromArguments<HybridLinearInvertedPendulum, HybridLinearInvertedPendulumParams>()),
           py::arg("params") = HybridLinearInvertedPendulumParams{})
      .def_property_readonly("params", &HybridLinearInvertedPendulum::params)
      .def_property_readonly("lambda_", &HybridLinearInvertedPendulum::lambda, "[1/s]")
      .def_property_readonly("sigma1", &HybridLinearInvertedPendulum::sigma1, "[1/s] slope of P1 orbits")
      .def_property_readonly("sigma2", &HybridLinearInvertedPendulum::sigma2, "[1/s] Eq. (8), slope of P2 orbits")
      .def("single_support_transition", &HybridLinearInvertedPendulum::SingleSupportTransition, py::arg("t"))
      .def("step_to_step_A", &HybridLinearInvertedPendulum::StepToStepA)
      .def("step_to_step_B", &HybridLinearInvertedPendulum::StepToStepB)
      .def("deadbeat_gain", &HybridLinearInvertedPendulum::DeadbeatGain)
      .def("p1_pre_impact_state", &HybridLinearInvertedPendulum::P1PreImpactState, py::arg("step"))
      .def("p2_pre_impact_state", &HybridLinearInvertedPendulum::P2PreImpactState, py::arg("step_width"))
      .def("p2_step", &HybridLinearInvertedPendulum::P2Step, py::arg("pre_impact"));

  using HlipSystemParams = HybridLinearInvertedPendulumSystemParams;
  ParamsClass<HlipSystemParams>(m, "HybridLinearInvertedPendulumSystemParams",
                                "Parameters of HybridLinearInvertedPendulumSystem.")
      .Field("hlip", &HlipSystemParams::hlip)
      .Field("footed", &HlipSystemParams::footed)
      .Field("mass", &HlipSystemParams::mass, "[kg]")
      .Field("initial_state", &HlipSystemParams::initial_state, "[m, m/s]")
      .Field("start_in_single_support", &HlipSystemParams::start_in_single_support)
      .Field("initial_stance_foot_y", &HlipSystemParams::initial_stance_foot_y, "[m]")
      .Field("initial_stance_side", &HlipSystemParams::initial_stance_side, "+1 left, -1 right");
  py::class_<HybridLinearInvertedPendulumSystem, LeafSystem, Holder<HybridLinearInvertedPendulumSystem>>(
      m, "HybridLinearInvertedPendulumSystem", "The (footed) H-LIP as a hybrid block (SSP and DSP modes).")
      .def(py::init([](std::string name, const HlipSystemParams& p) {
             return FromArguments([&] { return new HybridLinearInvertedPendulumSystem(std::move(name), p); });
           }),
           py::arg("name") = "hlip", py::arg("params") = HlipSystemParams{})
      .def_property_readonly("hlip", &HybridLinearInvertedPendulumSystem::hlip);
}

void BindSpringMass(py::module_& m) {
  ParamsClass<LegPolynomial>(m, "LegPolynomial", "c0 + c1 L + c2 L^2 + c4 L^4 (spring_mass_model.h).")
      .Field("c0", &LegPolynomial::c0)
      .Field("c1", &LegPolynomial::c1)
      .Field("c2", &LegPolynomial::c2)
      .Field("c4", &LegPolynomial::c4);
  ParamsClass<LegStiffness>(m, "LegStiffness", "K(L) [N/m] and D(L) [N s/m] of one leg.")
      .Field("stiffness", &LegStiffness::stiffness)
      .Field("damping", &LegStiffness::damping);
  m.def("published_leg_stiffness", &PublishedLegStiffness, "The walking paper's Appendix 3 quartic (c = 1).");
  ParamsClass<SpringMassParams>(m, "SpringMassParams", "The hopping paper's spring-mass ROM (Sec. III-B).")
      .Field("mass", &SpringMassParams::mass, "[kg]")
      .Field("gravity", &SpringMassParams::gravity, "[m/s^2]")
      .Field("n_legs", &SpringMassParams::n_legs)
      .Field("leg", &SpringMassParams::leg);
  py::class_<SpringMassModel>(m, "SpringMassModel",
                              "z = [x (m), xdot (m/s), L (m), Ldot (m/s)], input v = Lddot (spring_mass_model.h).")
      .def((InitFromArguments<SpringMassModel, SpringMassParams>()), py::arg("params") = SpringMassParams{})
      .def_property_readonly("params", &SpringMassModel::params)
      .def("stiffness", &SpringMassModel::Stiffness, py::arg("L"))
      .def("damping", &SpringMassModel::Damping, py::arg("L"))
      .def("static_deflection", &SpringMassModel::StaticDeflection, py::arg("L"))
      .def("static_state", &SpringMassModel::StaticState, py::arg("L"))
      .def("leg_force", &SpringMassModel::LegForce, py::arg("z"))
      .def("derivative", &SpringMassModel::Derivative, py::arg("z"), py::arg("v"))
      .def(
          "energy",
          [](const SpringMassModel& model, const Eigen::Vector4d& z) {
            const SpringMassEnergy e = model.Energy(z);
            py::dict d;
            d["kinetic"] = e.kinetic;
            d["potential"] = e.potential;
            d["spring"] = e.spring;
            d["total"] = e.total();
            return d;
          },
          py::arg("z"), "[J] kinetic, potential, spring and total");
  ParamsClass<SpringMassSystemParams>(m, "SpringMassSystemParams", "Parameters of SpringMassSystem.")
      .Field("model", &SpringMassSystemParams::model)
      .Field("initial_state", &SpringMassSystemParams::initial_state, "z(0) [m, m/s, m, m/s]");
  py::class_<SpringMassSystem, LeafSystem, Holder<SpringMassSystem>>(
      m, "SpringMassSystem",
      "The spring-mass ROM as a block. Input leg_length_acceleration (m/s^2); outputs state, leg_force (N), energy "
      "(J).")
      .def(py::init([](std::string name, const SpringMassSystemParams& p) {
             return FromArguments([&] { return new SpringMassSystem(std::move(name), p); });
           }),
           py::arg("name") = "spring_mass", py::arg("params") = SpringMassSystemParams{})
      .def_property_readonly("model", &SpringMassSystem::model);
}

}  // namespace

void BindReducedOrderModels(py::module_& m) {
  BindLinearInvertedPendulum(m);
  BindHybridLinearInvertedPendulum(m);
  BindSpringMass(m);
}

}  // namespace rome::python
