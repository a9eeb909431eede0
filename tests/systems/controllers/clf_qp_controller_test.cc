// ClfQpController: the CLF condition against closed forms and an independent forward-dynamics path, the two
// formulations against each other and against the plant's constraint forces, the force band at F_ref = 0, each
// fallback on a problem built to need it, and the flat-foot CoP rows on the exoskeleton under a lateral push.
//
// Independent references:
//  * for one relative-degree-2 output with Q = I the CARE has the closed form P = [[√3, 1], [1, √3]] (hopping spec
//  A4.2),
//    so γ = 1/λ_max(P) = 1/(√3 + 1) and P_ε = diag(1/ε, 1) P diag(1/ε, 1);
//  * q̈ from Bullet's articulated-body forward dynamics (CalcForwardDynamics), not the controller's M⁻¹ path;
//  * contact forces from the plant's constrained dynamics (CalcConstrainedForwardDynamics).
#include "systems/controllers/clf_qp_controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "tests/systems/controllers/amber_test_setup.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> LoadTestModel(const std::string& name) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("tests/systems/controllers/data/" + name + ".rome.json"), {.euler_floating_base = true}));
}

Eigen::VectorXd Stack(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  Eigen::VectorXd s(a.size() + b.size());
  s << a, b;
  return s;
}

struct Solved {
  Eigen::VectorXd u;
  double delta = 0, V = 0;
  QpStatus status = QpStatus::kInvalidInput;
  Eigen::VectorXd fallbacks;
  double failures = 0;
};

Solved RunUpdate(const ClfQpController& controller, LeafContext& context, const Eigen::VectorXd& x, int mode,
                 const Eigen::VectorXd& desired) {
  context.FixInputPort(0, x);
  context.FixAbstractInputPort(1, std::any(mode));
  context.FixInputPort(2, desired);
  Eigen::VectorXd next = context.discrete_state();
  const EventStatus es = controller.periodic_events().at(0).update(context, &next);
  EXPECT_TRUE(es.ok()) << es.message;
  context.get_mutable_discrete_state() = next;
  const ClfQpDiagnostics d = controller.diagnostics(context);
  EXPECT_TRUE(d.qp_status.has_value());
  Solved r;
  r.u = controller.EvalOutput(context, "u");
  r.delta = d.delta;
  r.V = d.V;
  r.status = d.qp_status.value_or(QpStatus::kInvalidInput);
  r.fallbacks = Eigen::Vector4d(d.drift_dropped, d.band_dropped, d.cop_dropped, d.held);
  r.failures = d.qp_failures;
  return r;
}

// P_ε of n decoupled relative-degree-2 outputs, η = [y; ẏ], from the closed-form CARE solution.
Eigen::MatrixXd ClosedFormPEpsilon(int n, double eps) {
  Eigen::MatrixXd P(2 * n, 2 * n);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  P << std::sqrt(3.0) / (eps * eps) * I, 1.0 / eps * I, 1.0 / eps * I, std::sqrt(3.0) * I;
  return P;
}

TEST(ClfQpController, DoubleIntegratorMeetsTheClfConditionWheneverDeltaIsZero) {
  auto model = LoadTestModel("slider");
  ClfQpParams params;
  params.epsilon = 0.2;
  ClfQpController controller("clf", model, {0},
                             {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("x", *model, "slide"))},
                             params);
  const double gamma = 1.0 / (std::sqrt(3.0) + 1.0), rate = gamma / params.epsilon;
  EXPECT_NEAR(controller.convergence_rate(0), rate, 1e-9);
  EXPECT_LT((controller.P_epsilon(0) - ClosedFormPEpsilon(1, params.epsilon)).cwiseAbs().maxCoeff(), 1e-8);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::MatrixXd P = ClosedFormPEpsilon(1, params.epsilon);
  int unrelaxed = 0, relaxed = 0;
  for (double q : {-0.5, -0.1, 0.0, 0.05, 0.3, 2.0})
    for (double v : {-1.0, -0.2, 0.0, 0.4, 3.0}) {
      const Solved s = RunUpdate(controller, *context, Eigen::Vector2d(q, v), 0, Eigen::VectorXd::Zero(3));
      ASSERT_EQ(s.status, QpStatus::kOptimal);
      const double qdd = s.u[0] / 2.0;  // m = 2 kg: q̈ = u / m, closed form
      const Eigen::Vector2d eta(q, v), eta_dot(v, qdd);
      const double V = eta.dot(P * eta), Vdot = 2.0 * eta.dot(P * eta_dot);
      EXPECT_NEAR(s.V, V, 1e-9 * (1.0 + V));
      // δ is exactly 0 where the CLF row is inactive, O(1/p) where it binds against the output cost, and large only
      // where the 20 N limit makes the condition unreachable.
      if (s.delta == 0.0) {
        ++unrelaxed;
        EXPECT_LE(Vdot, -rate * V + 1e-9 * (1.0 + V)) << "q = " << q << ", v = " << v << ", u = " << s.u[0];
      } else if (s.delta < 1e-4) {
        EXPECT_LE(Vdot, -rate * V + 1e-4 * (1.0 + V)) << "q = " << q << ", v = " << v << ", u = " << s.u[0];
      } else {
        ++relaxed;
        EXPECT_NEAR(std::abs(s.u[0]), 20.0, 1e-9)
            << "a large δ only where the 20 N limit binds; q = " << q << ", v = " << v;
      }
    }
  EXPECT_GE(unrelaxed, 3);
  EXPECT_GE(relaxed, 3);
}

// The clf_activity port counts an update as active exactly when the CLF row binds. On the double integrator with the
// cost on ÿ_d = 0 the cost alone picks u = 0, so the row binds iff u = 0 would break it: V̇(u = 0) = 2 ηᵀ P_ε [ẏ; 0] >
// −(γ/ε) V, from the closed-form P_ε (not the controller's), on states that are clearly on one side.
TEST(ClfQpController, ClfActivityCountsTheUpdatesWhereTheClfRowBinds) {
  auto model = LoadTestModel("slider");
  ClfQpParams params;
  params.epsilon = 0.2;
  ClfQpController controller("clf", model, {0},
                             {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("x", *model, "slide"))},
                             params);
  const double rate = 1.0 / (std::sqrt(3.0) + 1.0) / params.epsilon;
  const Eigen::MatrixXd P = ClosedFormPEpsilon(1, params.epsilon);
  auto context = controller.CreateDefaultLeafContext();
  int active = 0, slack = 0;
  for (double q : {-0.5, -0.1, 0.0, 0.05, 0.3})
    for (double v : {-1.0, -0.2, 0.0, 0.4, 3.0}) {
      const Eigen::Vector2d eta(q, v);
      const double V = eta.dot(P * eta), Vdot0 = 2.0 * eta.dot(P * Eigen::Vector2d(v, 0.0));
      const ClfQpDiagnostics before = controller.diagnostics(*context);
      const Solved s = RunUpdate(controller, *context, eta, 0, Eigen::VectorXd::Zero(3));
      ASSERT_EQ(s.status, QpStatus::kOptimal);
      const ClfQpDiagnostics after = controller.EvalTypedOutput<ClfQpDiagnostics>(*context, "diagnostics");
      const Eigen::Vector2d counted(after.clf_active - before.clf_active, after.solved - before.solved);
      EXPECT_EQ(counted,
                controller.EvalOutput(*context, "clf_activity") - Eigen::Vector2d(before.clf_active, before.solved));
      EXPECT_EQ(counted[1], 1.0);  // one solved update
      if (V == 0.0) {
        EXPECT_EQ(counted[0], 0.0) << "η = 0: the row 0 ≤ δ is not counted";
      } else if (Vdot0 + rate * V > 1e-6 * (1.0 + V)) {
        ++active;
        EXPECT_EQ(counted[0], 1.0) << "q = " << q << ", v = " << v
                                   << ": u = 0 breaks the CLF condition, the row must bind";
        EXPECT_GT(std::abs(s.u[0]), 1e-6);
      } else if (Vdot0 + rate * V < -1e-6 * (1.0 + V)) {
        ++slack;
        EXPECT_EQ(counted[0], 0.0) << "q = " << q << ", v = " << v << ": u = 0 meets the CLF condition strictly";
        EXPECT_NEAR(s.u[0], 0.0, 1e-9);
      }
    }
  EXPECT_GE(active, 5);
  EXPECT_GE(slack, 3);
  auto fresh = controller.CreateDefaultLeafContext();
  EXPECT_EQ(controller.EvalOutput(*fresh, "clf_activity"), Eigen::Vector2d::Zero());
  EXPECT_FALSE(controller.diagnostics(*fresh).qp_status.has_value()) << "no QP solved in a fresh context";
}

TEST(ClfQpController, TwoLinkArmMeetsTheClfConditionAgainstIndependentDynamics) {
  auto model = LoadTestModel("arm");
  ClfQpParams params;
  params.epsilon = 0.1;
  ClfQpController controller(
      "clf", model, {0},
      {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("shoulder", *model, "shoulder")),
       ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("elbow", *model, "elbow"))},
      params);
  auto context = controller.CreateDefaultLeafContext();
  MultibodyWorkspace ws(*model);
  const Eigen::MatrixXd P = ClosedFormPEpsilon(2, params.epsilon);
  const double rate = 1.0 / (std::sqrt(3.0) + 1.0) / params.epsilon;
  int checked = 0;
  for (int k = 0; k < 12; ++k) {
    Eigen::VectorXd q(2), v(2);
    q << 0.3 + 0.05 * k, -0.2 + 0.04 * k;
    v << 0.3 - 0.07 * k, 0.1 * std::sin(k);
    Eigen::VectorXd desired = Eigen::VectorXd::Zero(6);
    desired[0] = 0.35;  // y_d = (0.35, 0); ẏ_d = ÿ_d = 0
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    Eigen::VectorXd qdd(2);
    CalcForwardDynamics(*model, ws, q, v, s.u, Eigen::VectorXd(0), qdd);  // Bullet ABA
    Eigen::VectorXd eta(4), eta_dot(4);
    for (int i = 0; i < 2; ++i) {  // η = [y − y_d; ẏ], η̇ = [ẏ; ÿ] with y = q
      eta[i] = q[i] - desired[i];
      eta[2 + i] = v[i];
      eta_dot[i] = v[i];
      eta_dot[2 + i] = qdd[i];
    }
    const double V = eta.dot(P * eta), Vdot = 2.0 * eta.dot(P * eta_dot);
    if (s.delta < 1e-4) {  // δ = 0, or O(1/p) where the CLF row binds against the output cost
      ++checked;
      EXPECT_LE(Vdot, -rate * V + 1e-4 * (1.0 + V)) << "sample " << k << ", delta " << s.delta;
    }
  }
  EXPECT_GE(checked, 8);
}

// A cost-only output (params.cost_only_outputs) leaves the RES-CLF: P_ε is the closed form of the one CLF output, the
// CLF condition holds on the shoulder's V alone, and, since the CLF row does not see the elbow's row of the output
// dynamics, the elbow's acceleration (Bullet's ABA, not the controller's path) is its PD target wherever no torque
// limit binds: q̈_e = ÿ_d − Kp (q_e − y_d) − Kd (q̇_e − ẏ_d).
TEST(ClfQpController, CostOnlyOutputTracksItsPdTargetOutsideTheClf) {
  auto model = LoadTestModel("arm");
  ClfQpParams params;
  params.epsilon = 0.1;
  params.cost_only_outputs = {"elbow"};
  params.u_regularization = 0.0;  // the QP's optimum is then exactly the PD target
  const TaskGains elbow_gains{1.0, 144.0, 24.0};
  ClfQpController controller(
      "clf", model, {0},
      {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("shoulder", *model, "shoulder")),
       ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("elbow", *model, "elbow", elbow_gains))},
      params);
  EXPECT_LT((controller.P_epsilon(0) - ClosedFormPEpsilon(1, params.epsilon)).cwiseAbs().maxCoeff(), 1e-8);
  auto context = controller.CreateDefaultLeafContext();
  MultibodyWorkspace ws(*model);
  const Eigen::MatrixXd P = ClosedFormPEpsilon(1, params.epsilon);
  const double rate = 1.0 / (std::sqrt(3.0) + 1.0) / params.epsilon;
  int pd_checked = 0, clf_checked = 0;
  for (int k = 0; k < 12; ++k) {
    Eigen::VectorXd q(2), v(2);
    q << 0.3 + 0.05 * k, -0.2 + 0.04 * k;
    v << 0.3 - 0.07 * k, 0.1 * std::sin(k);
    Eigen::VectorXd desired = Eigen::VectorXd::Zero(6);
    desired << 0.35, 0.1, 0.2, -0.3, 0.5, 1.5;  // y_d, ẏ_d, ÿ_d of (shoulder, elbow)
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    Eigen::VectorXd qdd(2);
    CalcForwardDynamics(*model, ws, q, v, s.u, Eigen::VectorXd(0), qdd);
    const Eigen::Vector2d eta(q[0] - desired[0], v[0] - desired[2]), eta_dot(v[0] - desired[2], qdd[0] - desired[4]);
    const double V = eta.dot(P * eta), Vdot = 2.0 * eta.dot(P * eta_dot);
    EXPECT_NEAR(s.V, V, 1e-9 * (1.0 + V)) << "V is the shoulder's alone, sample " << k;
    if (s.delta < 1e-4) {
      ++clf_checked;
      EXPECT_LE(Vdot, -rate * V + 1e-4 * (1.0 + V)) << "sample " << k;
    }
    if (std::abs(s.u[0]) < 60.0 - 1e-6 && std::abs(s.u[1]) < 40.0 - 1e-6) {
      ++pd_checked;
      const double target = desired[5] - elbow_gains.kp * (q[1] - desired[1]) - elbow_gains.kd * (v[1] - desired[3]);
      EXPECT_NEAR(qdd[1], target, 1e-6 * (1.0 + std::abs(target))) << "sample " << k;
    }
  }
  EXPECT_GE(clf_checked, 8);
  EXPECT_GE(pd_checked, 8);
  try {
    ClfQpParams bad;
    bad.cost_only_outputs = {"wrist"};
    ClfQpController("clf", model, {0},
                    {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("elbow", *model, "elbow"))}, bad);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "system 'clf': params.cost_only_outputs names 'wrist', which is not an output of this controller");
  }
}

// params.cost_pd_feedback: where the CLF row is slack (V̇ strictly below −(γ/ε) V, from Bullet's ABA), the QP's optimum
// is the unconstrained one, every output at its PD target: q̈ = ÿ_d − Kp (q − y_d) − Kd (q̇ − ẏ_d); where it binds the
// CLF condition holds.
TEST(ClfQpController, CostPdFeedbackTracksThePdTargetsWhereTheClfRowIsSlack) {
  auto model = LoadTestModel("arm");
  ClfQpParams params;
  params.epsilon = 1.0;
  params.cost_pd_feedback = true;
  params.u_regularization = 0.0;
  const TaskGains gains{1.0, 100.0, 20.0};
  ClfQpController controller(
      "clf", model, {0},
      {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("shoulder", *model, "shoulder", gains)),
       ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("elbow", *model, "elbow", gains))},
      params);
  auto context = controller.CreateDefaultLeafContext();
  MultibodyWorkspace ws(*model);
  const Eigen::MatrixXd P = ClosedFormPEpsilon(2, params.epsilon);
  const double rate = 1.0 / (std::sqrt(3.0) + 1.0) / params.epsilon;
  int slack = 0, binding = 0;
  for (int k = 0; k < 16; ++k) {
    Eigen::VectorXd q(2), v(2);
    q << 0.3 + 0.02 * k, -0.2 + 0.03 * k;
    v << 0.3 * std::cos(k), 0.2 * std::sin(2 * k);
    Eigen::VectorXd desired = Eigen::VectorXd::Zero(6);
    desired << 0.35, 0.0, 0.0, 0.0, 0.0, 0.0;
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    Eigen::VectorXd qdd(2);
    CalcForwardDynamics(*model, ws, q, v, s.u, Eigen::VectorXd(0), qdd);
    Eigen::VectorXd eta(4), eta_dot(4);
    eta << q - desired.head(2), v;
    eta_dot << v, qdd;
    const double V = eta.dot(P * eta), Vdot = 2.0 * eta.dot(P * eta_dot);
    if (Vdot < -rate * V - 1e-6 * (1.0 + V)) {
      ++slack;
      for (int i = 0; i < 2; ++i) {
        const double target = -gains.kp * (q[i] - desired[i]) - gains.kd * v[i];
        EXPECT_NEAR(qdd[i], target, 1e-6 * (1.0 + std::abs(target))) << "sample " << k << ", joint " << i;
      }
    } else {
      ++binding;
      if (s.delta < 1e-4) {  // else a torque limit binds
        EXPECT_LE(Vdot, -rate * V + 1e-4 * (1.0 + V)) << "sample " << k;
      }
    }
  }
  std::printf("  cost PD: %d samples with the CLF row slack, %d binding\n", slack, binding);
  EXPECT_GE(slack, 4);
}

// params.predict_hold_drift: AMBER in single support, updated at t = 0 and one period later at the state the plant
// reaches under the held torque (constrained dynamics, semi-implicit Euler in 10 substeps). The drift d is computed
// here from the plant's own constrained-dynamics forces, F(x1, u0) − F(x0, u0), not from the controller; the second
// update's planned force plus d must satisfy the friction pyramid and the normal-force floor.
TEST(ClfQpController, HoldDriftRowsKeepThePredictedForceInsideThePyramid) {
  auto model = test::LoadRobot("amber");
  const Eigen::VectorXd q0 = test::AmberSingleSupportPose(*model);
  MultibodyWorkspace ws(*model);
  const ContactSet left = ContactBit(model->ContactIndex("left_foot"));
  Eigen::VectorXd v0 = Eigen::VectorXd::Zero(model->nv());
  v0[0] = 0.8, v0[1] = -0.3, v0[3] = 2.0, v0[5] = -3.0;
  const int rows = CalcConstraintJacobian(*model, ws, q0, v0, left);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  v0 -= J.completeOrthogonalDecomposition().solve(J * v0);
  const auto tasks = test::AmberWalkingTasks(*model);
  std::vector<ClfOutput> outputs;
  for (const auto& t : tasks) outputs.push_back(ClfOutput::RelativeDegreeTwo(t));
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(12);
  desired.head(4) = test::TaskValues(*model, tasks, q0, v0) + Eigen::Vector4d(0.1, -0.05, 0.08, 0.06);
  ClfQpParams params;
  params.predict_hold_drift = true;
  params.contact.friction_margin = 0.95;
  params.contact.min_normal_force_N = 2.0;
  params.contact.friction_cone_offset_N = 1.5;
  ClfQpController controller("clf", model, {left}, outputs, params);
  auto context = controller.CreateDefaultLeafContext();
  const Solved s0 = RunUpdate(controller, *context, Stack(q0, v0), 0, desired);
  ASSERT_EQ(s0.status, QpStatus::kOptimal);
  // One held period of the plant.
  const double T = params.update_period_s;
  Eigen::VectorXd q = q0, v = v0, qdd(model->nv()), F0(model->max_constraint_rows()), F1(model->max_constraint_rows());
  CalcConstrainedForwardDynamics(*model, ws, q0, v0, s0.u, left, ConstrainedDynamicsParameters{}, qdd, F0);
  for (int i = 0; i < 10; ++i) {
    CalcConstrainedForwardDynamics(*model, ws, q, v, s0.u, left, ConstrainedDynamicsParameters{}, qdd, F1);
    v += 0.1 * T * qdd;
    q += 0.1 * T * v;
  }
  CalcConstrainedForwardDynamics(*model, ws, q, v, s0.u, left, ConstrainedDynamicsParameters{}, qdd, F1);
  const Eigen::VectorXd d = F1.head(rows) - F0.head(rows);
  context->SetTime(T);
  const Solved s1 = RunUpdate(controller, *context, Stack(q, v), 0, desired);
  ASSERT_EQ(s1.status, QpStatus::kOptimal);
  const Eigen::VectorXd predicted = controller.last_constraint_forces(*context) + d;
  const double mu = 0.95 * model->contacts()[model->ContactIndex("left_foot")].friction_coefficient;
  // Planar point contact: rows (F_x, F_z).
  ASSERT_EQ(rows, 2);
  std::printf("  hold drift d = (%.3f, %.3f) N, planned (%.3f, %.3f) N, predicted |F_x| %.3f <= %.3f\n", d[0], d[1],
              controller.last_constraint_forces(*context)[0], controller.last_constraint_forces(*context)[1],
              std::abs(predicted[0]), mu * (predicted[1] - 1.5));
  EXPECT_GT(d.norm(), 1e-3) << "the state moved over the hold, so the plant's force drifts";
  EXPECT_GE(predicted[1], 2.0 - 1e-6);
  EXPECT_LE(std::abs(predicted[0]), mu * (predicted[1] - 1.5) + 1e-6);
}

// AMBER in single support, the paper's four outputs away from their targets: both formulations give the same torques,
// and their planned forces are the plant's constrained-dynamics forces for those torques.
TEST(ClfQpController, FormulationsAgreeAndMatchThePlantsForces) {
  auto model = test::LoadRobot("amber");
  const Eigen::VectorXd q = test::AmberSingleSupportPose(*model);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model->nv());
  v[0] = 0.4;  // a base velocity consistent with the welded stance foot: project below
  MultibodyWorkspace ws(*model);
  const ContactSet left = ContactBit(model->ContactIndex("left_foot"));
  const int rows = CalcConstraintJacobian(*model, ws, q, v, left);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  v -= J.completeOrthogonalDecomposition().solve(J * v);
  const auto tasks = test::AmberWalkingTasks(*model);
  std::vector<ClfOutput> outputs;
  for (const auto& t : tasks) outputs.push_back(ClfOutput::RelativeDegreeTwo(t));
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(12);
  desired.head(4) = test::TaskValues(*model, tasks, q, v) + Eigen::Vector4d(0.03, -0.01, 0.02, 0.03);
  Eigen::VectorXd u[2];
  for (int f = 0; f < 2; ++f) {
    ClfQpParams params;
    params.formulation = f == 0 ? ClfQpFormulation::kEliminateContactForces : ClfQpFormulation::kAugmentedInput;
    ClfQpController controller("clf", model, {left}, outputs, params);
    auto context = controller.CreateDefaultLeafContext();
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    const QpKktResiduals kkt = ComputeQpKktResiduals(controller.last_qp(*context));
    EXPECT_LT(kkt.Max(), 1e-7) << "formulation " << f;
    u[f] = s.u;
    // The plant, given these torques, applies the planned forces.
    Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
    CalcConstrainedForwardDynamics(*model, ws, q, v, s.u, left, ConstrainedDynamicsParameters{}, qdd, F);
    EXPECT_LT((F.head(rows) - controller.last_constraint_forces(*context)).cwiseAbs().maxCoeff(), 1e-6)
        << "formulation " << f;
    std::printf("  formulation %d: u = [%.6f %.6f %.6f %.6f], delta %.3g, V %.4g\n", f, s.u[0], s.u[1], s.u[2], s.u[3],
                s.delta, s.V);
  }
  EXPECT_LT((u[0] - u[1]).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + u[0].cwiseAbs().maxCoeff()));
}

// The force-band tests' setup: AMBER at rest in its double-support pose with the torso pitch and the COM (x, z) as
// outputs, held at their current values; and the plant's own normal force on a contact at the QP's torques.
struct AmberBandSetup {
  std::shared_ptr<const MultibodyModel> model = test::LoadRobot("amber");
  Eigen::VectorXd q = test::AmberDoubleSupportPose(*model), v = Eigen::VectorXd::Zero(model->nv());
  int l = model->ContactIndex("left_foot"), r = model->ContactIndex("right_foot");
  double mg = model->total_mass() * 9.81;
  std::vector<ClfOutput> outputs = {
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyPitchTask>("torso_pitch", *model, "torso")),
      ClfOutput::RelativeDegreeTwo(std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}))};
  Eigen::VectorXd Desired() const {
    Eigen::VectorXd desired = Eigen::VectorXd::Zero(9);
    desired.head(3) = test::TaskValues(*model,
                                       {std::make_shared<BodyPitchTask>("p", *model, "torso"),
                                        std::make_shared<ComPositionTask>("c", std::vector<Axis>{Axis::kX, Axis::kZ})},
                                       q, v);
    return desired;
  }
  /// The force [N] of `contact` at pose q_at, at rest, from CalcConstrainedForwardDynamics with `active` at torques u.
  Eigen::Vector3d PlantForce(const Eigen::VectorXd& q_at, const Eigen::VectorXd& u, ContactSet active,
                             int contact) const {
    MultibodyWorkspace ws(*model);
    Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
    CalcConstrainedForwardDynamics(*model, ws, q_at, v, u, active, ConstrainedDynamicsParameters{}, qdd, F);
    return ExtractContactWrench(*model, ws, q_at, active, F, contact).force;
  }
  /// F_z [N] of `contact` at the setup's pose.
  double PlantNormalForce(const Eigen::VectorXd& u, ContactSet active, int contact) const {
    return PlantForce(q, u, active, contact).z();
  }
  /// One update of `controller` at time t and pose q_at, at rest, with f_left planned on the left foot and the rest of
  /// m g on the right (the force band's input, port 3).
  Solved UpdateAt(const ClfQpController& controller, LeafContext& context, double t, const Eigen::VectorXd& q_at,
                  double f_left) const {
    context.SetTime(t);
    Eigen::VectorXd f_ref = Eigen::VectorXd::Zero(2);
    f_ref[l] = f_left;
    f_ref[r] = mg - f_left;
    context.FixInputPort(3, f_ref);
    return RunUpdate(controller, context, Stack(q_at, v), 0, Desired());
  }
};

// With a reference of 0 N on the left foot in double support, the band (1 ± c) · 0 makes the left normal force 0.
TEST(ClfQpController, ForceBandHoldsAtZeroReference) {
  const AmberBandSetup a;
  const ContactSet both = ContactBit(a.l) | ContactBit(a.r);
  for (int f = 0; f < 2; ++f) {
    ClfQpParams params;
    params.formulation = f == 0 ? ClfQpFormulation::kEliminateContactForces : ClfQpFormulation::kAugmentedInput;
    params.force_band = true;
    ClfQpController controller("clf", a.model, {both}, a.outputs, params);
    auto context = controller.CreateDefaultLeafContext();
    Eigen::VectorXd f_ref = Eigen::VectorXd::Zero(2);
    f_ref[a.r] = a.mg;
    context->FixInputPort(3, f_ref);
    const Solved s = RunUpdate(controller, *context, Stack(a.q, a.v), 0, a.Desired());
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    EXPECT_EQ(s.fallbacks.sum(), 0.0);
    const double fz_left = a.PlantNormalForce(s.u, both, a.l), fz_right = a.PlantNormalForce(s.u, both, a.r);
    std::printf("  formulation %d: plant F_z left %.3g N, right %.4g N\n", f, fz_left, fz_right);
    EXPECT_NEAR(fz_left, 0.0, 1e-6);
    EXPECT_NEAR(fz_right, a.mg, 0.1 * a.mg + 1e-6);
  }
}

// force_band_loading_floor_N (20 N): the left foot's reference is 0 N in double support. At the first update (the
// contact was not in the mode before: loading) the plant's own constrained dynamics at the QP's torques give the left
// foot at least 20 N, also while the zero reference wobbles by solver noise; after an update at 50 N the reference
// falls to 0 (unloading) and the band (1 ± c) · 0 holds it at 0 N, as without a floor. Both on the plant's forces, not
// the QP's.
TEST(ClfQpController, ForceBandLoadingFloorHoldsALoadingFootAboveIt) {
  const AmberBandSetup a;
  const ContactSet both = ContactBit(a.l) | ContactBit(a.r);
  const double floor = 20.0;
  ClfQpParams params;
  params.force_band = true;
  params.force_band_loading_floor_N = floor;
  ClfQpController controller("clf", a.model, {both}, a.outputs, params);
  auto context = controller.CreateDefaultLeafContext();
  auto plant_left_fz = [&](const Eigen::VectorXd& u) { return a.PlantNormalForce(u, both, a.l); };
  auto update = [&](double t, double f_left) { return a.UpdateAt(controller, *context, t, a.q, f_left); };
  const Solved loading = update(0.0, 0.0);
  ASSERT_EQ(loading.status, QpStatus::kOptimal);
  const double f_loading = plant_left_fz(loading.u);
  // Solver noise on a zero reference (1e-5 N, then 3e-6 N: a fall of 7e-6 N, below force_band_loading_fall_tolerance_N)
  // does not end the loading (the walking plans' F⁺ = 0 at touchdown carry such noise).
  ASSERT_EQ(update(1e-3, 1e-5).status, QpStatus::kOptimal);
  const Solved noisy = update(2e-3, 3e-6);
  ASSERT_EQ(noisy.status, QpStatus::kOptimal);
  const double f_noisy = plant_left_fz(noisy.u);
  ASSERT_EQ(update(3e-3, 50.0).status, QpStatus::kOptimal);
  const Solved unloading = update(4e-3, 0.0);
  ASSERT_EQ(unloading.status, QpStatus::kOptimal);
  const double f_unloading = plant_left_fz(unloading.u);
  std::printf("  plant F_z left: loading %.4g N (floor %.0f N), noisy zero reference %.4g N, unloading %.3g N\n",
              f_loading, floor, f_noisy, f_unloading);
  EXPECT_GE(f_loading, floor - 1e-6);
  EXPECT_GE(f_noisy, floor - 1e-6);
  EXPECT_LE(f_loading, floor + 1e-6);  // the band's upper edge is raised to the floor, no further
  EXPECT_NEAR(f_unloading, 0.0, 1e-6);
  EXPECT_EQ(loading.fallbacks.sum() + unloading.fallbacks.sum(), 0.0);
  // One update later the foot is still in the mode with its reference still 0 (a plant that has not released it): it
  // stays unloading. Before, the reference no longer falling made it loading again, and the floor held a walking foot
  // above the plant's release force for good (docs/design-notes.md#walking-late-release).
  const Solved late = update(5e-3, 0.0);
  ASSERT_EQ(late.status, QpStatus::kOptimal);
  std::printf("  a released foot still in contact: plant F_z left %.3g N\n", plant_left_fz(late.u));
  EXPECT_NEAR(plant_left_fz(late.u), 0.0, 1e-6);
  EXPECT_EQ(late.fallbacks.sum(), 0.0);
}

// predict_hold_drift with the force band: a foot whose reference falls to 0 (the plan lifts it off) gets no hold-drift
// rows. AMBER at rest in double support, updated at t = 0 with 50 N planned on the left foot, then one period later at
// a pose whose feet are 0.26 m apart instead of 0.3 m, with the left reference 0. The drift d = F(x1, u0) − F(x0, u0)
// is computed here from the plant's own constrained dynamics. The band at the hold's end asks F_z(u) + d_z = 0;
// hold-drift rows on that foot would also ask the whole force F(u) + d = 0, that is F(u) = −d, which the friction rows
// at the solve instant refuse when −d is outside the pyramid (checked here): the update would need a fallback. Without
// those rows it solves at once, and the plant's left force at the end of the hold, F_z(x1, u1) + d_z, is 0.
TEST(ClfQpController, HoldDriftRowsSkipAFootTheBandReleases) {
  const AmberBandSetup a;
  const ContactSet both = ContactBit(a.l) | ContactBit(a.r);
  ClfQpParams params;
  params.force_band = true;
  params.force_band_at_hold_end = true;
  params.predict_hold_drift = true;
  params.contact.friction_coefficient = 0.5;  // the pyramid μ' (planar: not inscribed)
  ClfQpController controller("clf", a.model, {both}, a.outputs, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q0 = a.q, q1 = test::AmberDoubleSupportPose(*a.model, 0.26);
  auto update = [&](double t, const Eigen::VectorXd& q, double f_left) {
    return a.UpdateAt(controller, *context, t, q, f_left);
  };
  auto left_force = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& u) { return a.PlantForce(q, u, both, a.l); };
  const Solved s0 = update(0.0, q0, 50.0);
  ASSERT_EQ(s0.status, QpStatus::kOptimal);
  const Eigen::Vector3d d = left_force(q1, s0.u) - left_force(q0, s0.u);
  const double mu = params.contact.friction_coefficient;
  const bool inside = -d.z() > 0 && std::abs(d.x()) <= mu * -d.z();
  std::printf("  left foot's hold drift d = (%.3f, %.3f) N; -d inside the pyramid (mu %.2f): %d\n", d.x(), d.z(), mu,
              inside);
  ASSERT_FALSE(inside) << "the case needs a drift the pyramid cannot hold";
  ASSERT_LT(d.z(), 0.0) << "the case needs a falling force (a rising one: AReleasedFootsBandWithARisingDrift...)";
  const Solved s1 = update(1e-3, q1, 0.0);
  ASSERT_EQ(s1.status, QpStatus::kOptimal);
  EXPECT_EQ(s1.fallbacks.sum(), 0.0);
  EXPECT_EQ(s1.failures, 0.0);
  const double hold_end = left_force(q1, s1.u).z() + d.z();
  std::printf("  the plant's left F_z at the hold's end %.3g N\n", hold_end);
  EXPECT_NEAR(hold_end, 0.0, 1e-6);
}

// force_band_at_hold_end on a foot the band releases, with a rising drift: AMBER at rest in double support, updated at
// t = 0 with 50 N planned on the left foot, then one period later at a pose whose feet are 0.34 m apart instead of
// 0.3 m, with the left reference 0. The drift d = F(x1, u0) − F(x0, u0) (from the plant's own constrained dynamics)
// has d_z > 0 there (checked), so the band at the hold's end, F_z(u) + d_z ≤ 0, would ask F_z(u) < 0 against the
// unilateral row: infeasible, and the fallback dropped the band (walking: a foot left at 60 N after its planned
// lift-off). The band's upper edge then binds F_z(u) at the solve instant: it solves at once with the plant's left
// F_z(x1, u1) = 0.
TEST(ClfQpController, AReleasedFootsBandWithARisingDriftHoldsItAtZero) {
  const AmberBandSetup a;
  const ContactSet both = ContactBit(a.l) | ContactBit(a.r);
  ClfQpParams params;
  params.force_band = true;
  params.force_band_at_hold_end = true;
  params.predict_hold_drift = true;
  ClfQpController controller("clf", a.model, {both}, a.outputs, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q0 = a.q, q1 = test::AmberDoubleSupportPose(*a.model, 0.34);
  auto update = [&](double t, const Eigen::VectorXd& q, double f_left) {
    return a.UpdateAt(controller, *context, t, q, f_left);
  };
  auto left_fz = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& u) { return a.PlantForce(q, u, both, a.l).z(); };
  const Solved s0 = update(0.0, q0, 50.0);
  ASSERT_EQ(s0.status, QpStatus::kOptimal);
  const double dz = left_fz(q1, s0.u) - left_fz(q0, s0.u);
  std::printf("  left foot's hold drift d_z = %.3f N\n", dz);
  ASSERT_GT(dz, 0.0) << "the case needs a rising drift";
  const Solved s1 = update(1e-3, q1, 0.0);
  ASSERT_EQ(s1.status, QpStatus::kOptimal);
  EXPECT_EQ(s1.fallbacks.sum(), 0.0);
  std::printf("  the plant's left F_z at the solve instant %.3g N\n", left_fz(q1, s1.u));
  EXPECT_NEAR(left_fz(q1, s1.u), 0.0, 1e-6);
}

// force_band_carry_inactive: in left stance, the right foot's planned 0.7 m g moves to the left foot, so the band is
// (1 ± c) · m g there; checked on the plant's own constrained dynamics at the QP's torques (off: the band holds 0.3 m
// g).
TEST(ClfQpController, ForceBandCarriesTheInactiveContactsLoad) {
  const AmberBandSetup a;
  const ContactSet left = ContactBit(a.l);
  const double mg = a.mg;
  for (int carry = 0; carry < 2; ++carry) {
    ClfQpParams params;
    params.force_band = true;
    params.force_band_carry_inactive = carry == 1;
    params.contact.cop_margin_m = 0.0;
    ClfQpController controller("clf", a.model, {left}, a.outputs, params);
    auto context = controller.CreateDefaultLeafContext();
    Eigen::VectorXd f_ref = Eigen::VectorXd::Zero(2);
    f_ref[a.l] = 0.3 * mg;
    f_ref[a.r] = 0.7 * mg;
    context->FixInputPort(3, f_ref);
    const Solved s = RunUpdate(controller, *context, Stack(a.q, a.v), 0, a.Desired());
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    const double fz = a.PlantNormalForce(s.u, left, a.l);
    std::printf("  carry %d: plant F_z left %.4g N (m g %.4g N), fallbacks %.0f\n", carry, fz, mg, s.fallbacks.sum());
    EXPECT_EQ(s.fallbacks.sum(), 0.0);  // the band held (not dropped)
    const double total = carry == 1 ? mg : 0.3 * mg;
    EXPECT_GE(fz, 0.9 * total - 1e-6);
    EXPECT_LE(fz, 1.1 * total + 1e-6);
  }
}

// force_band_at_hold_end: AMBER in double support, moving, with a reference split (0.2 m g left, 0.8 m g right) the
// outputs do not ask for, so the band binds. Updates at t = 0 and T, each torque held over one period of the plant
// (its own constrained dynamics, semi-implicit Euler in 10 substeps). The plant's F_z at the end of the second hold,
// where the next update (and the walking runs' scoring) samples it, is inside Eq. (25)'s band with no slack when the
// QP bounds the force predicted at the hold's end (0.5 N inside the edges); bounding the force at the solve instant
// instead, the same plant force leaves the band by the drift over the hold.
TEST(ClfQpController, ForceBandAtHoldEndKeepsThePlantsForceInTheBandAtTheEndOfTheHold) {
  const AmberBandSetup a;
  const ContactSet both = ContactBit(a.l) | ContactBit(a.r);
  MultibodyWorkspace ws(*a.model);
  Eigen::VectorXd v0 = Eigen::VectorXd::Zero(a.model->nv());
  v0[0] = 0.6, v0[1] = -0.4, v0[3] = 1.5, v0[5] = -2.0;
  const int rows = CalcConstraintJacobian(*a.model, ws, a.q, v0, both);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  v0 -= J.completeOrthogonalDecomposition().solve(J * v0);  // consistent with both feet on the ground
  Eigen::VectorXd f_ref = Eigen::VectorXd::Zero(2);
  f_ref[a.l] = 0.2 * a.mg, f_ref[a.r] = 0.8 * a.mg;
  const double c = 0.1;
  double outside[2] = {0, 0};  // [N] how far the plant's end-of-hold F_z is outside the band (the larger foot)
  for (int at_end = 0; at_end < 2; ++at_end) {
    ClfQpParams params;
    params.force_band = true;
    params.force_band_halfwidth = c;
    params.force_band_at_hold_end = at_end == 1;
    params.force_band_margin_N = at_end == 1 ? 0.5 : 0.0;
    ClfQpController controller("clf", a.model, {both}, a.outputs, params);
    auto context = controller.CreateDefaultLeafContext();
    context->FixInputPort(3, f_ref);
    const double T = params.update_period_s;
    Eigen::VectorXd q = a.q, v = v0, qdd(a.model->nv()), F(a.model->max_constraint_rows());
    auto hold = [&](const Eigen::VectorXd& u) {
      for (int i = 0; i < 10; ++i) {
        CalcConstrainedForwardDynamics(*a.model, ws, q, v, u, both, ConstrainedDynamicsParameters{}, qdd, F);
        v += 0.1 * T * qdd;
        q += 0.1 * T * v;
      }
    };
    const Solved s0 = RunUpdate(controller, *context, Stack(q, v), 0, a.Desired());
    ASSERT_EQ(s0.status, QpStatus::kOptimal);
    hold(s0.u);
    context->SetTime(T);
    const Solved s1 = RunUpdate(controller, *context, Stack(q, v), 0, a.Desired());
    ASSERT_EQ(s1.status, QpStatus::kOptimal);
    EXPECT_EQ(s0.fallbacks.sum() + s1.fallbacks.sum(), 0.0);
    hold(s1.u);
    CalcConstrainedForwardDynamics(*a.model, ws, q, v, s1.u, both, ConstrainedDynamicsParameters{}, qdd, F);
    for (int foot : {a.l, a.r}) {
      const double fz = ExtractContactWrench(*a.model, ws, q, both, F, foot).force.z();
      const double miss = std::max((1 - c) * f_ref[foot] - fz, fz - (1 + c) * f_ref[foot]);
      std::printf("  band at the %s: foot %d plant F_z at the hold's end %.3f N, band [%.3f, %.3f] N\n",
                  at_end ? "hold's end" : "solve instant", foot, fz, (1 - c) * f_ref[foot], (1 + c) * f_ref[foot]);
      outside[at_end] = std::max(outside[at_end], miss);
    }
  }
  EXPECT_LE(outside[1], 0.0);
  EXPECT_GT(outside[0], 0.0) << "the drift over the hold takes the force the QP held on an edge out of the band";
}

TEST(ClfQpController, EachFallbackFiresOnAProblemBuiltToNeedIt) {
  auto model = test::LoadRobot("amber");
  const Eigen::VectorXd q = test::AmberSingleSupportPose(*model);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model->nv());
  const int l = model->ContactIndex("left_foot");
  const auto tasks = test::AmberWalkingTasks(*model);
  std::vector<ClfOutput> outputs;
  for (const auto& t : tasks) outputs.push_back(ClfOutput::RelativeDegreeTwo(t));
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(12);
  desired.head(4) = test::TaskValues(*model, tasks, q, v);
  // 1. A band at 20 m g on the stance foot: out of reach of the 100 N m motors; dropping the band solves.
  {
    ClfQpParams params;
    params.force_band = true;
    ClfQpController controller("clf", model, {ContactBit(l)}, outputs, params);
    auto context = controller.CreateDefaultLeafContext();
    Eigen::VectorXd f_ref = Eigen::VectorXd::Zero(2);
    f_ref[l] = 20.0 * model->total_mass() * 9.81;
    context->FixInputPort(3, f_ref);
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    EXPECT_EQ(s.status, QpStatus::kOptimal);
    EXPECT_EQ(s.fallbacks, Eigen::Vector4d(0, 1, 0, 0));
    EXPECT_EQ(s.failures, 1.0);
  }
  // 3. F_z ≥ 20 m g cannot be met even without the band and CoP rows: the previous u is held.
  {
    ClfQpParams params;
    params.contact.min_normal_force_N = 20.0 * model->total_mass() * 9.81;
    ClfQpController controller("clf", model, {ContactBit(l)}, outputs, params);
    auto context = controller.CreateDefaultLeafContext();
    context->get_mutable_discrete_state().head(4) = Eigen::Vector4d(1, 2, 3, 4);  // "previous" u
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    EXPECT_NE(s.status, QpStatus::kOptimal);
    EXPECT_EQ(s.fallbacks, Eigen::Vector4d(0, 0, 1, 1));
    EXPECT_EQ(s.u, Eigen::Vector4d(1, 2, 3, 4));
  }
}

// A planar foot (a 0.1 m line contact) carrying a pendulum swinging at 4 rad/s on a 0.5 m pivot, its motor limited to
// 0 N m: the passive pivot force times the pivot height puts the centre of pressure off the sole, so the QP is
// infeasible with the CoP rows and feasible without them (friction is made non-binding).
TEST(ClfQpController, CopFallbackFiresWhenOnlyTheCopRowsConflict) {
  auto model = LoadTestModel("footed_pendulum");
  const Eigen::VectorXd q = model->q_nominal();
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model->nv());
  v[3] = 4.0;  // pendulum rate; the foot is at rest
  const int sole = model->ContactIndex("sole");
  const ContactSet on = ContactBit(sole);
  // The independent check that the problem is built right: the plant's passive forces put the CoP off the sole.
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
  CalcConstrainedForwardDynamics(*model, ws, q, v, Eigen::VectorXd::Zero(1), on, ConstrainedDynamicsParameters{}, qdd,
                                 F);
  const ContactForceCheck check =
      CheckContactForce(*model, ws, q, sole, ExtractContactWrench(*model, ws, q, on, F, sole));
  std::printf("  passive footed pendulum: F_z %.2f N, CoP (%.3f, %.3f) m, CoP on the sole %d\n", check.normal_force_N,
              check.cop.x(), check.cop.y(), check.cop_ok);
  ASSERT_TRUE(check.unilateral_ok);
  ASSERT_FALSE(check.cop_ok);
  ClfQpParams params;
  params.torque_limits = Eigen::VectorXd::Zero(1);
  params.contact.friction_coefficient = 100.0;
  ClfQpController controller(
      "clf", model, {on}, {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pivot", *model, "pivot"))},
      params);
  auto context = controller.CreateDefaultLeafContext();
  const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(s.status, QpStatus::kOptimal);
  EXPECT_EQ(s.fallbacks, Eigen::Vector4d(0, 0, 1, 0));
  EXPECT_EQ(s.failures, 1.0);
}

// Per-actuator torque penalty (params.u_regularization_kind = kInverseJointInertia, u_regularization_weights): the QP
// answer meets its KKT conditions with the penalty ½ ρ_u Σ_j w_j (u_j / m_j)², m_j = M_jj, built here independently of
// the controller: q̈(u) = q̈0 + Q u from Bullet's articulated-body forward dynamics (Q by finite differences, exact for
// the affine map), M = Q⁻¹ (B = I on the arm), P_ε from the closed-form CARE. With the CLF row's multiplier λ = p δ
// (stationarity in δ: p δ − λ − μ_δ = 0, μ_δ δ = 0, so λ = p δ), stationarity in u reads
//   Qᵀ (q̈(u) − ÿ_d) + ρ_u diag(w_j / m_j²) u + p δ Qᵀ L_G V = 0     (torque limits inactive),
// and the answer must differ from the uniform penalty's (the option changes the QP).
TEST(ClfQpController, PerActuatorTorquePenaltyMeetsItsKktConditions) {
  auto model = LoadTestModel("arm");
  auto outputs = [&] {
    return std::vector<ClfOutput>{
        ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("shoulder", *model, "shoulder")),
        ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("elbow", *model, "elbow"))};
  };
  ClfQpParams params;
  params.epsilon = 0.1;
  params.u_regularization = 0.05;
  params.u_regularization_kind = TorqueRegularization::kInverseJointInertia;
  params.u_regularization_weights = Eigen::Vector2d(1.0, 3.0);
  params.u_regularization_modes = {0};
  ClfQpParams uniform = params;
  uniform.u_regularization_kind = TorqueRegularization::kUniform;
  uniform.u_regularization_weights.resize(0);
  ClfQpController controller("clf", model, {0}, outputs(), params);
  ClfQpController reference("clf_uniform", model, {0}, outputs(), uniform);
  auto context = controller.CreateDefaultLeafContext();
  auto ref_context = reference.CreateDefaultLeafContext();
  MultibodyWorkspace ws(*model);
  const Eigen::MatrixXd P = ClosedFormPEpsilon(2, params.epsilon);
  const double p = params.relaxation_weight;
  int checked = 0, clf_bound = 0;
  double max_difference = 0.0;
  for (int k = 0; k < 12; ++k) {
    Eigen::VectorXd q(2), v(2);
    q << 0.2 + 0.06 * k, -0.4 + 0.07 * k;
    v << 0.4 - 0.08 * k, 0.3 * std::cos(k);
    Eigen::VectorXd desired = Eigen::VectorXd::Zero(6);
    desired[0] = 0.5, desired[1] = 0.2;  // y_d; ẏ_d = ÿ_d = 0
    const Solved s = RunUpdate(controller, *context, Stack(q, v), 0, desired);
    const Solved su = RunUpdate(reference, *ref_context, Stack(q, v), 0, desired);
    ASSERT_EQ(s.status, QpStatus::kOptimal);
    ASSERT_EQ(su.status, QpStatus::kOptimal);
    max_difference = std::max(max_difference, (s.u - su.u).norm());
    if (std::abs(s.u[0]) > 59.0 || std::abs(s.u[1]) > 39.0)
      continue;  // a torque limit binds: stationarity has its term
    Eigen::VectorXd qdd0(2), qdd(2);
    CalcForwardDynamics(*model, ws, q, v, Eigen::Vector2d::Zero(), Eigen::VectorXd(0), qdd0);
    Eigen::Matrix2d Q;
    for (int j = 0; j < 2; ++j) {
      CalcForwardDynamics(*model, ws, q, v, Eigen::Vector2d::Unit(j), Eigen::VectorXd(0), qdd);
      Q.col(j) = qdd - qdd0;
    }
    const Eigen::Matrix2d M = Q.inverse();
    Eigen::Vector4d eta;
    eta << q - desired.head(2), v;
    const Eigen::Vector4d Peta = P * eta;
    const Eigen::Vector2d LGV = 2.0 * Peta.tail(2);
    Eigen::Vector2d penalty;
    for (int j = 0; j < 2; ++j)
      penalty[j] = params.u_regularization * params.u_regularization_weights[j] / (M(j, j) * M(j, j));
    const Eigen::Vector2d grad =
        Q.transpose() * (qdd0 + Q * s.u) + penalty.cwiseProduct(s.u) + p * s.delta * Q.transpose() * LGV;
    const double size = (Q.transpose() * (qdd0 + Q * s.u)).norm() + penalty.cwiseProduct(s.u).norm() + 1.0;
    EXPECT_LT(grad.norm(), 1e-6 * size) << "sample " << k << ", delta " << s.delta << ", u " << s.u.transpose();
    // Primal feasibility of the CLF row: V̇ ≤ −(γ/ε) V + δ.
    const double rate = 1.0 / (std::sqrt(3.0) + 1.0) / params.epsilon;
    Eigen::Vector4d eta_dot;
    eta_dot << v, qdd0 + Q * s.u;
    EXPECT_LE(2.0 * eta.dot(P * eta_dot), -rate * eta.dot(Peta) + s.delta + 1e-6 * (1.0 + eta.dot(Peta)))
        << "sample " << k;
    ++checked;
    if (s.delta > 0.0) ++clf_bound;
  }
  EXPECT_GE(checked, 8);
  EXPECT_GE(clf_bound, 1);  // the multiplier term was exercised
  EXPECT_GT(max_difference, 1e-2);
}

TEST(ClfQpController, BadParametersAndInputsAreNamed) {
  auto model = LoadTestModel("slider");
  const auto out = ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("x", *model, "slide"));
  ClfQpParams params;
  params.epsilon = 0.0;
  try {
    ClfQpController("clf", model, {0}, {out}, params);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "system 'clf': params.epsilon = 0.000000 must be positive and finite");
  }
  for (const double alpha : {-1.0, std::numeric_limits<double>::quiet_NaN()}) {
    ClfQpParams bad_alpha;
    bad_alpha.contact_stabilization.baumgarte_alpha_per_s = alpha;
    try {
      ClfQpController("clf", model, {0}, {out}, bad_alpha);
      FAIL() << "no error for alpha " << alpha;
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("system 'clf': params.contact_stabilization.baumgarte_alpha_per_s = ", 0),
                0u)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("must be >= 0 1/s and finite"), std::string::npos) << e.what();
    }
  }
  ClfQpParams bad_beta;
  bad_beta.contact_stabilization.baumgarte_beta_per_s = -2.0;
  EXPECT_THROW(ClfQpController("clf", model, {0}, {out}, bad_beta), std::runtime_error);
  ClfQpParams held;  // α = β = 0 is allowed: the contacts predicted as held
  held.contact_stabilization.baumgarte_alpha_per_s = 0.0;
  held.contact_stabilization.baumgarte_beta_per_s = 0.0;
  EXPECT_NO_THROW(ClfQpController("clf", model, {0}, {out}, held));
  ClfQpParams bad_weights;
  bad_weights.u_regularization_weights = Eigen::Vector2d(1.0, 2.0);
  EXPECT_THROW(
      {
        try {
          ClfQpController("clf", model, {0}, {out}, bad_weights);
        } catch (const std::runtime_error& e) {
          EXPECT_EQ(std::string(e.what()),
                    "system 'clf': params.u_regularization_weights has 2 entries, expected 1 (one per actuator)");
          throw;
        }
      },
      std::runtime_error);
  ClfQpParams bad_modes;
  bad_modes.u_regularization_modes = {3};
  EXPECT_THROW(ClfQpController("clf", model, {0}, {out}, bad_modes), std::runtime_error);
  ClfQpController controller("clf", model, {0}, {out});
  auto context = controller.CreateDefaultLeafContext();
  context->FixInputPort(0, Eigen::Vector2d(0, 0));
  context->FixAbstractInputPort(1, std::any(4));
  context->FixInputPort(2, Eigen::VectorXd::Zero(3));
  Eigen::VectorXd next = context->discrete_state();
  const EventStatus status = controller.periodic_events().at(0).update(*context, &next);
  EXPECT_EQ(status.kind, EventStatus::Kind::kFailed);
  EXPECT_EQ(status.message, "system 'clf': input port 'mode' has value 4; expected a mode index in [0, 1)");
}

}  // namespace
}  // namespace rome
