// Python bindings of the multibody robot model (systems/multibody): MultibodyModel loaded from a robot file, with its
// facts (nq, nv, joint names, limits, mass) and its dynamics on numpy arrays. Each Python MultibodyModel owns one
// MultibodyWorkspace (Pinocchio's model/data pair in one object), so its calls are not for several threads at once.
#include <cmath>
#include <memory>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"

namespace py = pybind11;

namespace rome::python {
namespace {

/// The model and its workspace (the workspace refers to the model, so both live at one fixed address).
struct PyMultibodyModel {
  explicit PyMultibodyModel(MultibodyModel m) : model(std::move(m)), ws(model) {}
  MultibodyModel model;
  MultibodyWorkspace ws;
  std::shared_ptr<const MultibodyModel> shared;  ///< a copy for blocks (plants, controllers), made once, on demand

  void Check(const Eigen::VectorXd& x, int size, const char* what) const {
    if (x.size() != size)
      throw py::value_error("MultibodyModel '" + model.name() + "': " + what + " has " + std::to_string(x.size()) +
                            " entries, expected " + std::to_string(size));
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (!std::isfinite(x[i]))
        throw py::value_error("MultibodyModel '" + model.name() + "': " + what + "[" + std::to_string(i) +
                              "] = " + std::to_string(x[i]) + " is not finite");
  }
  Eigen::MatrixXd MassMatrix(const Eigen::VectorXd& q) {
    Check(q, model.nq(), "q");
    return CalcMassMatrix(model, ws, q).selfadjointView<Eigen::Lower>();
  }
  Eigen::VectorXd BiasForces(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    Check(q, model.nq(), "q");
    Check(v, model.nv(), "v");
    return CalcBiasForces(model, ws, q, v);
  }
  Eigen::VectorXd SpringTorques(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    Check(q, model.nq(), "q");
    Check(v, model.nv(), "v");
    return CalcSpringTorques(model, ws, q, v);
  }
  Eigen::VectorXd InverseDynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& qdd) {
    Check(q, model.nq(), "q");
    Check(v, model.nv(), "v");
    Check(qdd, model.nv(), "qdd");
    Eigen::VectorXd tau(model.nv());
    CalcInverseDynamics(model, ws, q, v, qdd, tau);
    return tau;
  }
  Eigen::VectorXd ForwardDynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& u,
                                  const Eigen::VectorXd& tau_ext) {
    Check(q, model.nq(), "q");
    Check(v, model.nv(), "v");
    Check(u, model.nu(), "u");
    if (tau_ext.size() != 0) Check(tau_ext, model.nv(), "tau_ext");
    Eigen::VectorXd qdd(model.nv());
    CalcForwardDynamics(model, ws, q, v, u, tau_ext, qdd);
    return qdd;
  }
  Eigen::Vector3d ComPosition(const Eigen::VectorXd& q) {
    Check(q, model.nq(), "q");
    return CalcComPosition(model, ws, q);
  }
  Eigen::Vector3d ComVelocity(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    Check(q, model.nq(), "q");
    Check(v, model.nv(), "v");
    return CalcComVelocity(model, ws, q, v);
  }
  Eigen::Vector3d PointPosition(const Eigen::VectorXd& q, const std::string& link, const Eigen::Vector3d& p_link) {
    Check(q, model.nq(), "q");
    const MultibodyFrame& frame = model.Frame(link);
    return CalcPointPosition(model, ws, q, frame.body, frame.X_body_frame * p_link);
  }
  Eigen::MatrixXd PointJacobian(const Eigen::VectorXd& q, const std::string& link, const Eigen::Vector3d& p_link) {
    Check(q, model.nq(), "q");
    const MultibodyFrame& frame = model.Frame(link);
    Eigen::MatrixXd J(3, model.nv());
    CalcPointJacobian(model, ws, q, frame.body, frame.X_body_frame * p_link, J);
    return J;
  }
  int ContactIndex(const std::string& contact) const {
    for (int i = 0; i < model.num_contacts(); ++i)
      if (model.contacts()[i].name == contact) return i;
    throw py::value_error("MultibodyModel '" + model.name() + "': no contact named '" + contact + "'");
  }
  /// World position and 3 x nv Jacobian of a contact's frame origin.
  Eigen::Vector3d ContactPosition(const Eigen::VectorXd& q, const std::string& contact) {
    Check(q, model.nq(), "q");
    const ContactInfo& c = model.contacts()[ContactIndex(contact)];
    return CalcPointPosition(model, ws, q, c.body, c.frame_origin);
  }
  Eigen::MatrixXd ContactJacobian(const Eigen::VectorXd& q, const std::string& contact) {
    Check(q, model.nq(), "q");
    const ContactInfo& c = model.contacts()[ContactIndex(contact)];
    Eigen::MatrixXd J(3, model.nv());
    CalcPointJacobian(model, ws, q, c.body, c.frame_origin, J);
    return J;
  }
  Eigen::VectorXd CentroidalMomentum(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    Check(q, model.nq(), "q");
    Check(v, model.nv(), "v");
    return CalcCentroidalMomentum(model, ws, q, v);
  }
};

std::vector<std::string> ActuatedJoints(const MultibodyModel& model) {
  std::vector<std::string> names;
  for (const ActuatorInfo& a : model.actuators()) names.push_back(a.joint);
  return names;
}

std::vector<std::string> ContactNames(const MultibodyModel& model) {
  std::vector<std::string> names;
  for (const ContactInfo& c : model.contacts()) names.push_back(c.name);
  return names;
}

}  // namespace

std::shared_ptr<const MultibodyModel> SharedModel(const py::handle& model) {
  PyMultibodyModel* p = nullptr;
  try {
    p = model.cast<PyMultibodyModel*>();
  } catch (const py::cast_error&) {}
  if (p == nullptr)
    throw py::type_error("expected a rome.MultibodyModel, got " + std::string(py::str(py::repr(model))));
  if (!p->shared) p->shared = std::make_shared<const MultibodyModel>(p->model);
  return p->shared;
}

void BindMultibody(py::module_& m) {
  py::class_<PyMultibodyModel>(
      m, "MultibodyModel",
      "A robot loaded from its robot files (systems/multibody/multibody_model.h), with a workspace for its dynamics:\n"
      "  M(q) qdd + h(q, v) = B u + tau_spring(q, v) + tau_ext   (SI units, gravity 9.81 m/s^2 along -z).\n"
      "q = [base coordinates, joints] with nq == nv (nq == nv + 1 on the quaternion base); joint_names lists every\n"
      "velocity coordinate in order.")
      .def_static(
          "load",
          [](const std::string& path, bool repair_inertia, bool quaternion_floating_base, bool euler_floating_base) {
            LoadOptions options;
            options.repair_inertia = repair_inertia;
            options.quaternion_floating_base = quaternion_floating_base;
            options.euler_floating_base = euler_floating_base;
            const bool sidecar = path.size() > 10 && path.substr(path.size() - 10) == ".rome.json";
            return FromArguments([&] {
              return std::make_unique<PyMultibodyModel>(sidecar ? MultibodyModel::LoadFromSidecar(path, options)
                                                                : MultibodyModel::Load(path, "", options));
            });
          },
          py::arg("path"), py::arg("repair_inertia") = false, py::arg("quaternion_floating_base") = false,
          py::arg("euler_floating_base") = false,
          "Loads a robot from its sidecar (robots/NAME/NAME.rome.json) or its URDF (the sidecar beside it, if any).\n"
          "A spatial base is the quaternion free-flyer by default (systems/multibody/free_flyer.h):\n"
          "q = [x, y, z, qw, qx, qy, qz, joints] (nq = nv + 1), v = [base twist in base axes (linear, angular),\n"
          "joint rates]. euler_floating_base: the ZYX-Euler base instead (q = [x, y, z, yaw, pitch, roll, joints],\n"
          "nq = nv), as the sidecar's \"floating_base\": \"spatial_euler\"; no effect on a fixed or planar robot.\n"
          "quaternion_floating_base: the free-flyer even if the sidecar says \"spatial_euler\"; a fixed or planar\n"
          "robot is refused. Both set is refused.")
      .def_property_readonly("name", [](const PyMultibodyModel& p) { return p.model.name(); })
      .def_property_readonly("floating_base",
                             [](const PyMultibodyModel& p) { return ToString(p.model.floating_base()); })
      .def_property_readonly(
          "base_kind", [](const PyMultibodyModel& p) { return p.model.base_kind(); },
          "'fixed', 'planar', 'quaternion' or 'spatial_euler' (ZYX Euler)")
      .def_property_readonly("nq", [](const PyMultibodyModel& p) { return p.model.nq(); })
      .def_property_readonly("nv", [](const PyMultibodyModel& p) { return p.model.nv(); })
      .def_property_readonly("nu", [](const PyMultibodyModel& p) { return p.model.nu(); })
      .def_property_readonly("num_base_dofs", [](const PyMultibodyModel& p) { return p.model.num_base_dofs(); })
      .def_property_readonly("joint_names", [](const PyMultibodyModel& p) { return p.model.joint_names(); })
      .def_property_readonly("actuated_joints", [](const PyMultibodyModel& p) { return ActuatedJoints(p.model); })
      .def_property_readonly("contact_names", [](const PyMultibodyModel& p) { return ContactNames(p.model); })
      .def_property_readonly(
          "total_mass", [](const PyMultibodyModel& p) { return p.model.total_mass(); }, "[kg]")
      .def_property_readonly(
          "body_masses",
          [](const PyMultibodyModel& p) {
            std::vector<double> masses;
            for (const MultibodyBody& b : p.model.bodies()) masses.push_back(b.mass);
            return masses;
          },
          "[kg] of every rigid body (links merged over fixed joints), virtual base bodies 0")
      .def_property_readonly("position_lower_limits",
                             [](const PyMultibodyModel& p) { return p.model.position_lower_limits(); })
      .def_property_readonly("position_upper_limits",
                             [](const PyMultibodyModel& p) { return p.model.position_upper_limits(); })
      .def_property_readonly("torque_limits", [](const PyMultibodyModel& p) { return p.model.torque_limits(); })
      .def_property_readonly(
          "B", [](const PyMultibodyModel& p) { return p.model.B(); }, "nv x nu actuation matrix")
      .def_property_readonly("q_nominal", [](const PyMultibodyModel& p) { return p.model.q_nominal(); })
      .def_property_readonly("gravity", [](const PyMultibodyModel& p) { return p.model.gravity(); })
      .def_property_readonly("warnings", [](const PyMultibodyModel& p) { return p.model.warnings(); })
      .def("velocity_index",
           [](const PyMultibodyModel& p, const std::string& joint) { return p.model.VelocityIndex(joint); })
      .def("mass_matrix", &PyMultibodyModel::MassMatrix, py::arg("q"), "M(q), nv x nv (CRBA + reflected inertia)")
      .def("bias_forces", &PyMultibodyModel::BiasForces, py::arg("q"), py::arg("v"), "h = C(q, v) v + g(q) (RNEA)")
      .def("spring_torques", &PyMultibodyModel::SpringTorques, py::arg("q"), py::arg("v"))
      .def("inverse_dynamics", &PyMultibodyModel::InverseDynamics, py::arg("q"), py::arg("v"), py::arg("qdd"),
           "tau = M qdd + h - tau_spring")
      .def("forward_dynamics", &PyMultibodyModel::ForwardDynamics, py::arg("q"), py::arg("v"), py::arg("u"),
           py::arg("tau_ext") = Eigen::VectorXd(),
           "qdd = M^-1 (B u + tau_spring + tau_ext - h) (Bullet's ABA; CRBA + tree factor on the quaternion base)")
      .def("com_position", &PyMultibodyModel::ComPosition, py::arg("q"))
      .def("com_velocity", &PyMultibodyModel::ComVelocity, py::arg("q"), py::arg("v"))
      .def("point_position", &PyMultibodyModel::PointPosition, py::arg("q"), py::arg("link"),
           py::arg("p_link") = Eigen::Vector3d::Zero(), "world position of a point given in a URDF link's frame")
      .def("point_jacobian", &PyMultibodyModel::PointJacobian, py::arg("q"), py::arg("link"),
           py::arg("p_link") = Eigen::Vector3d::Zero(), "3 x nv")
      .def("contact_position", &PyMultibodyModel::ContactPosition, py::arg("q"), py::arg("contact"),
           "world position of a contact's frame origin [m]")
      .def("contact_jacobian", &PyMultibodyModel::ContactJacobian, py::arg("q"), py::arg("contact"),
           "3 x nv Jacobian of a contact's frame origin (world axes)")
      .def_property_readonly("contact_friction_coefficients",
                             [](const PyMultibodyModel& p) {
                               std::vector<double> mu;
                               for (const ContactInfo& c : p.model.contacts()) mu.push_back(c.friction_coefficient);
                               return mu;
                             })
      .def("centroidal_momentum", &PyMultibodyModel::CentroidalMomentum, py::arg("q"), py::arg("v"),
           "[angular about the COM; linear]")
      .def("__repr__", [](const PyMultibodyModel& p) {
        return "MultibodyModel('" + p.model.name() + "', floating_base=" + ToString(p.model.floating_base()) +
               ", nq=" + std::to_string(p.model.nq()) + ", nu=" + std::to_string(p.model.nu()) +
               ", total_mass=" + std::to_string(p.model.total_mass()) + " kg)";
      });
}

}  // namespace rome::python
