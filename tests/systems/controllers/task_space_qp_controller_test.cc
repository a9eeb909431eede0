// TaskSpaceQpController: the QP answer against its KKT conditions and against the plant's constrained forward
// dynamics, the GRF constraints when they bind and the documented fallback on an infeasible QP. The closed-loop runs
// with the HybridContactPlant are in task_space_qp_controller_closed_loop_test.cc (slow under sanitizers).
#include "systems/controllers/task_space_qp_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "systems/multibody/multibody_dynamics.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

using test::AmberDoubleSupportPose;
using test::AmberSingleSupportPose;
using test::AmberWalkingTasks;
using test::LoadRobot;
using test::TaskValues;

using Tasks = std::vector<std::shared_ptr<const TaskSpaceTask>>;

// A velocity that the stance contacts allow (J_c v = 0), so the plant's Baumgarte term vanishes.
Eigen::VectorXd ContactConsistentVelocity(const MultibodyModel& model, const Eigen::VectorXd& q, ContactSet active,
                                          unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Eigen::VectorXd v(model.nv());
  for (int i = 0; i < model.nv(); ++i) v[i] = scale * U(rng);
  MultibodyWorkspace ws(model);
  const int rows = CalcConstraintJacobian(model, ws, q, v, active);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  return v - J.completeOrthogonalDecomposition().solve(J * v);
}

Eigen::VectorXd Stack(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c) {
  Eigen::VectorXd d(a.size() + b.size() + c.size());
  d << a, b, c;
  return d;
}

struct QpAnswer {
  Eigen::VectorXd qdd, u, F;
};

// Solves once at (q, v) with the desired outputs; checks the KKT conditions and the equations of motion with the
// QP's own (q̈, u, F), recomputed from the multibody layer.
QpAnswer SolveAndCheck(const TaskSpaceQpController& controller, LeafContext& context, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& v, int mode, ContactSet active, const Eigen::VectorXd& desired) {
  const MultibodyModel& model = controller.model();
  const int nv = model.nv(), nu = model.nu();
  Eigen::VectorXd x(2 * nv);
  x << q, v;
  context.FixInputPort(0, x);
  context.FixAbstractInputPort(1, std::any(static_cast<int>(mode)));
  context.FixInputPort(2, desired);
  const QpStatus status = controller.SolveQp(context);
  const DenseQpSolver& qp = controller.last_qp(context);
  EXPECT_EQ(status, QpStatus::kOptimal) << qp.status_message();
  const QpKktResiduals kkt = ComputeQpKktResiduals(qp);
  std::printf("  QP KKT: stationarity %.2e, primal %.2e, dual %.2e, complementarity %.2e (%d iterations, %d active)\n",
              kkt.stationarity, kkt.primal_feasibility, kkt.dual_feasibility, kkt.complementarity, qp.iterations(),
              qp.active_set_size());
  EXPECT_LT(kkt.stationarity, 1e-8);
  EXPECT_LT(kkt.primal_feasibility, 1e-8);
  EXPECT_LT(kkt.dual_feasibility, 1e-12);
  EXPECT_LT(kkt.complementarity, 1e-8);
  const int rows = controller.last_num_force_rows(context);
  QpAnswer r{qp.x().head(nv), qp.x().segment(nv, nu), qp.x().tail(rows)};
  MultibodyWorkspace ws(model);
  EXPECT_EQ(CalcConstraintJacobian(model, ws, q, v, active), rows);
  const Eigen::MatrixXd Jc = ws.J.topRows(rows);
  const Eigen::VectorXd Jdq = ws.Jdot_qdot.head(rows);
  const Eigen::VectorXd eom =
      CalcMassMatrix(model, ws, q) * r.qdd + CalcBiasForces(model, ws, q, v) - model.B() * r.u - Jc.transpose() * r.F;
  EXPECT_LT(eom.cwiseAbs().maxCoeff(), 1e-7) << eom.transpose();
  EXPECT_LT((Jc * r.qdd + Jdq).cwiseAbs().maxCoeff(), 1e-9);
  // Torque limits, unilateral contact and the friction pyramid (planar point feet: F = [F_x, F_z] per foot).
  EXPECT_LE(r.u.cwiseAbs().maxCoeff(), controller.torque_limits().maxCoeff() + 1e-9);
  for (int i = 0; i < rows / 2; ++i) {
    EXPECT_GE(r.F[2 * i + 1], controller.params().min_normal_force_N - 1e-9);
    const double mu = controller.params().friction_coefficient >= 0 ? controller.params().friction_coefficient : 0.8;
    EXPECT_LE(std::abs(r.F[2 * i]), mu * r.F[2 * i + 1] + 1e-9);
  }
  return r;
}

// The plant's constrained dynamics with the QP's torques reproduce the QP's q̈ and F.
void ExpectPlantAgrees(const MultibodyModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                       ContactSet active, const QpAnswer& a, const Tasks& tasks, const Eigen::VectorXd& ydd_star,
                       double task_tolerance) {
  MultibodyWorkspace ws(model);
  Eigen::VectorXd qdd(model.nv()), F(model.max_constraint_rows());
  const int rows =
      CalcConstrainedForwardDynamics(model, ws, q, v, a.u, active, ConstrainedDynamicsParameters{}, qdd, F);
  const double qdd_error = (qdd - a.qdd).cwiseAbs().maxCoeff();
  const double F_error = (F.head(rows) - a.F).cwiseAbs().maxCoeff();
  Eigen::MatrixXd J;
  Eigen::VectorXd Jdq;
  TaskValues(model, tasks, q, v, &J, &Jdq);
  const Eigen::VectorXd ydd_plant = J * qdd + Jdq, ydd_qp = J * a.qdd + Jdq;
  std::printf("  plant vs QP: |q̈ error| %.2e, |F error| %.2e N, |ÿ_plant − ÿ_QP| %.2e, |ÿ_plant − ÿ*| %.2e\n",
              qdd_error, F_error, (ydd_plant - ydd_qp).cwiseAbs().maxCoeff(),
              (ydd_plant - ydd_star).cwiseAbs().maxCoeff());
  EXPECT_LT(qdd_error, 1e-6);
  EXPECT_LT(F_error, 1e-6 * model.total_mass() * 9.81);
  EXPECT_LT((ydd_plant - ydd_qp).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((ydd_plant - ydd_star).cwiseAbs().maxCoeff(), task_tolerance)
      << "ÿ_plant " << ydd_plant.transpose() << "\nÿ*      " << ydd_star.transpose();
}

// ÿ* = ÿ_d + Kp (y_d − y) + Kd (ẏ_d − J v) for tasks that share one TaskGains.
Eigen::VectorXd PdTarget(const MultibodyModel& model, const Tasks& tasks, const Eigen::VectorXd& q,
                         const Eigen::VectorXd& v, const Eigen::VectorXd& desired, const TaskGains& g) {
  Eigen::MatrixXd J;
  const Eigen::VectorXd y = TaskValues(model, tasks, q, v, &J);
  const int ny = static_cast<int>(y.size());
  return desired.tail(ny) + g.kp * (desired.head(ny) - y) + g.kd * (desired.segment(ny, ny) - J * v);
}

// The smallest regularisation that keeps H numerically positive definite for DenseQpSolver (pivots above 1e-8
// max H_jj): tasks the robot can meet exactly are met up to a bias of about 3e-5 |ÿ*| (measured ~2e-4 m/s²).
TaskSpaceQpParams TinyRegularisation() {
  TaskSpaceQpParams p;
  p.qdd_regularization = 1e-7;
  p.u_regularization = 1e-7;
  p.force_regularization = 1e-7;
  return p;
}

TEST(TaskSpaceQpController, SingleSupportAnswerSatisfiesKktAndTheConstrainedDynamics) {
  auto model = LoadRobot("amber");
  const ContactSet left = ContactBit(model->ContactIndex("left_foot"));
  const TaskGains gains;
  const Tasks tasks = AmberWalkingTasks(*model, gains);  // Eq. (19): 4 outputs, 4 actuators
  TaskSpaceQpController controller("tsc", model, {left}, tasks, TinyRegularisation());
  ASSERT_EQ(controller.num_task_outputs(), 4);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = AmberSingleSupportPose(*model);
  for (unsigned seed : {1u, 2u, 3u}) {
    const Eigen::VectorXd v = ContactConsistentVelocity(*model, q, left, seed, seed == 1 ? 0.0 : 0.5);
    const Eigen::VectorXd y = TaskValues(*model, tasks, q, v);
    Eigen::Vector4d offset(0.05, -0.02, 0.03, 0.02), yd_d(0.1, -0.1, 0.5, 0.2), ydd_d(0, 0.5, 0, 0);
    const Eigen::VectorXd desired = Stack(y + offset, yd_d, ydd_d);
    const QpAnswer a = SolveAndCheck(controller, *context, q, v, 0, left, desired);
    // Square decoupling (4 outputs, 4 torques): the tasks are met up to the tiny regularisation.
    ExpectPlantAgrees(*model, q, v, left, a, tasks, PdTarget(*model, tasks, q, v, desired, gains), 5e-4);
  }
}

TEST(TaskSpaceQpController, DoubleSupportAnswerSatisfiesKktAndTheConstrainedDynamics) {
  auto model = LoadRobot("amber");
  const ContactSet both = ContactBit(0) | ContactBit(1);
  const TaskGains gains;
  const Tasks tasks = {std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}, gains),
                       std::make_shared<BodyPitchTask>("torso_pitch", *model, "torso", gains)};
  TaskSpaceQpController controller("tsc", model, {both}, tasks, TinyRegularisation());
  auto context = controller.CreateDefaultLeafContext();
  // Feet 0.3 m apart: with both point feet on one spot the pair is a single pivot and COM x, COM z and torso
  // pitch cannot be set independently (the angular momentum about the pivot only changes through gravity).
  const Eigen::VectorXd q = AmberDoubleSupportPose(*model);
  const Eigen::VectorXd v = ContactConsistentVelocity(*model, q, both, 5, 0.3);
  const Eigen::VectorXd y = TaskValues(*model, tasks, q, v);
  const Eigen::VectorXd desired =
      Stack(y + Eigen::Vector3d(0.01, -0.02, 0.05), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const QpAnswer a = SolveAndCheck(controller, *context, q, v, 0, both, desired);
  // 3 outputs, q̈ has 7 − 4 = 3 free directions: met up to the regularisation.
  ExpectPlantAgrees(*model, q, v, both, a, tasks, PdTarget(*model, tasks, q, v, desired, gains), 5e-4);
}

TEST(TaskSpaceQpController, FrictionConeBindsWhenTheTaskAsksForTooMuchShear) {
  auto model = LoadRobot("amber");
  const ContactSet both = ContactBit(0) | ContactBit(1);
  TaskSpaceQpParams params;
  params.friction_coefficient = 0.1;
  const Tasks tasks = {std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                       std::make_shared<BodyPitchTask>("torso_pitch", *model, "torso")};
  TaskSpaceQpController controller("tsc", model, {both}, tasks, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = AmberDoubleSupportPose(*model), v = Eigen::VectorXd::Zero(7);
  const Eigen::VectorXd y = TaskValues(*model, tasks, q, v);
  // ẍ_com = 3 m/s² needs F_x = 3 m, far beyond μ m g ≈ 0.98 m.
  const QpAnswer a = SolveAndCheck(controller, *context, q, v, 0, both,
                                   Stack(y, Eigen::Vector3d::Zero(), Eigen::Vector3d(3.0, 0.0, 0.0)));
  const double Fx = a.F[0] + a.F[2], Fz = a.F[1] + a.F[3];
  EXPECT_NEAR(std::abs(Fx), 0.1 * Fz, 1e-6 * Fz);  // total shear at the cone's edge
  const DenseQpSolver& qp = controller.last_qp(*context);
  EXPECT_GT(qp.y_ineq().cwiseAbs().maxCoeff(), 1e-3);  // a friction row carries a multiplier
  // The COM accelerates as much as friction allows: ẍ = μ F_z / m (F_z = m (g + z̈)).
  MultibodyWorkspace ws(*model);
  Eigen::Matrix3Xd Jcom(3, 7);
  CalcComJacobian(*model, ws, q, Jcom);
  const double xdd = Jcom.row(0) * a.qdd + CalcComJdotQdot(*model, ws, q, v).x();
  EXPECT_NEAR(xdd, Fx / model->total_mass(), 1e-6);
}

// The pyramid's apex raised to F_0 (friction_cone_offset_N): the same shear-hungry task now meets |F_t| ≤ μ (F_z − F_0)
// at each foot, so the total shear is μ (F_z − 2 F_0) and the COM's forward acceleration drops by 2 μ F_0 / m.
TEST(TaskSpaceQpController, FrictionConeOffsetKeepsEachFootInsideTheShiftedPyramid) {
  auto model = LoadRobot("amber");
  const ContactSet both = ContactBit(0) | ContactBit(1);
  TaskSpaceQpParams params;
  params.friction_coefficient = 0.1;
  params.friction_cone_offset_N = 20.0;
  const Tasks tasks = {std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                       std::make_shared<BodyPitchTask>("torso_pitch", *model, "torso")};
  TaskSpaceQpController controller("tsc", model, {both}, tasks, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = AmberDoubleSupportPose(*model), v = Eigen::VectorXd::Zero(7);
  const Eigen::VectorXd y = TaskValues(*model, tasks, q, v);
  const QpAnswer a = SolveAndCheck(controller, *context, q, v, 0, both,
                                   Stack(y, Eigen::Vector3d::Zero(), Eigen::Vector3d(3.0, 0.0, 0.0)));
  for (int foot = 0; foot < 2; ++foot)
    EXPECT_LE(std::abs(a.F[2 * foot]), 0.1 * (a.F[2 * foot + 1] - 20.0) + 1e-9) << "foot " << foot;
  const double Fx = a.F[0] + a.F[2], Fz = a.F[1] + a.F[3];
  EXPECT_NEAR(std::abs(Fx), 0.1 * (Fz - 40.0), 1e-6 * Fz);  // both feet at the shifted edge
  MultibodyWorkspace ws(*model);
  Eigen::Matrix3Xd Jcom(3, 7);
  CalcComJacobian(*model, ws, q, Jcom);
  const double xdd = Jcom.row(0) * a.qdd + CalcComJdotQdot(*model, ws, q, v).x();
  EXPECT_NEAR(xdd, Fx / model->total_mass(), 1e-6);  // Newton: m ẍ = F_x
  params.friction_cone_offset_N = -1.0;
  EXPECT_THROW(TaskSpaceQpController("tsc", model, {both}, tasks, params), std::exception);
}

TEST(TaskSpaceQpController, InfeasibleQpHoldsThePreviousTorqueAndCountsTheFailure) {
  auto model = LoadRobot("amber");
  const ContactSet left = ContactBit(model->ContactIndex("left_foot"));
  for (QpFailurePolicy policy : {QpFailurePolicy::kHoldPrevious, QpFailurePolicy::kZeroTorque}) {
    TaskSpaceQpParams params;
    params.torque_limits = Eigen::VectorXd::Zero(4);               // no torque at all …
    params.min_normal_force_N = 3.0 * model->total_mass() * 9.81;  // … yet the foot must push with 3 m g
    params.failure_policy = policy;
    const Tasks tasks = AmberWalkingTasks(*model);
    TaskSpaceQpController controller("tsc", model, {left}, tasks, params);
    auto context = controller.CreateDefaultLeafContext();
    const Eigen::VectorXd q = AmberSingleSupportPose(*model), v = Eigen::VectorXd::Zero(7);
    Eigen::VectorXd x(14);
    x << q, v;
    context->FixInputPort(controller.GetInputPortIndex("state"), x);
    context->FixAbstractInputPort(controller.GetInputPortIndex("mode"), std::any(0));
    context->FixInputPort(controller.GetInputPortIndex("desired"),
                          Stack(TaskValues(*model, tasks, q, v), Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero()));
    const Eigen::Vector4d u_previous(1.0, -2.0, 3.0, -4.0);
    context->get_mutable_discrete_state().head(4) = u_previous;
    Eigen::VectorXd next = context->discrete_state();
    for (int update = 0; update < 3; ++update)  // three failed updates, each holding the torque of the one before
      ASSERT_TRUE(controller.periodic_events().at(0).update(*context, &next).ok());
    EXPECT_EQ(controller.last_qp(*context).status(), QpStatus::kInfeasible);
    std::printf("  infeasible QP reported as: %s\n", controller.last_qp(*context).status_message().c_str());
    context->get_mutable_discrete_state() = next;
    EXPECT_EQ(controller.EvalOutput(*context, "qp_failures")[0], 3.0);
    EXPECT_EQ(controller.EvalOutput(*context, "qp_status")[0], static_cast<double>(QpStatus::kInfeasible));
    const TaskSpaceQpDiagnostics d = controller.diagnostics(*context);
    EXPECT_EQ(d.qp_failures, 3);
    EXPECT_EQ(d.held, 3);  // no answer was used: every update held (or zeroed) the torque
    EXPECT_EQ(d.solved + d.relaxed, 0);
    const Eigen::VectorXd u = controller.EvalOutput(*context, "u");
    if (policy == QpFailurePolicy::kHoldPrevious)
      EXPECT_EQ((u - u_previous).norm(), 0.0);
    else
      EXPECT_EQ(u.norm(), 0.0);
  }
}

// The typed diagnostics against what the updates physically did. A reachable posture: the first QP solves, and the
// task cost equals ½ Σ w ||J q̈ + J̇ q̇ − ÿ*||² recomputed here from the "qdd" output with the tasks' own Jacobians and
// the PD law of Eq. (30). An unattainable normal-force bound (F_z ≥ 3 m g): the first QP fails, the relaxed answer is
// used, and its planned normal force is indeed below the bound it dropped (so the fallback was needed).
TEST(TaskSpaceQpController, TypedDiagnosticsReportWhatTheUpdatesDid) {
  auto model = LoadRobot("amber");
  const ContactSet left = ContactBit(model->ContactIndex("left_foot"));
  const Tasks tasks = AmberWalkingTasks(*model);
  const Eigen::VectorXd q = AmberSingleSupportPose(*model);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(7);
  v[0] = 0.3;
  Eigen::VectorXd x(14);
  x << q, v;
  // Desired outputs 1 cm / 0.01 rad away from the current ones, at rest: the PD law asks for a real acceleration.
  Eigen::MatrixXd J;
  Eigen::VectorXd Jdq;
  const Eigen::VectorXd y = TaskValues(*model, tasks, q, v, &J, &Jdq);
  const Eigen::VectorXd y_d = y + Eigen::VectorXd::Constant(y.size(), 0.01);
  const Eigen::VectorXd desired = Stack(y_d, Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero());
  const double m_g = model->total_mass() * 9.81;
  for (const double min_normal_force : {0.0, 3.0 * m_g}) {
    TaskSpaceQpParams params;
    params.min_normal_force_N = min_normal_force;
    TaskSpaceQpController controller("tsc", model, {left}, tasks, params);
    auto context = controller.CreateDefaultLeafContext();
    EXPECT_FALSE(controller.diagnostics(*context).qp_status.has_value());  // before the first update
    context->FixInputPort(controller.GetInputPortIndex("state"), x);
    context->FixAbstractInputPort(controller.GetInputPortIndex("mode"), std::any(0));
    context->FixInputPort(controller.GetInputPortIndex("desired"), desired);
    Eigen::VectorXd next = context->discrete_state();
    ASSERT_TRUE(controller.periodic_events().at(0).update(*context, &next).ok());
    context->get_mutable_discrete_state() = next;
    const TaskSpaceQpDiagnostics d = controller.EvalTypedOutput<TaskSpaceQpDiagnostics>(*context, "diagnostics");
    ASSERT_TRUE(d.qp_status.has_value());
    // The task cost from the answer, independently of the controller's own cost assembly.
    const Eigen::VectorXd qdd = controller.EvalOutput(*context, "qdd");
    double cost = 0.0;
    for (size_t i = 0, off = 0; i < tasks.size(); off += tasks[i]->size(), ++i) {
      const TaskGains& g = tasks[i]->gains();
      if (!tasks[i]->IsActiveIn(0)) continue;
      const int n = tasks[i]->size();
      const Eigen::VectorXd ydd_star =
          g.kp * (y_d.segment(off, n) - y.segment(off, n)) - g.kd * (J.middleRows(off, n) * v);
      cost += 0.5 * g.weight * (J.middleRows(off, n) * qdd + Jdq.segment(off, n) - ydd_star).squaredNorm();
    }
    const Eigen::VectorXd F = controller.EvalOutput(*context, "contact_forces");
    const double Fz = F[3 * model->ContactIndex("left_foot") + 2];
    std::printf(
        "  F_min %.0f N: status %s, failures %d, solved %d, relaxed %d, held %d, task cost %.6g (recomputed "
        "%.6g), planned F_z %.1f N\n",
        min_normal_force, std::string(to_string(*d.qp_status)).c_str(), d.qp_failures, d.solved, d.relaxed, d.held,
        d.task_cost, cost, Fz);
    EXPECT_GE(d.task_cost, 0.0);
    EXPECT_NEAR(d.task_cost, cost, 1e-9 * (1.0 + cost));
    EXPECT_GT(d.solve_time_s, 0.0);
    EXPECT_EQ(d.held, 0);
    if (min_normal_force == 0.0) {
      EXPECT_EQ(*d.qp_status, QpStatus::kOptimal);
      EXPECT_EQ(d.qp_failures, 0);
      EXPECT_EQ(d.solved, 1);
      EXPECT_EQ(d.relaxed, 0);
      EXPECT_GE(Fz, 0.0);  // unilateral contact held
    } else {
      EXPECT_EQ(*d.qp_status, QpStatus::kInfeasible);  // the first solve's status, so a relaxed answer is never silent
      EXPECT_EQ(d.qp_failures, 1);
      EXPECT_EQ(d.solved, 0);
      EXPECT_EQ(d.relaxed, 1);
      EXPECT_LT(Fz, min_normal_force);  // the relaxed answer breaks the dropped bound: it was unattainable
    }
  }
}

TEST(TaskSpaceQpController, InfeasibleGrfRowsAreRelaxedKeepingDynamicsAndTorqueLimits) {
  // The default failure policy: F_z >= 3 m g cannot hold (the robot would have to accelerate upwards at 2 g with
  // its torso pitch and COM tasks asking for rest), so the first QP is infeasible; the relaxed QP drops the GRF
  // rows and must then give exactly the answer of a controller that never had them.
  auto model = LoadRobot("amber");
  const ContactSet left = ContactBit(model->ContactIndex("left_foot"));
  const Tasks tasks = AmberWalkingTasks(*model);
  TaskSpaceQpParams strict;
  strict.min_normal_force_N = 3.0 * model->total_mass() * 9.81;
  ASSERT_EQ(strict.failure_policy, QpFailurePolicy::kRelaxContactForces);
  TaskSpaceQpParams free_contact;
  free_contact.friction_coefficient = 1e9;
  free_contact.min_normal_force_N = 0.0;
  TaskSpaceQpController relaxing("tsc", model, {left}, tasks, strict);
  TaskSpaceQpController reference("reference", model, {left}, tasks, free_contact);
  const Eigen::VectorXd q = AmberSingleSupportPose(*model);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(7);
  v[0] = 0.3;  // a forward base velocity: the answer is not trivially static
  Eigen::VectorXd x(14);
  x << q, v;
  const Eigen::VectorXd desired =
      Stack(TaskValues(*model, tasks, q, v), Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero());
  Eigen::VectorXd u[2];
  int k = 0;
  for (const TaskSpaceQpController* controller : {&relaxing, &reference}) {
    auto context = controller->CreateDefaultLeafContext();
    context->FixInputPort(controller->GetInputPortIndex("state"), x);
    context->FixAbstractInputPort(controller->GetInputPortIndex("mode"), std::any(0));
    context->FixInputPort(controller->GetInputPortIndex("desired"), desired);
    Eigen::VectorXd next = context->discrete_state();
    ASSERT_TRUE(controller->periodic_events().at(0).update(*context, &next).ok());
    context->get_mutable_discrete_state() = next;
    u[k] = controller->EvalOutput(*context, "u");
    const double failures = controller->EvalOutput(*context, "qp_failures")[0];
    const double status = controller->EvalOutput(*context, "qp_status")[0];
    if (controller == &relaxing) {
      EXPECT_EQ(failures, 1.0);  // the relaxed answer is used, and still counted and reported
      EXPECT_EQ(status, static_cast<double>(QpStatus::kInfeasible));
      EXPECT_EQ(controller->diagnostics(*context).relaxed, 1);
      // The relaxed QP kept the dynamics and torque limits: KKT of the QP it solved.
      const DenseQpSolver& qp = controller->last_qp(*context);
      EXPECT_LT((qp.A_eq * qp.x() - qp.b_eq).cwiseAbs().maxCoeff(), 1e-8);
      EXPECT_LE(u[k].cwiseAbs().maxCoeff(), model->torque_limits().maxCoeff() + 1e-9);
      // Its GRF rows were restored for the next update.
      EXPECT_EQ(qp.lb[7 + 4 + 1], strict.min_normal_force_N);
    } else {
      EXPECT_EQ(failures, 0.0);
    }
    ++k;
  }
  std::printf("  relaxed u = [%g %g %g %g], reference u = [%g %g %g %g]\n", u[0][0], u[0][1], u[0][2], u[0][3], u[1][0],
              u[1][1], u[1][2], u[1][3]);
  EXPECT_LT((u[0] - u[1]).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + u[1].cwiseAbs().maxCoeff()));
}

TEST(TaskSpaceQpController, BadInputsAndParametersAreNamed) {
  auto model = LoadRobot("amber");
  const ContactSet left = ContactBit(0);
  TaskSpaceQpController controller("tsc", model, {left}, AmberWalkingTasks(*model));
  EXPECT_EQ(controller.input_port(controller.GetInputPortIndex("desired")).size, 12);
  auto context = controller.CreateDefaultLeafContext();
  context->FixInputPort(0, Stack(model->q_nominal(), Eigen::VectorXd::Zero(7), Eigen::VectorXd(0)));
  context->FixAbstractInputPort(1, std::any(3));
  context->FixInputPort(2, Eigen::VectorXd::Zero(12));
  Eigen::VectorXd next = context->discrete_state();
  const EventStatus status = controller.periodic_events().at(0).update(*context, &next);
  EXPECT_EQ(status.kind, EventStatus::Kind::kFailed);
  EXPECT_NE(status.message.find("'mode'"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("'tsc'"), std::string::npos) << status.message;

  TaskSpaceQpParams params;
  params.torque_limits = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(TaskSpaceQpController("tsc", model, {left}, AmberWalkingTasks(*model), params), std::runtime_error);
  params = {};
  params.zero_torque_in_contact = {{"left_foot", "left_ankle"}};
  try {
    TaskSpaceQpController("tsc", model, {left}, AmberWalkingTasks(*model), params);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'left_ankle'"), std::string::npos) << e.what();
  }
  // A task active in a mode that does not exist.
  Tasks bad = {
      std::make_shared<ComPositionTask>("com_z", std::vector<Axis>{Axis::kZ}, TaskGains{}, std::vector<int>{4})};
  EXPECT_THROW(TaskSpaceQpController("tsc", model, {left}, bad), std::runtime_error);
}

TEST(TaskSpaceQpController, ZeroTorqueJointOptionPinsTheActuatorInContact) {
  auto model = LoadRobot("amber");
  const ContactSet left = ContactBit(0);
  TaskSpaceQpParams params;
  params.zero_torque_in_contact = {{"left_foot", "left_knee"}};  // stands in for a stance-ankle actuator
  const Tasks tasks = AmberWalkingTasks(*model);
  TaskSpaceQpController controller("tsc", model, {left, ContactSet{0}}, tasks, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = AmberSingleSupportPose(*model), v = Eigen::VectorXd::Zero(7);
  const Eigen::VectorXd desired = Stack(TaskValues(*model, tasks, q, v) + Eigen::Vector4d(0.05, 0.0, 0.0, 0.0),
                                        Eigen::Vector4d::Zero(), Eigen::Vector4d::Zero());
  const QpAnswer a = SolveAndCheck(controller, *context, q, v, 0, left, desired);
  EXPECT_NEAR(a.u[model->VelocityIndex("left_knee") - 3], 0.0, 1e-12);
  // In flight (mode 1, no contact) the knee is free again.
  Eigen::VectorXd x(14);
  x << q, v;
  context->FixAbstractInputPort(1, std::any(1));
  ASSERT_EQ(controller.SolveQp(*context), QpStatus::kOptimal);
  EXPECT_GT(std::abs(controller.last_qp(*context).x()[7 + 1]), 1e-3);
}

}  // namespace
}  // namespace rome
