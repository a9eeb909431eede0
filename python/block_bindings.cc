// Python bindings of a few C++ blocks (systems/): the LIP flow and the LQR state-feedback controller.
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "systems/controllers/lqr_controller.h"
#include "systems/rom/linear_inverted_pendulum_system.h"

namespace py = pybind11;

namespace rome::python {

void BindBlocks(py::module_& m) {
  py::class_<LinearInvertedPendulumSystem, LeafSystem, Holder<LinearInvertedPendulumSystem>>(
      m, "LinearInvertedPendulumSystem",
      "LIP flow, Eq. (12) of the stepping-stones paper: state [x (m), L (m^2/s)], x' = L/z0, L' = g x.")
      .def(py::init([](std::string name, double initial_x, double initial_L, double z0, double gravity) {
             LinearInvertedPendulumSystemParams p;
             p.initial_x = initial_x;
             p.initial_L = initial_L;
             p.lip.z0 = z0;
             p.lip.gravity = gravity;
             return new LinearInvertedPendulumSystem(std::move(name), p);
           }),
           py::arg("name") = "lip", py::arg("initial_x") = LinearInvertedPendulumSystemParams{}.initial_x,
           py::arg("initial_L") = LinearInvertedPendulumSystemParams{}.initial_L,
           py::arg("z0") = LinearInvertedPendulumParams{}.z0,
           py::arg("gravity") = LinearInvertedPendulumParams{}.gravity);
  py::class_<LqrController, LeafSystem, Holder<LqrController>>(
      m, "LqrController",
      "u = u0 - K (x - x0) with the LQR gain of (A, B, Q, R) (systems/controllers/lqr_controller.h).")
      .def(py::init([](std::string name, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                       const Eigen::MatrixXd& R, const Eigen::VectorXd& x0,
                       const Eigen::VectorXd& u0) { return new LqrController(std::move(name), A, B, Q, R, x0, u0); }),
           py::arg("name"), py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"), py::arg("x0"), py::arg("u0"))
      .def(py::init([](std::string name, const LinearSystemMatrices& linearization, const Eigen::MatrixXd& Q,
                       const Eigen::MatrixXd& R) { return new LqrController(std::move(name), linearization, Q, R); }),
           py::arg("name"), py::arg("linearization"), py::arg("Q"), py::arg("R"))
      .def_property_readonly("K", &LqrController::K)
      .def_property_readonly("S", &LqrController::S);
}

}  // namespace rome::python
