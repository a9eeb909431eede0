// Python bindings of the framework's structure: System, contexts, Diagram, DiagramBuilder, the primitive blocks, the
// VectorLogger and Linearize (framework/*.h). Values cross as numpy arrays (copies).
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "framework/diagram.h"
#include "framework/linearize.h"
#include "framework/primitives.h"
#include "framework/vector_logger.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace rome::python {
namespace {

int PortIndex(const System& system, const py::handle& port, bool input) {
  if (py::isinstance<py::str>(port)) {
    const std::string name = port.cast<std::string>();
    return input ? system.GetInputPortIndex(name) : system.GetOutputPortIndex(name);
  }
  const int index = port.cast<int>();
  const int count = input ? system.num_input_ports() : system.num_output_ports();
  if (index < 0 || index >= count)
    throw py::index_error("system '" + system.name() + "': " + (input ? "input" : "output") + " port index " +
                          std::to_string(index) + " is outside [0, " + std::to_string(count) + ")");
  return index;
}

/// Output `index` of `system` at `context`: a numpy copy for a vector port, the registered Python value for a typed
/// one.
py::object EvalOutputValue(const System& system, const Context& context, int index) {
  const PortInfo& port = system.output_port(index);
  if (port.is_vector()) return py::cast(Eigen::VectorXd(system.EvalOutput(context, index)));
  const TypedValueConverter& converter = TypedConverterFor(system, port, false);
  return converter.to_python(system.EvalAbstractOutput(context, index));
}

/// Fixes input `index` of `system` in `context`: a vector for a vector port, a registered value for a typed one.
void FixInputValue(const System& system, Context& context, int index, const py::handle& value) {
  const PortInfo& port = system.input_port(index);
  if (port.is_vector()) {
    system.FixInputPort(context, index, ToVector(value, "fix_input_port value"));
    return;
  }
  const auto* leaf = dynamic_cast<const LeafSystem*>(&system);
  if (leaf == nullptr)
    throw py::value_error("fix_input_port: typed input port '" + port.name + "' of diagram '" + system.name() +
                          "': fix it on the leaf (Diagram.get_subsystem_context) or with DiagramBuilder.fix_input");
  leaf->FixAbstractInputPort(context, index, TypedValueFromPython(system, port, value));
}

/// Typed values bound here: the int and double scalars (a plant's contact mode, a mode index).
void RegisterScalarTypedValues() {
  RegisterTypedValue<int>([](int v) { return py::int_(v); },
                          std::function<int(const py::handle&)>([](const py::handle& h) {
                            if (!PyIndex_Check(h.ptr()))  // a Python or numpy integer, not a float or a string
                              throw py::value_error("expected an int, got " + std::string(py::str(py::repr(h))));
                            return py::int_(py::reinterpret_borrow<py::object>(h)).cast<int>();
                          }));
  RegisterTypedValue<double>([](double v) { return py::float_(v); },
                             std::function<double(const py::handle&)>([](const py::handle& h) {
                               try {
                                 return h.cast<double>();
                               } catch (const py::cast_error&) {
                                 throw py::value_error("expected a number, got " + std::string(py::str(py::repr(h))));
                               }
                             }));
}

std::vector<std::string> PortNames(const System& system, bool input) {
  std::vector<std::string> names;
  const int n = input ? system.num_input_ports() : system.num_output_ports();
  for (int i = 0; i < n; ++i) names.push_back((input ? system.input_port(i) : system.output_port(i)).name);
  return names;
}

/// Copies `value` into `target` after checking its size; `what` names the value in the error.
void AssignSized(Eigen::VectorXd& target, const py::handle& value, const std::string& what) {
  Eigen::VectorXd v = ToVector(value, what.c_str());
  if (v.size() != target.size())
    throw py::value_error(what + ": expected " + std::to_string(target.size()) + " elements, got " +
                          std::to_string(v.size()));
  target = v;
}

void BindEventStatus(py::module_& m) {
  py::class_<EventStatus> status(
      m, "EventStatus", "What a reset, update, publish or monitor returns; any kind but succeeded ends the run.");
  py::enum_<EventStatus::Kind>(status, "Kind")
      .value("succeeded", EventStatus::Kind::kSucceeded)
      .value("reached_termination", EventStatus::Kind::kReachedTermination)
      .value("failed", EventStatus::Kind::kFailed);
  status.def_readonly("kind", &EventStatus::kind)
      .def_readonly("message", &EventStatus::message)
      .def_static("succeeded", &EventStatus::Succeeded)
      .def_static("reached_termination", &EventStatus::ReachedTermination, py::arg("why"))
      .def_static("failed", &EventStatus::Failed, py::arg("why"))
      .def("__repr__", [](const EventStatus& s) {
        return "EventStatus(" + std::string(py::str(py::cast(s.kind))) + ", '" + s.message + "')";
      });
}

void BindContexts(py::module_& m) {
  py::class_<Context>(m, "Context",
                      "The values of one run: time, state, parameters, fixed inputs (framework/context.h).")
      .def_property("time", &Context::time, &Context::SetTime, "[s]")
      .def("clone", &Context::Clone, "A deep copy (its own clock, state and scratch).");
  py::class_<LeafContext, Context>(m, "LeafContext")
      .def_property(
          "continuous_state", [](const LeafContext& c) { return Eigen::VectorXd(c.continuous_state()); },
          [](LeafContext& c, const py::handle& v) {
            AssignSized(c.get_mutable_continuous_state(), v, "continuous state of system '" + c.system().name() + "'");
          },
          "numpy copy; assigning checks the size")
      .def_property(
          "discrete_state", [](const LeafContext& c) { return Eigen::VectorXd(c.discrete_state()); },
          [](LeafContext& c, const py::handle& v) {
            AssignSized(c.get_mutable_discrete_state(), v, "discrete state of system '" + c.system().name() + "'");
          },
          "numpy copy; assigning checks the size")
      .def_property("mode", &LeafContext::mode, &LeafContext::set_mode);
  py::class_<DiagramContext, Context>(m, "DiagramContext")
      .def_property_readonly("num_leaves", [](const DiagramContext& c) { return c.num_leaves(); });
}

void BindSystem(py::module_& m) {
  py::class_<System, Holder<System>>(m, "System", py::dynamic_attr(), "A block or a diagram (framework/system.h).")
      .def_property_readonly("name", &System::name)
      .def_property_readonly("num_input_ports", &System::num_input_ports)
      .def_property_readonly("num_output_ports", &System::num_output_ports)
      .def("input_port_names", [](const System& s) { return PortNames(s, true); })
      .def("output_port_names", [](const System& s) { return PortNames(s, false); })
      .def("create_default_context", &System::CreateDefaultContext, py::keep_alive<0, 1>())
      .def(
          "input_port_type",
          [](const System& s, const py::handle& port) { return s.input_port(PortIndex(s, port, true)).TypeString(); },
          py::arg("port"), "'a vector of size n' or the C++ type a typed port carries, e.g. 'int'.")
      .def(
          "output_port_type",
          [](const System& s, const py::handle& port) { return s.output_port(PortIndex(s, port, false)).TypeString(); },
          py::arg("port"))
      .def(
          "eval_output",
          [](const System& s, const Context& c, const py::handle& port) {
            return EvalOutputValue(s, c, PortIndex(s, port, false));
          },
          py::arg("context"), py::arg("port"),
          "Value of an output port (by name or index): a numpy copy for a vector port; for a typed port its Python "
          "value (int, float, an enum, a dict of a struct; docs/python.md).")
      .def(
          "fix_input_port",
          [](const System& s, Context& c, const py::handle& port, const py::handle& value) {
            FixInputValue(s, c, PortIndex(s, port, true), value);
          },
          py::arg("context"), py::arg("port"), py::arg("value"),
          "A vector, or for a typed port of a settable type (int, float, the bound enums) its Python value.")
      .def("__repr__", [](const System& s) {
        return "<rome." + std::string(s.is_diagram() ? "Diagram" : "System") + " '" + s.name() + "'>";
      });
}

/// DiagramBuilder.add_system: the builder adopts the system (bindings.h) after the checks AddSystemImpl makes, so that
/// AddSystem cannot throw while it owns the pointer.
py::object AddSystem(py::object builder_object, py::object system_object, const std::string& name) {
  DiagramBuilder& builder = builder_object.cast<DiagramBuilder&>();
  System* system = system_object.cast<System*>();
  if (system == nullptr) throw py::value_error("DiagramBuilder.add_system: None is not a system");
  const std::string n = name.empty() ? system->name() : name;
  if (py::hasattr(system_object, "_rome_owner"))
    throw py::value_error("DiagramBuilder.add_system: system '" + system->name() +
                          "' already belongs to a builder or a diagram");
  if (n.find('/') != std::string::npos)
    throw py::value_error("DiagramBuilder: system name '" + n + "' must not contain '/'");
  if (builder.HasSystem(n))
    throw py::value_error("DiagramBuilder: a system named '" + n + "' was already added; names must be unique");
  if (!py::hasattr(builder_object, "_rome_systems")) builder_object.attr("_rome_systems") = py::list();
  MarkAdopted(system);
  builder.AddSystem(std::unique_ptr<System>(system), name);
  py::list owned = builder_object.attr("_rome_systems");
  owned.append(system_object);
  system_object.attr("_rome_owner") = builder_object;
  return system_object;
}

py::object Build(py::object builder_object, const std::string& name) {
  DiagramBuilder& builder = builder_object.cast<DiagramBuilder&>();
  if (!py::hasattr(builder_object, "_rome_systems")) builder_object.attr("_rome_systems") = py::list();
  std::unique_ptr<Diagram> built = builder.Build(name);
  py::object diagram = py::cast(Holder<Diagram>(built.release()));
  diagram.attr("_rome_systems") = builder_object.attr("_rome_systems");
  for (py::handle s : py::list(diagram.attr("_rome_systems"))) s.attr("_rome_owner") = diagram;
  builder_object.attr("_rome_systems") = py::list();
  return diagram;
}

void BindBuilder(py::module_& m) {
  py::class_<DiagramBuilder>(m, "DiagramBuilder", py::dynamic_attr(),
                             "Wires systems by port name (framework/diagram.h).")
      .def(py::init([]() { return std::make_unique<DiagramBuilder>(); }))
      .def("add_system", &AddSystem, py::arg("system"), py::arg("name") = "",
           "Adds a system (renamed to `name` if given); the diagram owns it from now on. Returns the system.")
      .def("connect",
           py::overload_cast<const std::string&, const std::string&, const std::string&, const std::string&>(
               &DiagramBuilder::Connect),
           py::arg("from_system"), py::arg("output_port"), py::arg("to_system"), py::arg("input_port"))
      .def("connect",
           py::overload_cast<const System&, const std::string&, const System&, const std::string&>(
               &DiagramBuilder::Connect),
           py::arg("from_system"), py::arg("output_port"), py::arg("to_system"), py::arg("input_port"))
      .def(
          "fix_input",
          [](py::object builder, const std::string& system, const std::string& port, const py::handle& value) {
            DiagramBuilder& b = builder.cast<DiagramBuilder&>();
            const System* target = nullptr;
            if (py::hasattr(builder, "_rome_systems"))
              for (py::handle s : py::list(builder.attr("_rome_systems")))
                if (s.cast<const System&>().name() == system) target = s.cast<const System*>();
            if (target != nullptr && target->HasInputPort(port)) {
              const PortInfo& info = target->input_port(target->GetInputPortIndex(port));
              if (!info.is_vector()) {
                b.FixAbstractInput(system, port, TypedValueFromPython(*target, info, value));
                return;
              }
            }
            b.FixInput(system, port, ToVector(value, "fix_input value"));
          },
          py::arg("system"), py::arg("input_port"), py::arg("value"))
      .def("export_input", &DiagramBuilder::ExportInput, py::arg("system"), py::arg("input_port"), py::arg("name") = "")
      .def("export_output", &DiagramBuilder::ExportOutput, py::arg("system"), py::arg("output_port"),
           py::arg("name") = "")
      .def("has_system", &DiagramBuilder::HasSystem)
      .def("build", &Build, py::arg("name") = "diagram", "Builds the diagram; the builder is empty afterwards.");
}

/// The stacked continuous state of a diagram's leaves, in leaf order (the Simulator's and Linearize's order).
Eigen::VectorXd StackedContinuousState(const Diagram& d, const Context& context, bool discrete) {
  const auto& dc = dynamic_cast<const DiagramContext&>(context);
  Eigen::Index n = 0;
  for (int i = 0; i < dc.num_leaves(); ++i)
    n += discrete ? dc.leaf(i).discrete_state().size() : dc.leaf(i).continuous_state().size();
  Eigen::VectorXd x(n);
  n = 0;
  for (int i = 0; i < dc.num_leaves(); ++i) {
    const Eigen::VectorXd& xi = discrete ? dc.leaf(i).discrete_state() : dc.leaf(i).continuous_state();
    x.segment(n, xi.size()) = xi;
    n += xi.size();
  }
  (void)d;
  return x;
}

void SetStackedState(const Diagram& d, Context& context, const py::handle& value, bool discrete) {
  auto& dc = dynamic_cast<DiagramContext&>(context);
  const Eigen::VectorXd now = StackedContinuousState(d, context, discrete);
  const Eigen::VectorXd x = ToVector(value, "diagram state");
  const char* kind = discrete ? "discrete" : "continuous";
  if (x.size() != now.size())
    throw py::value_error("diagram '" + d.name() + "': the " + kind + " state has " + std::to_string(now.size()) +
                          " elements, got " + std::to_string(x.size()));
  Eigen::Index n = 0;
  for (int i = 0; i < dc.num_leaves(); ++i) {
    Eigen::VectorXd& xi =
        discrete ? dc.leaf(i).get_mutable_discrete_state() : dc.leaf(i).get_mutable_continuous_state();
    xi = x.segment(n, xi.size());
    n += xi.size();
  }
}

void BindDiagram(py::module_& m) {
  py::class_<Diagram, System, Holder<Diagram>>(m, "Diagram", py::dynamic_attr())
      .def_property_readonly("num_leaves", &Diagram::num_leaves)
      .def("leaf_paths",
           [](const Diagram& d) {
             std::vector<std::string> paths;
             for (int i = 0; i < d.num_leaves(); ++i) paths.push_back(d.leaf_path(i));
             return paths;
           })
      .def("get_leaf", &Diagram::GetLeafByPath, py::arg("path"), py::return_value_policy::reference_internal)
      .def(
          "get_subsystem_context",
          [](const Diagram& d, const LeafSystem& s, Context& c) -> LeafContext& {
            return d.GetMutableSubsystemContext(s, c);
          },
          py::arg("system"), py::arg("context"), py::return_value_policy::reference, py::keep_alive<0, 3>(),
          "The leaf's own context inside the diagram's `context` (a view: changes act on the diagram's context).")
      .def(
          "eval_subsystem_output",
          [](const Diagram& d, const System& s, const std::string& port, const Context& c) -> py::object {
            const auto* leaf = dynamic_cast<const LeafSystem*>(&s);
            if (leaf != nullptr && s.HasOutputPort(port) && !s.output_port(s.GetOutputPortIndex(port)).is_vector())
              return EvalOutputValue(s, d.GetSubsystemContext(*leaf, c), s.GetOutputPortIndex(port));
            return py::cast(Eigen::VectorXd(d.EvalSubsystemOutput(s, port, c)));
          },
          py::arg("system"), py::arg("port"), py::arg("context"),
          "A leaf's output inside the diagram's context (typed ports as System.eval_output).")
      .def(
          "get_continuous_state",
          [](const Diagram& d, const Context& c) { return StackedContinuousState(d, c, false); }, py::arg("context"),
          "The leaves' continuous states stacked in leaf order (numpy copy).")
      .def(
          "set_continuous_state",
          [](const Diagram& d, Context& c, const py::handle& x) { SetStackedState(d, c, x, false); },
          py::arg("context"), py::arg("x"))
      .def(
          "get_discrete_state", [](const Diagram& d, const Context& c) { return StackedContinuousState(d, c, true); },
          py::arg("context"))
      .def(
          "set_discrete_state",
          [](const Diagram& d, Context& c, const py::handle& x) { SetStackedState(d, c, x, true); }, py::arg("context"),
          py::arg("x"));
}

void BindPrimitives(py::module_& m) {
  py::class_<ConstantVectorSource, LeafSystem, Holder<ConstantVectorSource>>(m, "ConstantVectorSource")
      .def(py::init([](std::string name, const py::handle& value) {
             return FromArguments([&] {
               return new ConstantVectorSource(std::move(name), ToVector(value, "ConstantVectorSource value"));
             });
           }),
           py::arg("name"), py::arg("value"));
  py::class_<Gain, LeafSystem, Holder<Gain>>(m, "Gain")
      .def((InitFromArguments<Gain, std::string, double, int>()), py::arg("name"), py::arg("k"), py::arg("size"))
      .def((InitFromArguments<Gain, std::string, const Eigen::MatrixXd&>()), py::arg("name"), py::arg("K"));
  py::class_<Adder, LeafSystem, Holder<Adder>>(m, "Adder")
      .def((InitFromArguments<Adder, std::string, int, int>()), py::arg("name"), py::arg("num_inputs"),
           py::arg("size"));
  py::class_<Saturation, LeafSystem, Holder<Saturation>>(m, "Saturation")
      .def((InitFromArguments<Saturation, std::string, const Eigen::VectorXd&, const Eigen::VectorXd&>()),
           py::arg("name"), py::arg("lower"), py::arg("upper"))
      .def((InitFromArguments<Saturation, std::string, double, int>()), py::arg("name"), py::arg("limit"),
           py::arg("size"));
  py::class_<ZeroOrderHold, LeafSystem, Holder<ZeroOrderHold>>(m, "ZeroOrderHold")
      .def((InitFromArguments<ZeroOrderHold, std::string, double, int, double>()), py::arg("name"), py::arg("period_s"),
           py::arg("size"), py::arg("offset_s") = 0.0);
}

/// The log as {column name: numpy array}, "time" first.
py::dict LogColumns(const VectorLogger& logger, const LeafContext& context) {
  const LogData& log = logger.log(context);
  const std::vector<std::string> names = logger.ColumnNames();
  const auto rows = static_cast<py::ssize_t>(log.times.size());
  py::dict columns;
  py::array_t<double> times(rows);
  for (py::ssize_t r = 0; r < rows; ++r) times.mutable_at(r) = log.times[r];
  columns["time"] = times;
  for (size_t c = 1; c < names.size(); ++c) {
    py::array_t<double> column(rows);
    for (py::ssize_t r = 0; r < rows; ++r) column.mutable_at(r) = log.samples[r][static_cast<Eigen::Index>(c - 1)];
    columns[py::str(names[c])] = column;
  }
  return columns;
}

void BindLogger(py::module_& m) {
  py::class_<VectorLogger, LeafSystem, Holder<VectorLogger>>(m, "VectorLogger")
      .def("column_names", &VectorLogger::ColumnNames)
      .def("data", &LogColumns, py::arg("context"),
           "The log as a dict of numpy arrays by column name ('time' first), from the logger's own context "
           "(Diagram.get_subsystem_context).")
      .def("write_csv", &VectorLogger::WriteCsv, py::arg("context"), py::arg("path"));
  m.def(
      "add_vector_logger",
      [](py::object builder, const std::string& name, const std::vector<std::pair<std::string, std::string>>& ports,
         double period_s) {
        DiagramBuilder& b = builder.cast<DiagramBuilder&>();
        VectorLogger* logger = AddVectorLogger(b, name, ports, period_s);
        py::object object = py::cast(logger, py::return_value_policy::reference);
        if (!py::hasattr(builder, "_rome_systems")) builder.attr("_rome_systems") = py::list();
        py::list(builder.attr("_rome_systems")).append(object);
        object.attr("_rome_owner") = builder;
        return object;
      },
      py::arg("builder"), py::arg("name"), py::arg("ports"), py::arg("period_s"),
      "Adds a VectorLogger and connects each (system, output port); columns are '<system>.<port>.<element>' or "
      "'<system>.<port>[i]'.");
}

void BindLinearize(py::module_& m) {
  py::class_<LinearSystemMatrices>(m, "LinearSystemMatrices",
                                   "δẋ = A δx + B δu, δy = C δx + D δu about (x0, u0) (framework/linearize.h).")
      .def_readonly("A", &LinearSystemMatrices::A)
      .def_readonly("B", &LinearSystemMatrices::B)
      .def_readonly("C", &LinearSystemMatrices::C)
      .def_readonly("D", &LinearSystemMatrices::D)
      .def_readonly("x0", &LinearSystemMatrices::x0)
      .def_readonly("u0", &LinearSystemMatrices::u0)
      .def_readonly("y0", &LinearSystemMatrices::y0)
      .def_readonly("xdot0", &LinearSystemMatrices::xdot0)
      .def_readonly("time", &LinearSystemMatrices::time);
  m.def(
      "linearize",
      [](const System& system, Context& context, const std::string& input_port, const std::string& output_port,
         double step_scale) {
        LinearizeParams params;
        params.step_scale = step_scale;
        return Linearize(system, context, input_port, output_port, params);
      },
      py::arg("system"), py::arg("context"), py::arg("input_port") = "", py::arg("output_port") = "",
      py::arg("step_scale") = LinearizeParams{}.step_scale,
      "Central-difference linearization about the point held by `context`.");
}

}  // namespace

void BindSystemBase(py::module_& m) {
  BindEventStatus(m);
  BindContexts(m);
  BindSystem(m);
  RegisterScalarTypedValues();
}

void BindFramework(py::module_& m) {
  BindPrimitives(m);
  BindDiagram(m);
  BindBuilder(m);
  BindLogger(m);
  BindLinearize(m);
}

}  // namespace rome::python
