// The rome Python module: PYBIND11_MODULE and the ownership rule of bindings.h.
#include <map>
#include <mutex>
#include <sstream>
#include <typeindex>
#include <unordered_set>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>

#include "python/bindings.h"

namespace py = pybind11;

namespace rome::python {

void BindActuatedSpringLoadedInvertedPendulum(py::module_& m);  // aslip_bindings.cc

namespace {

std::mutex adopted_mutex;
std::unordered_set<const System*>& Adopted() {
  static std::unordered_set<const System*> adopted;
  return adopted;
}

std::map<std::type_index, TypedValueConverter>& TypedConverters() {
  static std::map<std::type_index, TypedValueConverter> converters;
  return converters;
}

}  // namespace

void RegisterTypedValue(const std::type_info& type, TypedValueConverter converter) {
  TypedConverters()[std::type_index(type)] = std::move(converter);
}

const TypedValueConverter& TypedConverterFor(const System& system, const PortInfo& port, bool for_fixing) {
  if (port.is_vector())
    throw py::value_error("port '" + port.name + "' of system '" + system.name() + "' is a vector port, not typed");
  const auto found = TypedConverters().find(std::type_index(*port.value_type));
  if (found == TypedConverters().end() || (for_fixing && !found->second.from_python))
    throw py::value_error("port '" + port.name + "' of system '" + system.name() + "' carries " + port.TypeString() +
                          ", which Python cannot " + (for_fixing ? "set" : "read") + " (docs/python.md, typed ports)");
  return found->second;
}

std::any TypedValueFromPython(const System& system, const PortInfo& port, const py::handle& value) {
  const TypedValueConverter& converter = TypedConverterFor(system, port, true);
  try {
    return converter.from_python(value);
  } catch (const py::value_error& e) {
    throw py::value_error("input port '" + port.name + "' of system '" + system.name() + "': " + e.what());
  }
}

void SystemDeleter::operator()(System* system) const {
  {
    std::lock_guard<std::mutex> lock(adopted_mutex);
    if (Adopted().erase(system) > 0) return;  // a diagram owns it (and frees it)
  }
  delete system;
}

void MarkAdopted(const System* system) {
  std::lock_guard<std::mutex> lock(adopted_mutex);
  Adopted().insert(system);
}

std::string Number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

Eigen::VectorXd ToVector(const py::handle& value, const char* what) {
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {}
  if (!a || a.ndim() > 1)
    throw py::value_error(std::string(what) + ": expected a 1-D sequence of numbers, got " +
                          std::string(py::str(py::repr(value))));
  Eigen::VectorXd v(a.size());
  for (py::ssize_t i = 0; i < a.size(); ++i) v[i] = a.data()[i];
  return v;
}

}  // namespace rome::python

PYBIND11_MODULE(_rome, m) {
  m.doc() = "ROME: reduced-order models for legged robots (systems framework, solvers, diagrams); see docs/python.md";
  rome::python::BindSystemBase(m);
  rome::python::BindLeafSystem(m);
  rome::python::BindFramework(m);
  rome::python::BindSimulator(m);
  rome::python::BindSolvers(m);
  rome::python::BindBlocks(m);
  rome::python::BindMultibody(m);
  rome::python::BindReducedOrderModels(m);
  rome::python::BindActuatedSpringLoadedInvertedPendulum(m);
  rome::python::BindPlanners(m);
  rome::python::BindCollocation(m);
  rome::python::BindSteppingStones(m);
  rome::python::BindContactBlocks(m);
  rome::python::BindLocomotionRuns(m);  // after the plant and controller parameters its defaults hold
  rome::python::BindPosture(m);
  rome::python::BindWalkingPlan(m);
}
