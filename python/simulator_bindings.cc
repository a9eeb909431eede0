// Python bindings of the Simulator (framework/simulator.h): its config, statuses and statistics, and monitors written
// in Python.
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "framework/simulator.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace rome::python {
namespace {

/// "name=value, ..." of the named attributes of `object` (the repr of the parameter-like classes).
std::string AttributeList(const py::object& object, std::initializer_list<const char*> names) {
  std::string text;
  for (const char* name : names) {
    if (!text.empty()) text += ", ";
    text += std::string(name) + "=" + std::string(py::str(py::repr(object.attr(name))));
  }
  return text;
}

void BindConfig(py::module_& m) {
  py::enum_<IntegrationScheme>(m, "IntegrationScheme")
      .value("bdf", IntegrationScheme::kBdf)
      .value("adams", IntegrationScheme::kAdams)
      .value("adams_functional", IntegrationScheme::kAdamsFunctional)
      .value("explicit_runge_kutta", IntegrationScheme::kExplicitRungeKutta);
  py::enum_<ExplicitRungeKuttaMethod>(m, "ExplicitRungeKuttaMethod")
      .value("dormand_prince_54", ExplicitRungeKuttaMethod::kDormandPrince54)
      .value("bogacki_shampine_32", ExplicitRungeKuttaMethod::kBogackiShampine32);
  py::class_<EventPolicy>(m, "EventPolicy")
      .def(py::init<>())
      .def_readwrite("min_event_separation_s", &EventPolicy::min_event_separation_s)
      .def_readwrite("max_events_per_instant", &EventPolicy::max_events_per_instant)
      .def_readwrite("throw_on_violation", &EventPolicy::throw_on_violation);
  py::class_<SimulatorConfig>(m, "SimulatorConfig", "Integrator settings (framework/simulator.h); keyword constructor.")
      .def(py::init([](const py::kwargs& kwargs) {
        SimulatorConfig config;
        py::object self = py::cast(&config, py::return_value_policy::reference);
        for (const auto& [key, value] : kwargs) {
          if (!py::hasattr(self, key))
            throw py::type_error("SimulatorConfig has no field '" + std::string(py::str(key)) + "'");
          self.attr(key) = value;
        }
        return config;
      }))
      .def_readwrite("scheme", &SimulatorConfig::scheme)
      .def_readwrite("relative_tolerance", &SimulatorConfig::relative_tolerance)
      .def_readwrite("absolute_tolerance", &SimulatorConfig::absolute_tolerance)
      .def_readwrite("max_step_s", &SimulatorConfig::max_step_s)
      .def_readwrite("initial_step_s", &SimulatorConfig::initial_step_s)
      .def_readwrite("max_order", &SimulatorConfig::max_order)
      .def_readwrite("explicit_rk_method", &SimulatorConfig::explicit_rk_method)
      .def_readwrite("restart_with_last_step", &SimulatorConfig::restart_with_last_step)
      .def_readwrite("max_steps_per_advance", &SimulatorConfig::max_steps_per_advance)
      .def_readwrite("max_guard_events", &SimulatorConfig::max_guard_events)
      .def_readwrite("event_policy", &SimulatorConfig::event_policy)
      .def("__repr__", [](const py::object& self) {
        return "SimulatorConfig(" +
               AttributeList(self,
                             {"scheme", "relative_tolerance", "absolute_tolerance", "max_step_s", "initial_step_s",
                              "max_order", "explicit_rk_method", "restart_with_last_step", "max_guard_events"}) +
               ")";
      });
}

void BindStatus(py::module_& m) {
  py::class_<SimulatorStatus> status(m, "SimulatorStatus", "How a run ended (framework/simulator.h).");
  py::enum_<SimulatorStatus::Reason>(status, "Reason")
      .value("reached_boundary_time", SimulatorStatus::Reason::kReachedBoundaryTime)
      .value("reached_termination", SimulatorStatus::Reason::kReachedTermination)
      .value("zeno", SimulatorStatus::Reason::kZeno)
      .value("failed", SimulatorStatus::Reason::kFailed)
      .value("interrupted", SimulatorStatus::Reason::kInterrupted)
      .value("reached_event_limit", SimulatorStatus::Reason::kReachedEventLimit);
  status.def_readonly("reason", &SimulatorStatus::reason)
      .def_readonly("time", &SimulatorStatus::time)
      .def_readonly("system", &SimulatorStatus::system)
      .def_readonly("message", &SimulatorStatus::message)
      .def("ok", &SimulatorStatus::ok)
      .def_property_readonly("kind", &SimulatorStatus::kind_name, "'success', 'failure', 'limit' or 'interrupted'")
      .def("__repr__", [](const SimulatorStatus& s) { return "SimulatorStatus(" + s.ToString() + ")"; });
  py::class_<EventRecord>(m, "EventRecord")
      .def_readonly("time", &EventRecord::time)
      .def_readonly("system", &EventRecord::system)
      .def_readonly("guard", &EventRecord::guard)
      .def_readonly("component", &EventRecord::component)
      .def_readonly("mode_before", &EventRecord::mode_before)
      .def_readonly("mode_after", &EventRecord::mode_after);
  py::class_<SimulatorStatistics>(m, "SimulatorStatistics")
      .def_readonly("steps", &SimulatorStatistics::steps)
      .def_readonly("rhs_evals", &SimulatorStatistics::rhs_evals)
      .def_readonly("root_evals", &SimulatorStatistics::root_evals)
      .def_readonly("jacobian_evals", &SimulatorStatistics::jacobian_evals)
      .def_readonly("restarts", &SimulatorStatistics::restarts)
      .def_readonly("guard_events", &SimulatorStatistics::guard_events)
      .def_readonly("discrete_samples", &SimulatorStatistics::discrete_samples)
      .def_readonly("events", &SimulatorStatistics::events);
}

/// A Python monitor: returns None (go on) or an EventStatus.
Simulator::Monitor PythonMonitor(py::function f) {
  return [f = std::move(f)](const Context& context) {
    py::object result = f(py::cast(&context, py::return_value_policy::reference));
    if (result.is_none()) return EventStatus::Succeeded();
    return result.cast<EventStatus>();
  };
}

}  // namespace

void BindSimulator(py::module_& m) {
  BindConfig(m);
  BindStatus(m);
  py::class_<Simulator>(m, "Simulator", "Hybrid simulator (CVODE / ARKODE with root finding) of a system.")
      .def(py::init<const System&, SimulatorConfig>(), py::arg("system"), py::arg("config") = SimulatorConfig{},
           py::keep_alive<1, 2>())
      .def_property_readonly("context", py::overload_cast<>(&Simulator::get_mutable_context),
                             py::return_value_policy::reference_internal)
      .def_property("config", &Simulator::config, &Simulator::set_config)
      .def("initialize", &Simulator::Initialize)
      .def("advance_to", &Simulator::AdvanceTo, py::arg("t_final"))
      .def_property_readonly("statistics", &Simulator::statistics, py::return_value_policy::copy)
      .def_property_readonly("num_continuous_states", &Simulator::num_continuous_states)
      .def(
          "add_monitor",
          [](Simulator& s, py::function f, std::string name) {
            s.add_monitor(PythonMonitor(std::move(f)), std::move(name));
          },
          py::arg("monitor"), py::arg("name") = "monitor",
          "monitor(context) runs after every accepted step; returning an EventStatus other than succeeded ends the "
          "run.")
      .def("remove_monitor", &Simulator::remove_monitor, py::arg("name"));
}

}  // namespace rome::python
