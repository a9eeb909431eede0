// Python bindings of the contact plants and the QP controllers as blocks (systems/plants, systems/controllers): the
// contact-mode graph, HybridContactPlant, the task-space tasks, TaskSpaceQpController and ClfQpController. Their ports
// are the C++ blocks' (the headers list them with units); a diagram built in Python connects them by name.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/plants/bullet_world_plant.h"
#include "systems/plants/hybrid_contact_plant.h"

namespace py = pybind11;

namespace rome::python {
namespace {

void BindContactModeGraph(py::module_& m) {
  using G = ContactModeGraph;
  py::class_<G::Mode>(m, "ContactMode", "A mode of a ContactModeGraph: its name and active contacts.")
      .def(py::init([](std::string name, std::vector<std::string> contacts) {
             return G::Mode{std::move(name), std::move(contacts)};
           }),
           py::arg("name"), py::arg("contacts"))
      .def_readwrite("name", &G::Mode::name)
      .def_readwrite("contacts", &G::Mode::contacts)
      .def("__repr__", [](const G::Mode& mode) {
        return "ContactMode('" + mode.name + "', " + std::string(py::str(py::cast(mode.contacts))) + ")";
      });
  py::enum_<G::Kind>(m, "ContactTransitionKind")
      .value("touchdown", G::Kind::kTouchdown)
      .value("liftoff", G::Kind::kLiftoff);
  py::class_<G::Transition>(m, "ContactTransition", "A transition of a ContactModeGraph.")
      .def(py::init([](std::string from, std::string to, G::Kind kind, std::string contact) {
             return G::Transition{std::move(from), std::move(to), kind, std::move(contact)};
           }),
           py::arg("from_mode"), py::arg("to_mode"), py::arg("kind"), py::arg("contact"))
      .def_readwrite("from_mode", &G::Transition::from)
      .def_readwrite("to_mode", &G::Transition::to)
      .def_readwrite("kind", &G::Transition::kind)
      .def_readwrite("contact", &G::Transition::contact);
  py::class_<G>(m, "ContactModeGraph",
                "The contact modes a plant moves through (systems/plants/contact_plant.h). The lists are copies: "
                "assign a whole list to change one.")
      .def(py::init<>())
      .def_readwrite("modes", &G::modes)
      .def_readwrite("transitions", &G::transitions)
      .def_readwrite("initial_mode", &G::initial_mode)
      .def_static("alternating_single_support", &G::AlternatingSingleSupport, py::arg("left_contact"),
                  py::arg("right_contact"), py::arg("start_on_left") = true)
      .def_static("with_double_support", &G::WithDoubleSupport, py::arg("left_contact"), py::arg("right_contact"),
                  py::arg("initial_mode") = "double_support")
      .def_static("hopping", &G::Hopping, py::arg("left_contact"), py::arg("right_contact"))
      .def_static("jump_flight_landing", &G::JumpFlightLanding, py::arg("left_contact"), py::arg("right_contact"))
      .def("mode_index", [](const G& g, const std::string& name) {
        return FromArguments([&] { return g.ModeIndex(name, "ContactModeGraph"); });
      });
}

void BindHybridContactPlant(py::module_& m) {
  using P = HybridContactPlantParams;
  ParamsClass<P>(m, "HybridContactPlantParams", "HybridContactPlant (systems/plants/hybrid_contact_plant.h).")
      .Field("min_time_in_mode_s", &P::min_time_in_mode_s, "[s]")
      .Field("min_base_height_m", &P::min_base_height_m, "[m]")
      .Field("stone_tolerance_m", &P::stone_tolerance_m, "[m]")
      .Field("saturate_torques", &P::saturate_torques)
      .Field("unilateral_contact", &P::unilateral_contact)
      .Field("planned_liftoff_force_N", &P::planned_liftoff_force_N, "[N]")
      .Field("joint_stops", &P::joint_stops)
      .Field("joint_stop_tolerance", &P::joint_stop_tolerance, "[rad or m]")
      .Field("immediate_event_delay_s", &P::immediate_event_delay_s, "[s]")
      .Field("event_tolerance_N", &P::event_tolerance_N, "[N]")
      .Field("dynamics", &P::dynamics)
      .Field("external_force_input", &P::external_force_input)
      .Field("sole_torsion", &P::sole_torsion, "four-corner soles slip torsionally outside their corners' cone");
  py::class_<ContactPlant, LeafSystem, Holder<ContactPlant>>(
      m, "ContactPlant",
      "What both contact plants share. Input u (nu, N m); outputs q, v (nv), state (2 nv), mode (int, typed), "
      "contact_forces (3 nc, N, world), contact_violation (nc), com (6).")
      .def(
          "set_state",
          [](const ContactPlant& plant, LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
             const std::string& mode) { FromArguments([&] { plant.SetState(context, q, v, mode); }); },
          py::arg("context"), py::arg("q"), py::arg("v"), py::arg("mode"),
          "Sets q, v and the mode in the plant's context (Diagram.get_subsystem_context).")
      .def_property_readonly("graph", &ContactPlant::graph)
      .def_property_readonly("mode_names",
                             [](const ContactPlant& plant) {
                               std::vector<std::string> names;
                               for (const auto& mode : plant.graph().modes) names.push_back(mode.name);
                               return names;
                             })
      .def("active_contacts", [](const ContactPlant& plant, int mode) {
        if (mode < 0 || mode >= static_cast<int>(plant.graph().modes.size()))
          throw py::index_error("system '" + plant.name() + "': mode " + std::to_string(mode) + " is outside [0, " +
                                std::to_string(plant.graph().modes.size()) + ")");
        std::vector<std::string> names;
        for (int c = 0; c < plant.model().num_contacts(); ++c)
          if (plant.active_contacts(mode) & ContactBit(c)) names.push_back(plant.model().contacts()[c].name);
        return names;
      });
  py::class_<HybridContactPlant, ContactPlant, Holder<HybridContactPlant>>(
      m, "HybridContactPlant",
      "A robot as an event-accurate hybrid system: rigid unilateral contacts, touchdown impacts, lift-off at F_n = 0; "
      "a slip or a fall ends the run as a failure.")
      .def(py::init(
               [](std::string name, const py::object& model, ContactModeGraph graph, Terrain terrain, const P& params) {
                 return FromArguments([&] {
                   return new HybridContactPlant(std::move(name), SharedModel(model), std::move(graph),
                                                 std::move(terrain), params);
                 });
               }),
           py::arg("name"), py::arg("model"), py::arg("graph"), py::arg("terrain") = Terrain::Flat(),
           py::arg("params") = P{});
}

void BindBulletWorldPlant(py::module_& m) {
  using P = BulletWorldPlantParams;
  ParamsClass<P>(m, "BulletWorldPlantParams", "BulletWorldPlant (systems/plants/bullet_world_plant.h).")
      .Field("step_s", &P::step_s, "[s]")
      .Field("substeps", &P::substeps)
      .Field("solver_iterations", &P::solver_iterations)
      .Field("contact_erp", &P::contact_erp)
      .Field("contact_stiffness_N_per_m", &P::contact_stiffness_N_per_m, "[N/m] 0: rigid")
      .Field("contact_damping_Ns_per_m", &P::contact_damping_Ns_per_m, "[N s/m]")
      .Field("restitution", &P::restitution)
      .Field("min_base_height_m", &P::min_base_height_m, "[m]")
      .Field("saturate_torques", &P::saturate_torques)
      .Field("enable_joint_limits", &P::enable_joint_limits)
      .Field("update_offset_s", &P::update_offset_s, "[s] after each multiple of step_s")
      .Field("solver_residual_threshold", &P::solver_residual_threshold, "[(m/s)^2] 0: always solver_iterations")
      .Field("warm_start_factor", &P::warm_start_factor, "[-] of the previous substep's impulses")
      .Field("joint_erp", &P::joint_erp, "[-]")
      .Field("cfm", &P::cfm, "[-] 0: rigid")
      .Field("external_force_input", &P::external_force_input, "declare the tau_external input")
      .Field("point_radius_m", &P::point_radius_m, "[m] sphere at each contact point")
      .Field("stone_depth_m", &P::stone_depth_m, "[m]")
      .Field("touchdown_force_N", &P::touchdown_force_N, "[N]")
      .Field("liftoff_height_m", &P::liftoff_height_m, "[m]")
      .Field("planned_liftoff_force_N", &P::planned_liftoff_force_N, "[N] < 0: off")
      .Field("planned_liftoff_min_contact_s", &P::planned_liftoff_min_contact_s,
             "[s] a planned lift-off releases only a contact touching this long")
      .Field("min_time_in_mode_s", &P::min_time_in_mode_s, "[s]")
      .Field("mode_change_delay_s", &P::mode_change_delay_s, "[s]")
      .Field("stone_tolerance_m", &P::stone_tolerance_m, "[m]")
      .Field("max_impulse_Ns", &P::max_impulse_Ns, "[N s]")
      .Field("slip_speed_mps", &P::slip_speed_mps, "[m/s]")
      .Field("slip_distance_m", &P::slip_distance_m, "[m] inf: off")
      .Field("slip_min_point_force_N", &P::slip_min_point_force_N, "[N]");
  py::class_<BulletWorldPlant, ContactPlant, Holder<BulletWorldPlant>>(
      m, "BulletWorldPlant",
      "A robot in Bullet's discrete-time physics world (one world step per step_s), with HybridContactPlant's ports.")
      .def(py::init(
               [](std::string name, const py::object& model, ContactModeGraph graph, Terrain terrain, const P& params) {
                 return FromArguments([&] {
                   return new BulletWorldPlant(std::move(name), SharedModel(model), std::move(graph),
                                               std::move(terrain), params);
                 });
               }),
           py::arg("name"), py::arg("model"), py::arg("graph"), py::arg("terrain") = Terrain::Flat(),
           py::arg("params") = P{});
}

/// TaskSpaceTask.calc: y, J and Jdot_qdot at (q, v) on a fresh workspace (sizes checked here: ValueError). The
/// task resolved its names against the model it was made with; `model` must have the same structure.
py::tuple CalcTask(const TaskSpaceTask& task, const py::object& model_object, const py::handle& q_in,
                   const py::handle& v_in) {
  const std::shared_ptr<const MultibodyModel> model = SharedModel(model_object);
  const Eigen::VectorXd q = ToVector(q_in, "TaskSpaceTask.calc q"), v = ToVector(v_in, "TaskSpaceTask.calc v");
  if (q.size() != model->nq() || v.size() != model->nv())
    throw py::value_error("TaskSpaceTask '" + task.name() + "'.calc: q has " + std::to_string(q.size()) + " and v " +
                          std::to_string(v.size()) + " elements; the model has nq = " + std::to_string(model->nq()) +
                          ", nv = " + std::to_string(model->nv()));
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd y(task.size()), Jdot_qdot(task.size());
  Eigen::MatrixXd J(task.size(), model->nv());
  task.Calc(*model, ws, q, v, y, J, Jdot_qdot);  // a failing JointFunctionTask function: RuntimeError
  return py::make_tuple(y, J, Jdot_qdot);
}

/// f(q) for JointFunctionTask from a Python callable returning (f, f'). The GIL is taken for the call (a diagram may
/// run its controllers on another thread); a Python error or a result that is not two numbers is a RuntimeError.
JointFunctionTask::Function PythonJointFunction(py::function function) {
  auto shared = std::shared_ptr<py::function>(new py::function(std::move(function)), [](py::function* f) {
    py::gil_scoped_acquire gil;
    delete f;
  });
  return [shared](double q, double* value, double* derivative) {
    py::gil_scoped_acquire gil;
    const py::object result = (*shared)(q);
    try {
      const auto pair = result.cast<std::pair<double, double>>();
      *value = pair.first;
      *derivative = pair.second;
    } catch (const py::cast_error&) {
      throw std::runtime_error("JointFunctionTask: the function must return (f(q), f'(q)), got " +
                               std::string(py::str(py::repr(result))));
    }
  };
}

void BindTasks(py::module_& m) {
  ParamsClass<TaskGains>(m, "TaskGains", "PD gains and cost weight of one task.")
      .Field("weight", &TaskGains::weight, "[-]")
      .Field("kp", &TaskGains::kp, "[1/s^2]")
      .Field("kd", &TaskGains::kd, "[1/s]");
  py::enum_<Axis>(m, "Axis").value("x", Axis::kX).value("y", Axis::kY).value("z", Axis::kZ);
  py::class_<TaskSpaceTask, std::shared_ptr<TaskSpaceTask>>(
      m, "TaskSpaceTask", "An output y(q) of relative degree two (systems/controllers/task_space_tasks.h).")
      .def_property_readonly("name", &TaskSpaceTask::name)
      .def_property_readonly("size", &TaskSpaceTask::size)
      .def_property_readonly("gains", &TaskSpaceTask::gains)
      .def_property_readonly("active_modes", &TaskSpaceTask::active_modes)
      .def("calc", &CalcTask, py::arg("model"), py::arg("q"), py::arg("v"),
           "(y, J, Jdot_qdot) at (q, v): y (size), J = dy/dq (size x nv), Jdot_qdot (size), as the controllers see "
           "them. `model` must be the one the task was made for.");
  py::class_<ComPositionTask, TaskSpaceTask, std::shared_ptr<ComPositionTask>>(m, "ComPositionTask",
                                                                               "p_com along `axes` [m].")
      .def(py::init([](std::string name, std::vector<Axis> axes, const TaskGains& gains, std::vector<int> modes) {
             return FromArguments([&] {
               return std::make_shared<ComPositionTask>(std::move(name), std::move(axes), gains, std::move(modes));
             });
           }),
           py::arg("name"), py::arg("axes"), py::arg("gains") = TaskGains{},
           py::arg("active_modes") = std::vector<int>{});
  py::class_<BodyPitchTask, TaskSpaceTask, std::shared_ptr<BodyPitchTask>>(m, "BodyPitchTask",
                                                                           "Pitch of a link about world +y [rad].")
      .def(py::init([](std::string name, const py::object& model, const std::string& body, const TaskGains& gains,
                       std::vector<int> modes) {
             return FromArguments([&] {
               return std::make_shared<BodyPitchTask>(std::move(name), *SharedModel(model), body, gains,
                                                      std::move(modes));
             });
           }),
           py::arg("name"), py::arg("model"), py::arg("body"), py::arg("gains") = TaskGains{},
           py::arg("active_modes") = std::vector<int>{});
  py::class_<PointPositionTask, TaskSpaceTask, std::shared_ptr<PointPositionTask>>(
      m, "PointPositionTask", "World position of a point on a link along `axes` [m].")
      .def_static(
          "for_contact",
          [](std::string name, const py::object& model, const std::string& contact, std::vector<Axis> axes,
             const TaskGains& gains, std::vector<int> modes) {
            return FromArguments([&] {
              return PointPositionTask::ForContact(std::move(name), *SharedModel(model), contact, std::move(axes),
                                                   gains, std::move(modes));
            });
          },
          py::arg("name"), py::arg("model"), py::arg("contact"), py::arg("axes"), py::arg("gains") = TaskGains{},
          py::arg("active_modes") = std::vector<int>{});
  py::class_<JointPositionTask, TaskSpaceTask, std::shared_ptr<JointPositionTask>>(m, "JointPositionTask",
                                                                                   "One coordinate q_i [rad or m].")
      .def(py::init([](std::string name, const py::object& model, const std::string& joint, const TaskGains& gains,
                       std::vector<int> modes) {
             return FromArguments([&] {
               return std::make_shared<JointPositionTask>(std::move(name), *SharedModel(model), joint, gains,
                                                          std::move(modes));
             });
           }),
           py::arg("name"), py::arg("model"), py::arg("joint"), py::arg("gains") = TaskGains{},
           py::arg("active_modes") = std::vector<int>{});
  py::class_<JointFunctionTask, TaskSpaceTask, std::shared_ptr<JointFunctionTask>>(
      m, "JointFunctionTask",
      "y = f(q_i) of one coordinate, e.g. Cassie's virtual leg length (hopping Eq. (13)). `function(q)` returns "
      "(f(q), f'(q)); it is called from the control loop, so a Python function costs a Python call per use "
      "(for prototyping, as a Python LeafSystem).")
      .def(py::init([](std::string name, const py::object& model, const std::string& joint, py::function function,
                       const TaskGains& gains, std::vector<int> modes, double step) {
             return FromArguments([&] {
               return std::make_shared<JointFunctionTask>(std::move(name), *SharedModel(model), joint,
                                                          PythonJointFunction(std::move(function)), gains,
                                                          std::move(modes), step);
             });
           }),
           py::arg("name"), py::arg("model"), py::arg("joint"), py::arg("function"), py::arg("gains") = TaskGains{},
           py::arg("active_modes") = std::vector<int>{}, py::arg("second_derivative_step") = 1e-5);
  py::class_<BodyOrientationTask, TaskSpaceTask, std::shared_ptr<BodyOrientationTask>>(
      m, "BodyOrientationTask",
      "Orientation of a link as the rotation vector log(R_world_body) [rad], J the world angular-velocity Jacobian "
      "(3D models; walking Eq. (17)).")
      .def(py::init([](std::string name, const py::object& model, const std::string& body, const TaskGains& gains,
                       std::vector<int> modes) {
             return FromArguments([&] {
               return std::make_shared<BodyOrientationTask>(std::move(name), *SharedModel(model), body, gains,
                                                            std::move(modes));
             });
           }),
           py::arg("name"), py::arg("model"), py::arg("body"), py::arg("gains") = TaskGains{},
           py::arg("active_modes") = std::vector<int>{});
  py::enum_<EulerAngle>(m, "EulerAngle")
      .value("roll", EulerAngle::kRoll)
      .value("pitch", EulerAngle::kPitch)
      .value("yaw", EulerAngle::kYaw);
  py::class_<BodyEulerAngleTask, TaskSpaceTask, std::shared_ptr<BodyEulerAngleTask>>(
      m, "BodyEulerAngleTask",
      "One ZYX Euler angle of a link, R = Rz(yaw) Ry(pitch) Rx(roll) [rad], on any 3D base (the quaternion "
      "free-flyer included); refused within singularity_margin_rad of pitch +-90 deg.")
      .def(py::init([](std::string name, const py::object& model, const std::string& body, EulerAngle angle,
                       const TaskGains& gains, std::vector<int> modes, double margin) {
             return FromArguments([&] {
               return std::make_shared<BodyEulerAngleTask>(std::move(name), *SharedModel(model), body, angle, gains,
                                                           std::move(modes), margin);
             });
           }),
           py::arg("name"), py::arg("model"), py::arg("body"), py::arg("angle"), py::arg("gains") = TaskGains{},
           py::arg("active_modes") = std::vector<int>{}, py::arg("singularity_margin_rad") = 1e-2);
  m.def(
      "make_base_angle_task",
      [](std::string name, const py::object& model, EulerAngle angle, const TaskGains& gains, std::vector<int> modes) {
        return FromArguments(
            [&] { return MakeBaseAngleTask(std::move(name), *SharedModel(model), angle, gains, std::move(modes)); });
      },
      "The floating base's ZYX angle: its coordinate on the Euler base, the root link's BodyEulerAngleTask on the "
      "quaternion base.",
      py::arg("name"), py::arg("model"), py::arg("angle"), py::arg("gains") = TaskGains{},
      py::arg("active_modes") = std::vector<int>{});
}

std::vector<std::shared_ptr<const TaskSpaceTask>> ConstTasks(const std::vector<std::shared_ptr<TaskSpaceTask>>& tasks) {
  return {tasks.begin(), tasks.end()};
}

py::dict TaskSpaceDiagnosticsDict(const TaskSpaceQpDiagnostics& d) {
  py::dict r;
  r["qp_failures"] = d.qp_failures;
  r["qp_status"] = d.qp_status ? py::cast(std::string(to_string(*d.qp_status))) : py::none();
  r["solved"] = d.solved;
  r["relaxed"] = d.relaxed;
  r["held"] = d.held;
  r["task_cost"] = d.task_cost;
  r["solve_time_s"] = d.solve_time_s;
  return r;
}

py::dict ClfDiagnosticsDict(const ClfQpDiagnostics& d) {
  py::dict r;
  r["V"] = d.V;
  r["delta"] = d.delta;
  r["qp_failures"] = d.qp_failures;
  r["qp_status"] = d.qp_status ? py::cast(std::string(to_string(*d.qp_status))) : py::none();
  r["drift_dropped"] = d.drift_dropped;
  r["band_dropped"] = d.band_dropped;
  r["cop_dropped"] = d.cop_dropped;
  r["held"] = d.held;
  r["clf_active"] = d.clf_active;
  r["solved"] = d.solved;
  r["solve_time_s"] = d.solve_time_s;
  return r;
}

void BindQpControllers(py::module_& m) {
  py::class_<TaskSpaceQpController, LeafSystem, Holder<TaskSpaceQpController>>(
      m, "TaskSpaceQpController",
      "Task-space QP, stepping-stones paper Eq. (29)-(31). Inputs state (2 nv), mode (int, typed, from the plant), "
      "desired (3 ny: [y_d; ydot_d; yddot_d], tasks stacked in order); outputs u (nu, N m), qdd (nv), "
      "contact_forces (3 nc, N, world), qp_failures, qp_status, solve_time_s.")
      .def(py::init([](std::string name, const ContactPlant& plant,
                       const std::vector<std::shared_ptr<TaskSpaceTask>>& tasks, const TaskSpaceQpParams& params) {
             return FromArguments([&] {
               return new TaskSpaceQpController(std::move(name), plant.shared_model(), ActiveContactsPerMode(plant),
                                                ConstTasks(tasks), params);
             });
           }),
           py::arg("name"), py::arg("plant"), py::arg("tasks"), py::arg("params") = TaskSpaceQpParams{},
           "The plant gives the robot model and each mode's contacts.")
      .def_property_readonly("num_task_outputs", &TaskSpaceQpController::num_task_outputs)
      .def("task_offset",
           [](const TaskSpaceQpController& c, int i) { return FromArguments([&] { return c.task_offset(i); }); })
      .def(
          "diagnostics",
          [](const TaskSpaceQpController& c, const LeafContext& context) {
            return TaskSpaceDiagnosticsDict(c.diagnostics(context));
          },
          py::arg("context"), "The 'diagnostics' typed output as a dict.");
  py::class_<RelativeDegreeOneOutput, std::shared_ptr<RelativeDegreeOneOutput>>(m, "RelativeDegreeOneOutput")
      .def_property_readonly("name", &RelativeDegreeOneOutput::name)
      .def_property_readonly("size", &RelativeDegreeOneOutput::size);
  py::class_<CentroidalPitchMomentumOutput, RelativeDegreeOneOutput, std::shared_ptr<CentroidalPitchMomentumOutput>>(
      m, "CentroidalPitchMomentumOutput", "Centroidal angular momentum about world y [N m s] (hopping Eq. (38)).")
      .def(py::init([](std::string name, double weight, std::vector<int> modes) {
             return std::make_shared<CentroidalPitchMomentumOutput>(std::move(name), weight, std::move(modes));
           }),
           py::arg("name") = "centroidal_pitch_momentum", py::arg("weight") = 1.0,
           py::arg("active_modes") = std::vector<int>{});
  py::class_<ClfQpController, LeafSystem, Holder<ClfQpController>>(
      m, "ClfQpController",
      "CLF-QP, hopping Eq. (22)-(37) / walking Eq. (18)-(25). Inputs state (2 nv), mode (int, typed), desired "
      "(3 ny); outputs u (nu, N m), contact_forces (3 nc, N, world), V, delta, qp_failures, qp_status. `outputs` "
      "holds TaskSpaceTasks (relative degree 2) and RelativeDegreeOneOutputs.")
      .def(
          py::init([](std::string name, const ContactPlant& plant, const py::list& outputs, const ClfQpParams& params) {
            std::vector<ClfOutput> clf;
            for (const py::handle& o : outputs) {
              if (py::isinstance<TaskSpaceTask>(o))
                clf.push_back(ClfOutput::RelativeDegreeTwo(o.cast<std::shared_ptr<TaskSpaceTask>>()));
              else if (py::isinstance<RelativeDegreeOneOutput>(o))
                clf.push_back(ClfOutput::RelativeDegreeOne(o.cast<std::shared_ptr<RelativeDegreeOneOutput>>()));
              else
                throw py::type_error("ClfQpController '" + name + "': outputs must be TaskSpaceTask or " +
                                     "RelativeDegreeOneOutput objects, got " + std::string(py::str(py::repr(o))));
            }
            return FromArguments([&] {
              return new ClfQpController(std::move(name), plant.shared_model(), ActiveContactsPerMode(plant),
                                         std::move(clf), params);
            });
          }),
          py::arg("name"), py::arg("plant"), py::arg("outputs"), py::arg("params") = ClfQpParams{})
      .def_property_readonly("num_outputs", &ClfQpController::num_outputs)
      .def("P_epsilon",
           [](const ClfQpController& c, int mode) { return FromArguments([&] { return c.P_epsilon(mode); }); })
      .def(
          "diagnostics",
          [](const ClfQpController& c, const LeafContext& context) {
            return ClfDiagnosticsDict(c.diagnostics(context));
          },
          py::arg("context"), "The 'diagnostics' typed output as a dict.");
}

}  // namespace

void BindContactBlocks(py::module_& m) {
  RegisterTypedValue<TaskSpaceQpDiagnostics>(
      [](const TaskSpaceQpDiagnostics& d) { return TaskSpaceDiagnosticsDict(d); });
  RegisterTypedValue<ClfQpDiagnostics>([](const ClfQpDiagnostics& d) { return ClfDiagnosticsDict(d); });
  BindContactModeGraph(m);
  BindHybridContactPlant(m);
  BindBulletWorldPlant(m);
  BindTasks(m);
  BindQpControllers(m);
}

}  // namespace rome::python
