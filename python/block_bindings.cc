// Python bindings of C++ blocks (systems/): the LIP flow, the controllers (LQR state feedback, joint PD) and the
// parameter structs of the CLF-QP and task-space QP controllers (the controllers themselves are built by the
// diagrams, whose parameters hold these structs).
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "python/params.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/joint_pd_controller.h"
#include "systems/controllers/lqr_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/rom/linear_inverted_pendulum_system.h"

namespace py = pybind11;

namespace rome::python {
namespace {

void BindControllerParams(py::module_& m) {
  py::enum_<ClfQpFormulation>(m, "ClfQpFormulation")
      .value("eliminate_contact_forces", ClfQpFormulation::kEliminateContactForces)
      .value("augmented_input", ClfQpFormulation::kAugmentedInput);
  ParamsClass<ContactWrenchParams>(
      m, "ContactWrenchParams", "Contact wrench rows of the CLF-QP (systems/controllers/contact_wrench_constraints.h).")
      .Field("min_normal_force_N", &ContactWrenchParams::min_normal_force_N, "[N]")
      .Field("friction_coefficient", &ContactWrenchParams::friction_coefficient, "[-] < 0: the model's")
      .Field("friction_margin", &ContactWrenchParams::friction_margin, "[-]")
      .Field("friction_cone_offset_N", &ContactWrenchParams::friction_cone_offset_N, "[N] the pyramid's apex")
      .Field("inscribe_pyramid", &ContactWrenchParams::inscribe_pyramid)
      .Field("cop_margin_m", &ContactWrenchParams::cop_margin_m, "[m]")
      .Field("yaw_moment_coefficient_m", &ContactWrenchParams::yaw_moment_coefficient_m, "[m] < 0: no bound")
      .Field("corner_wrench_cone", &ContactWrenchParams::corner_wrench_cone)
      .Field("corner_cone_friction_coefficient", &ContactWrenchParams::corner_cone_friction_coefficient,
             "[-] the corner cone's mu; < 0: the friction rows' (margin-scaled) mu")
      .Field("corner_cone_yaw_margin_m", &ContactWrenchParams::corner_cone_yaw_margin_m,
             "[m] the corner cone's yaw rows on the whole sole less this; < 0: the CoP rows' sole");
  ParamsClass<JointLimitBrakeParams>(m, "JointLimitBrakeParams",
                                     "q-double-dot bounds that brake each joint before its URDF limit "
                                     "(systems/controllers/joint_limit_brake.h).")
      .Field("enabled", &JointLimitBrakeParams::enabled)
      .Field("margin_rad", &JointLimitBrakeParams::margin_rad, "[rad]")
      .Field("horizon_s", &JointLimitBrakeParams::horizon_s, "[s]");
  py::enum_<TorqueRegularization>(m, "TorqueRegularization")
      .value("uniform", TorqueRegularization::kUniform)
      .value("inverse_joint_inertia", TorqueRegularization::kInverseJointInertia);
  ParamsClass<ConstrainedDynamicsParameters>(
      m, "ConstrainedDynamicsParameters", "Contact/loop-closure stabilisation (systems/multibody/contact_dynamics.h).")
      .Field("baumgarte_alpha_per_s", &ConstrainedDynamicsParameters::baumgarte_alpha_per_s, "[1/s]")
      .Field("baumgarte_beta_per_s", &ConstrainedDynamicsParameters::baumgarte_beta_per_s, "[1/s]")
      .Field("regularization", &ConstrainedDynamicsParameters::regularization, "[-] relative Tikhonov term");
  ParamsClass<QpSettings>(m, "QpSettings", "DenseQpSolver tolerances (solvers/qp/dense_qp_solver.h).")
      .Field("max_iterations", &QpSettings::max_iterations)
      .Field("feasibility_tolerance", &QpSettings::feasibility_tolerance, "[unit of each row]")
      .Field("linear_dependence_tolerance", &QpSettings::linear_dependence_tolerance, "[-]")
      .Field("regularization", &QpSettings::regularization, "[unit of H]")
      .Field("proximal_tolerance", &QpSettings::proximal_tolerance, "[unit of g]")
      .Field("max_proximal_iterations", &QpSettings::max_proximal_iterations)
      .Field("infinity", &QpSettings::infinity)
      .Field("warm_start", &QpSettings::warm_start)
      .Field("hot_start", &QpSettings::hot_start);
  py::class_<EventTrigger>(m, "EventTrigger",
                           "Which guard events run an event update: every guard (no names) or the named (system, "
                           "guard) pairs; a guard ending in '*' matches a prefix (framework/system.h).")
      .def(py::init([](const std::vector<std::pair<std::string, std::string>>& guards) {
             EventTrigger t;
             for (const auto& [system, guard] : guards) t.guards.push_back({system, guard});
             return t;
           }),
           py::arg("guards") = std::vector<std::pair<std::string, std::string>>{})
      .def_property_readonly("guards",
                             [](const EventTrigger& t) {
                               std::vector<std::pair<std::string, std::string>> g;
                               for (const auto& name : t.guards) g.emplace_back(name.system, name.guard);
                               return g;
                             })
      .def("__repr__", [](const EventTrigger& t) {
        if (t.any()) return std::string("EventTrigger(any guard)");
        std::string text = "EventTrigger([";
        for (size_t i = 0; i < t.guards.size(); ++i)
          text += (i ? ", " : "") + ("('" + t.guards[i].system + "', '" + t.guards[i].guard + "')");
        return text + "])";
      });
  ParamsClass<ClfQpParams>(m, "ClfQpParams", "CLF-QP controller (systems/controllers/clf_qp_controller.h).")
      .Field("update_period_s", &ClfQpParams::update_period_s, "[s]")
      .Field("formulation", &ClfQpParams::formulation)
      .Field("epsilon", &ClfQpParams::epsilon, "[-] RES-CLF epsilon")
      .Field("gamma", &ClfQpParams::gamma, "[-] <= 0: lambda_min(Q)/lambda_max(P)")
      .Field("relaxation_weight", &ClfQpParams::relaxation_weight, "[-] p on delta^2 / 2")
      .Field("u_regularization", &ClfQpParams::u_regularization, "[-]")
      .Field("force_band", &ClfQpParams::force_band)
      .Field("contact", &ClfQpParams::contact)
      .Field("force_band_halfwidth", &ClfQpParams::force_band_halfwidth, "[-] c of Eq. (25)")
      .Field("force_band_loading_floor_N", &ClfQpParams::force_band_loading_floor_N, "[N]")
      .Field("force_band_carry_inactive", &ClfQpParams::force_band_carry_inactive)
      .Field("force_band_at_hold_end", &ClfQpParams::force_band_at_hold_end)
      .Field("force_band_margin_N", &ClfQpParams::force_band_margin_N, "[N]")
      .Field("joint_limit_brake", &ClfQpParams::joint_limit_brake)
      .Field("torque_limits", &ClfQpParams::torque_limits, "[N m]; empty: the model's")
      .Field("resolve_at_events", &ClfQpParams::resolve_at_events)
      .Field("u_regularization_kind", &ClfQpParams::u_regularization_kind)
      .Field("u_regularization_weights", &ClfQpParams::u_regularization_weights, "[-] per actuator, > 0; empty: 1")
      .Field("u_regularization_modes", &ClfQpParams::u_regularization_modes, "empty: every mode")
      .Field("force_band_loading_fall_tolerance_N", &ClfQpParams::force_band_loading_fall_tolerance_N, "[N]")
      .Field("zero_torque_in_contact", &ClfQpParams::zero_torque_in_contact, "[(contact, joint)]: u = 0 in contact")
      .Field("contact_stabilization", &ClfQpParams::contact_stabilization)
      .Field("resolve_at", &ClfQpParams::resolve_at)
      .Field("qp", &ClfQpParams::qp)
      .Field("cost_only_outputs", &ClfQpParams::cost_only_outputs, "names of outputs kept out of the RES-CLF")
      .Field("predict_hold_drift", &ClfQpParams::predict_hold_drift)
      .Field("hold_drift_settle_s", &ClfQpParams::hold_drift_settle_s)
      .Field("cost_pd_feedback", &ClfQpParams::cost_pd_feedback)
      .Field("clf_active_tolerance", &ClfQpParams::clf_active_tolerance, "[-]");
  py::enum_<QpFailurePolicy>(m, "QpFailurePolicy")
      .value("relax_contact_forces", QpFailurePolicy::kRelaxContactForces)
      .value("hold_previous", QpFailurePolicy::kHoldPrevious)
      .value("zero_torque", QpFailurePolicy::kZeroTorque);
  ParamsClass<TaskSpaceQpParams>(m, "TaskSpaceQpParams",
                                 "Task-space QP controller (systems/controllers/task_space_qp_controller.h).")
      .Field("update_period_s", &TaskSpaceQpParams::update_period_s, "[s]")
      .Field("qdd_regularization", &TaskSpaceQpParams::qdd_regularization)
      .Field("u_regularization", &TaskSpaceQpParams::u_regularization)
      .Field("force_regularization", &TaskSpaceQpParams::force_regularization)
      .Field("min_normal_force_N", &TaskSpaceQpParams::min_normal_force_N, "[N]")
      .Field("friction_coefficient", &TaskSpaceQpParams::friction_coefficient, "[-] < 0: the model's")
      .Field("friction_margin", &TaskSpaceQpParams::friction_margin, "[-]")
      .Field("friction_cone_offset_N", &TaskSpaceQpParams::friction_cone_offset_N, "[N] the pyramid's apex")
      .Field("torque_limits", &TaskSpaceQpParams::torque_limits, "[N m]; empty: the model's")
      .Field("resolve_at_events", &TaskSpaceQpParams::resolve_at_events)
      .Field("predict_hold_drift", &TaskSpaceQpParams::predict_hold_drift)
      .Field("resolve_at", &TaskSpaceQpParams::resolve_at)
      .Field("zero_torque_in_contact", &TaskSpaceQpParams::zero_torque_in_contact,
             "[(contact, joint)]: u = 0 in contact")
      .Field("contact_stabilization", &TaskSpaceQpParams::contact_stabilization)
      .Field("qp", &TaskSpaceQpParams::qp)
      .Field("failure_policy", &TaskSpaceQpParams::failure_policy);
}

void BindJointPd(py::module_& m) {
  ParamsClass<JointPdGains>(m, "JointPdGains", "Per-actuator gains of JointPdController.")
      .Field("kp", &JointPdGains::kp, "[N m/rad]")
      .Field("kd", &JointPdGains::kd, "[N m s/rad]")
      .Field("q_des", &JointPdGains::q_des, "[rad]")
      .Field("u_ff", &JointPdGains::u_ff, "[N m]");
  py::class_<JointPdController, LeafSystem, Holder<JointPdController>>(
      m, "JointPdController",
      "u = u_ff + Kp (q_des - B^T q) - Kd B^T v on the actuated joints. Input state [q; v] (2 nv), output u (nu).")
      .def(py::init([](std::string name, const Eigen::MatrixXd& B, const JointPdGains& gains) {
             return FromArguments([&] { return new JointPdController(std::move(name), B, gains); });
           }),
           py::arg("name"), py::arg("B"), py::arg("gains"));
}

}  // namespace

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
             return FromArguments([&] { return new LinearInvertedPendulumSystem(std::move(name), p); });
           }),
           py::arg("name") = "lip", py::arg("initial_x") = LinearInvertedPendulumSystemParams{}.initial_x,
           py::arg("initial_L") = LinearInvertedPendulumSystemParams{}.initial_L,
           py::arg("z0") = LinearInvertedPendulumParams{}.z0,
           py::arg("gravity") = LinearInvertedPendulumParams{}.gravity);
  py::class_<LqrController, LeafSystem, Holder<LqrController>>(
      m, "LqrController",
      "u = u0 - K (x - x0) with the LQR gain of (A, B, Q, R) (systems/controllers/lqr_controller.h).")
      .def(py::init([](std::string name, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                       const Eigen::MatrixXd& R, const Eigen::VectorXd& x0, const Eigen::VectorXd& u0) {
             return FromArguments([&] { return new LqrController(std::move(name), A, B, Q, R, x0, u0); });
           }),
           py::arg("name"), py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"), py::arg("x0"), py::arg("u0"))
      .def(py::init([](std::string name, const LinearSystemMatrices& linearization, const Eigen::MatrixXd& Q,
                       const Eigen::MatrixXd& R) {
             return FromArguments([&] { return new LqrController(std::move(name), linearization, Q, R); });
           }),
           py::arg("name"), py::arg("linearization"), py::arg("Q"), py::arg("R"))
      .def_property_readonly("K", &LqrController::K)
      .def_property_readonly("S", &LqrController::S);
  BindJointPd(m);
  BindControllerParams(m);
}

}  // namespace rome::python
