#pragma once
// Shared declarations of the rome Python module (python/*.cc): one Bind* function per area, and how Python objects
// own systems.
//
// Ownership: a System made in Python is owned by its Python object until it is added to a DiagramBuilder; from then on
// the built Diagram owns it (DiagramBuilder takes a unique_ptr) and the Python object only refers to it.
// SystemHolder's deleter frees the system only if no builder adopted it. The builder's Python object and then the
// Diagram's keep the Python objects of their systems alive (so a Python LeafSystem's overrides stay callable while the
// diagram runs), and each system's Python object keeps its diagram alive (so a block is never used after its diagram
// is gone). These references are ordinary attributes, so Python's garbage collector frees the cycle.
#include <any>
#include <functional>
#include <memory>
#include <stdexcept>
#include <typeinfo>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <pybind11/pybind11.h>

#include "framework/system.h"
#include "systems/multibody/multibody_model.h"

namespace rome::python {

/// Frees a System unless a DiagramBuilder adopted it (MarkAdopted).
struct SystemDeleter {
  void operator()(System* system) const;
};
/// The holder of every System class bound to Python.
template <class T>
using Holder = std::unique_ptr<T, SystemDeleter>;
/// Records that a DiagramBuilder owns `system` from now on.
void MarkAdopted(const System* system);

/// In this order: EventStatus, contexts and System; LeafSystem; the rest of the framework; ...
void BindSystemBase(pybind11::module_& m);
void BindFramework(pybind11::module_& m);
void BindSimulator(pybind11::module_& m);
void BindLeafSystem(pybind11::module_& m);
void BindSolvers(pybind11::module_& m);
void BindBlocks(pybind11::module_& m);
void BindMultibody(pybind11::module_& m);
void BindReducedOrderModels(pybind11::module_& m);
void BindPlanners(pybind11::module_& m);
void BindCollocation(pybind11::module_& m);
void BindSteppingStones(pybind11::module_& m);
void BindLocomotionRuns(pybind11::module_& m);
/// After BindSteppingStones (Terrain) and BindBlocks (the controllers' parameters).
void BindContactBlocks(pybind11::module_& m);
/// The pre-impact posture NLP, Ipopt's options and the stepping-stones step parameters.
void BindPosture(pybind11::module_& m);
/// After BindActuatedSpringLoadedInvertedPendulum (AslipPeriodicGaitPlanner).
void BindWalkingPlan(pybind11::module_& m);

/// Errors (docs/python.md, "Errors"): a C++ object made from the caller's arguments (a block, a planner, a robot
/// model from its file) reports bad arguments as ValueError, whatever C++ exception type carries them: the blocks
/// report bad parameters through LeafSystem::ThrowError and the robot files through FileError, both
/// std::runtime_error, which pybind11 alone would raise as RuntimeError. Runs `make` and rethrows a std::runtime_error
/// as ValueError with the same message; std::invalid_argument (and the other std::logic_error kinds) keep pybind11's
/// mapping (ValueError; IndexError for std::out_of_range).
template <class F>
auto FromArguments(F&& make) -> decltype(make()) {
  try {
    return make();
  } catch (const pybind11::error_already_set&) { throw; } catch (const pybind11::builtin_exception&) {
    throw;  // already a Python exception type (pybind11::value_error, type_error, ...)
  } catch (const std::overflow_error&) {
    throw;  // OverflowError
  } catch (const std::runtime_error& e) { throw pybind11::value_error(e.what()); }
}

/// pybind11::init for T(Args...) through FromArguments.
template <class T, class... Args>
auto InitFromArguments() {
  return pybind11::init([](Args... args) { return FromArguments([&] { return new T(std::forward<Args>(args)...); }); });
}

/// The C++ model of a Python rome.MultibodyModel, shared with the blocks made from it (a copy of the Python object's
/// model, made on first use; later changes to the Python object cannot reach it: a MultibodyModel is immutable).
std::shared_ptr<const MultibodyModel> SharedModel(const pybind11::handle& model);

/// Typed ports (framework/system.h: a port that carries one C++ value, e.g. a plant's int mode or a controller's
/// diagnostics struct): how a value of each C++ type crosses to Python. Each Bind* function registers the types it
/// binds; a typed port of an unregistered type is a ValueError naming the system, the port and the type.
struct TypedValueConverter {
  std::function<pybind11::object(const std::any&)> to_python;
  std::function<std::any(const pybind11::handle&)> from_python;  ///< empty: the type cannot be fixed from Python
};
void RegisterTypedValue(const std::type_info& type, TypedValueConverter converter);
/// Registers T with `to_python(const T&) -> pybind11::object`, and (if given) `from_python(handle) -> T`.
template <class T, class ToPython>
void RegisterTypedValue(ToPython to_python, std::function<T(const pybind11::handle&)> from_python = {}) {
  TypedValueConverter c;
  c.to_python = [to_python](const std::any& value) { return pybind11::object(to_python(*std::any_cast<T>(&value))); };
  if (from_python) c.from_python = [from_python](const pybind11::handle& h) { return std::any(from_python(h)); };
  RegisterTypedValue(typeid(T), std::move(c));
}
/// The converter of typed port `port` of `system`; a ValueError naming them if its type has none (or, with
/// `for_fixing`, none from Python).
const TypedValueConverter& TypedConverterFor(const System& system, const PortInfo& port, bool for_fixing);
/// `value` as the C++ value of typed input `port` of `system`; a ValueError naming both if it is of another kind.
std::any TypedValueFromPython(const System& system, const PortInfo& port, const pybind11::handle& value);

/// A number for an error message: up to 6 significant digits, as std::ostream prints it (nan, inf, -0.25, 1e+06).
std::string Number(double value);

/// A column vector of doubles from any Python sequence or numpy array; `what` names the value in the error.
Eigen::VectorXd ToVector(const pybind11::handle& value, const char* what);

}  // namespace rome::python
