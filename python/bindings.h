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
#include <memory>

#include <Eigen/Core>
#include <pybind11/pybind11.h>

#include "framework/system.h"

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

/// A column vector of doubles from any Python sequence or numpy array; `what` names the value in the error.
Eigen::VectorXd ToVector(const pybind11::handle& value, const char* what);

}  // namespace rome::python
