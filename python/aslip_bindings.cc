// Python bindings of the aSLIP of the walking paper (systems/rom/actuated_spring_loaded_inverted_pendulum*.h): its
// parameters and its hybrid block (double support, left and right stance).
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "systems/rom/actuated_spring_loaded_inverted_pendulum_system.h"

namespace py = pybind11;

namespace rome::python {

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
}

}  // namespace rome::python
