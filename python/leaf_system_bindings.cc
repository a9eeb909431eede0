// LeafSystem subclassable in Python (framework/system.h): a Python class declares its ports, state, modes, guards and
// periodic updates in __init__ and overrides do_calc_time_derivatives, as a C++ block does. Every call from the
// simulator into Python costs an interpreter round trip (measured in docs/python.md).
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "framework/system.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace rome::python {
namespace {

/// Writes the Python result `value` into `out` of size `size`; `what` names the function in the error.
void CopyResult(const py::handle& value, Eigen::Ref<Eigen::VectorXd> out, const std::string& what) {
  const Eigen::VectorXd v = ToVector(value, what.c_str());
  if (v.size() != out.size())
    throw py::value_error(what + " returned " + std::to_string(v.size()) + " elements, expected " +
                          std::to_string(out.size()));
  out = v;
}

EventStatus StatusOf(const py::object& result) {
  if (result.is_none()) return EventStatus::Succeeded();
  return result.cast<EventStatus>();
}

/// A Python callback of a Python LeafSystem. A method bound to the system itself (`self.calc`) is kept unbound and
/// called with the system's Python object looked up at call time: a strong reference from the C++ system to its own
/// Python object would be a cycle that Python's collector cannot see, and the system and its diagram would never be
/// freed.
class Callback {
 public:
  Callback(py::function f, const LeafSystem* system) : system_(system) {
    if (py::hasattr(f, "__self__") && py::hasattr(f, "__func__")) {
      py::handle self = f.attr("__self__");
      if (py::isinstance<LeafSystem>(self) && self.cast<const LeafSystem*>() == system) {
        f_ = f.attr("__func__");
        bound_ = true;
        return;
      }
    }
    f_ = std::move(f);
  }
  template <class... Args>
  py::object operator()(Args&&... args) const {
    if (bound_) return f_(py::cast(system_, py::return_value_policy::reference), std::forward<Args>(args)...);
    return f_(std::forward<Args>(args)...);
  }

 private:
  py::object f_;
  const LeafSystem* system_;
  bool bound_ = false;
};

/// The C++ side of a Python LeafSystem: makes the protected declarations public and forwards the hooks to Python.
class PyLeafSystem : public LeafSystem {
 public:
  explicit PyLeafSystem(std::string name) : LeafSystem(std::move(name)) {}

  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override {
    py::gil_scoped_acquire gil;
    py::function override = py::get_override(static_cast<const LeafSystem*>(this), "do_calc_time_derivatives");
    if (!override) return LeafSystem::DoCalcTimeDerivatives(context, xdot);
    CopyResult(override(py::cast(&context, py::return_value_policy::reference)), *xdot,
               "system '" + name() + "': do_calc_time_derivatives");
  }

  int InputPort(std::string port, const py::object& size_or_names) {
    if (py::isinstance<py::int_>(size_or_names)) return DeclareInputPort(std::move(port), size_or_names.cast<int>());
    return DeclareInputPort(std::move(port), size_or_names.cast<std::vector<std::string>>());
  }

  int OutputPort(std::string port, const py::object& size_or_names, py::function calc, const py::object& feedthrough) {
    const std::string what = "system '" + name() + "': output port '" + port + "'";
    OutputCalc c = [calc = Callback(std::move(calc), this), what](const LeafContext& context, Eigen::VectorXd* y) {
      CopyResult(calc(py::cast(&context, py::return_value_policy::reference)), *y, what);
    };
    const Feedthrough f = FeedthroughOf(feedthrough);
    if (py::isinstance<py::int_>(size_or_names))
      return DeclareOutputPort(std::move(port), size_or_names.cast<int>(), std::move(c), f);
    return DeclareOutputPort(std::move(port), size_or_names.cast<std::vector<std::string>>(), std::move(c), f);
  }

  int ScalarGuard(std::string guard, int mode, py::function witness, CrossingDirection direction, py::function reset) {
    return DeclareGuard(
        std::move(guard), mode,
        [witness = Callback(std::move(witness), this)](const LeafContext& context) {
          return witness(py::cast(&context, py::return_value_policy::reference)).cast<double>();
        },
        direction,
        [reset = Callback(std::move(reset), this)](const LeafContext& context, int component, State* next) {
          return StatusOf(reset(py::cast(&context, py::return_value_policy::reference), component,
                                py::cast(next, py::return_value_policy::reference)));
        });
  }

  void PeriodicUpdate(double period, double offset, py::function update) {
    const std::string what = "system '" + name() + "': periodic update";
    DeclarePeriodicDiscreteUpdate(
        period, offset,
        [update = Callback(std::move(update), this), what](const LeafContext& context, Eigen::VectorXd* next) {
          py::object result = update(py::cast(&context, py::return_value_policy::reference));
          if (result.is_none()) return EventStatus::Succeeded();
          if (py::isinstance<EventStatus>(result)) return result.cast<EventStatus>();
          CopyResult(result, *next, what);
          return EventStatus::Succeeded();
        });
  }

  using LeafSystem::DeclareContinuousState;
  using LeafSystem::DeclareDiscreteState;
  using LeafSystem::DeclareModes;

 private:
  static Feedthrough FeedthroughOf(const py::object& feedthrough) {
    if (feedthrough.is_none()) return Feedthrough::All();
    if (py::isinstance<py::bool_>(feedthrough))
      return feedthrough.cast<bool>() ? Feedthrough::All() : Feedthrough::None();
    return Feedthrough::From(feedthrough.cast<std::vector<int>>());
  }
};

PyLeafSystem& Self(LeafSystem& s) {
  auto* p = dynamic_cast<PyLeafSystem*>(&s);
  if (p == nullptr)
    throw py::type_error("system '" + s.name() +
                         "' is a C++ block: only a Python subclass of rome.LeafSystem declares ports and state");
  return *p;
}

void BindState(py::module_& m) {
  py::class_<State>(m, "State",
                    "A leaf's state handed to a guard's reset: assign continuous, discrete or mode to change it.")
      .def_property(
          "continuous", [](const State& s) { return Eigen::VectorXd(s.continuous); },
          [](State& s, const py::handle& v) { CopyResult(v, s.continuous, "State.continuous"); })
      .def_property(
          "discrete", [](const State& s) { return Eigen::VectorXd(s.discrete); },
          [](State& s, const py::handle& v) { CopyResult(v, s.discrete, "State.discrete"); })
      .def_readwrite("mode", &State::mode);
  py::enum_<CrossingDirection>(m, "CrossingDirection")
      .value("rising", CrossingDirection::kRising)
      .value("falling", CrossingDirection::kFalling)
      .value("either", CrossingDirection::kEither);
}

void BindDeclarations(py::class_<LeafSystem, PyLeafSystem, System, Holder<LeafSystem>>& c) {
  c.def(
       "declare_input_port",
       [](LeafSystem& s, std::string port, const py::object& size) {
         return FromArguments([&] { return Self(s).InputPort(std::move(port), size); });
       },
       py::arg("name"), py::arg("size"),
       "A vector input of `size` elements (or a list of element names). Returns its index.")
      .def(
          "declare_output_port",
          [](LeafSystem& s, std::string port, const py::object& size, py::function calc,
             const py::object& feedthrough) {
            return FromArguments(
                [&] { return Self(s).OutputPort(std::move(port), size, std::move(calc), feedthrough); });
          },
          py::arg("name"), py::arg("size"), py::arg("calc"), py::arg("feedthrough") = py::none(),
          "calc(context) returns the value. feedthrough: None/True (reads every input), False (none), or a list of "
          "input indices.")
      .def(
          "declare_continuous_state",
          [](LeafSystem& s, const py::object& size_or_value) {
            FromArguments([&] {
              if (py::isinstance<py::int_>(size_or_value))
                return Self(s).DeclareContinuousState(size_or_value.cast<int>());
              Self(s).DeclareContinuousState(ToVector(size_or_value, "declare_continuous_state"));
            });
          },
          py::arg("size_or_default"))
      .def(
          "declare_discrete_state",
          [](LeafSystem& s, const py::handle& value) {
            FromArguments([&] { Self(s).DeclareDiscreteState(ToVector(value, "declare_discrete_state")); });
          },
          py::arg("default"))
      .def(
          "declare_modes",
          [](LeafSystem& s, std::vector<std::string> names, int default_mode) {
            FromArguments([&] { Self(s).DeclareModes(std::move(names), default_mode); });
          },
          py::arg("names"), py::arg("default_mode") = 0)
      .def(
          "declare_guard",
          [](LeafSystem& s, std::string name, py::function witness, CrossingDirection direction, py::function reset,
             int mode) {
            return FromArguments([&] {
              return Self(s).ScalarGuard(std::move(name), mode, std::move(witness), direction, std::move(reset));
            });
          },
          py::arg("name"), py::arg("witness"), py::arg("direction"), py::arg("reset"),
          py::arg("mode") = LeafSystem::kAllModes,
          "witness(context) -> float; reset(context, component, state) changes `state` in place and returns None or an "
          "EventStatus.")
      .def(
          "declare_periodic_discrete_update",
          [](LeafSystem& s, double period, double offset, py::function update) {
            FromArguments([&] { Self(s).PeriodicUpdate(period, offset, std::move(update)); });
          },
          py::arg("period_s"), py::arg("offset_s"), py::arg("update"),
          "update(context) returns the next discrete state (or None: unchanged, or an EventStatus to end the run).");
}

}  // namespace

void BindLeafSystem(py::module_& m) {
  BindState(m);
  py::class_<LeafSystem, PyLeafSystem, System, Holder<LeafSystem>> c(
      m, "LeafSystem", py::dynamic_attr(), "A block; subclass it in Python and declare everything in __init__.");
  c.def(py::init<std::string>(), py::arg("name"))
      .def_property_readonly("num_continuous_states", &LeafSystem::num_continuous_states)
      .def_property_readonly("num_discrete_states", &LeafSystem::num_discrete_states)
      .def_property_readonly("num_modes", &LeafSystem::num_modes)
      .def(
          "eval_input",
          [](const LeafSystem& s, const LeafContext& c, const py::handle& port) {
            const int index =
                py::isinstance<py::str>(port) ? s.GetInputPortIndex(port.cast<std::string>()) : port.cast<int>();
            if (index < 0 || index >= s.num_input_ports())
              throw py::index_error("system '" + s.name() + "': input port index " + std::to_string(index) +
                                    " does not exist");
            return Eigen::VectorXd(s.EvalInput(c, index));
          },
          py::arg("context"), py::arg("port"),
          "Value of a vector input port (by name or index) in the leaf's context, as a numpy copy.")
      .def(
          "calc_time_derivatives",
          [](const LeafSystem& s, const LeafContext& c) {
            Eigen::VectorXd xdot;
            s.CalcTimeDerivatives(c, &xdot);
            return xdot;
          },
          py::arg("context"))
      .def("create_default_leaf_context", &LeafSystem::CreateDefaultLeafContext, py::keep_alive<0, 1>());
  BindDeclarations(c);
}

}  // namespace rome::python
