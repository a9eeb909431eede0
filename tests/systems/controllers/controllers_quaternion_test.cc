// The controllers and their outputs on the quaternion free-flyer base (issue 43), checked against the same robot on
// the ZYX-Euler base and against finite differences taken on the manifold (MultibodyModel::Integrate):
//   - BodyEulerAngleTask equals a JointPositionTask on base_roll / base_pitch / base_yaw on the Euler base;
//   - on the quaternion base its J and J̇q̇ match central differences along the constant-twist flow;
//   - JointPositionTask reads a joint's coordinate at its position index and refuses the base's twist entries;
//   - JointLimitBrake writes the same rows from either base;
//   - ClfQpController gives the same torques from either base at the same physical state (its cost, the outputs'
//     accelerations, the contact constraints and the wrench rows do not depend on the coordinates), and the same
//     closed loop: the exoskeleton pushed while standing, run on each base's hybrid plant, with the plant's own
//     contact wrenches unilateral and inside the friction cone at every integrator step; its update on the quaternion
//     model allocates nothing once running (this binary replaces the global allocator).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "framework/diagram.h"
#include "framework/simulator.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/joint_limit_brake.h"
#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "systems/plants/quaternion_to_euler_state.h"
#include "tests/common/allocation_counter.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

struct Twins {
  std::shared_ptr<const MultibodyModel> euler, quaternion;
};

Twins LoadTwins() {
  Twins t;
  t.euler = test::LoadRobot("exoskeleton");
  t.quaternion = LoadQuaternionTwin(*t.euler);
  return t;
}

// A generic Euler state of the exoskeleton: pitch −0.7, roll 0.3 rad, every coordinate moving.
Eigen::VectorXd GenericEulerState(const MultibodyModel& euler) { return test::GenericEulerState(euler, -0.7, 0.3); }

struct TaskValue {
  double y;
  Eigen::RowVectorXd J;
  double Jdot_qdot;
};

TaskValue Evaluate(const TaskSpaceTask& task, const MultibodyModel& model, const Eigen::VectorXd& q,
                   const Eigen::VectorXd& v) {
  MultibodyWorkspace ws(model);
  Eigen::VectorXd y(1), a(1);
  Eigen::MatrixXd J(1, model.nv());
  task.Calc(model, ws, q, v, y, J, a);
  return {y[0], J.row(0), a[0]};
}

const std::pair<EulerAngle, const char*> kAngles[] = {
    {EulerAngle::kRoll, "base_roll"}, {EulerAngle::kPitch, "base_pitch"}, {EulerAngle::kYaw, "base_yaw"}};

TEST(BodyEulerAngleTask, EqualsTheEulerBaseCoordinates) {
  const Twins t = LoadTwins();
  const MultibodyModel& m = *t.euler;
  const Eigen::VectorXd x = GenericEulerState(m);
  const Eigen::VectorXd q = x.head(m.nv()), v = x.tail(m.nv());
  for (const auto& [angle, joint] : kAngles) {
    const TaskValue body = Evaluate(BodyEulerAngleTask("pelvis", m, "pelvis", angle), m, q, v);
    const TaskValue coordinate = Evaluate(JointPositionTask("coordinate", m, joint), m, q, v);
    EXPECT_NEAR(body.y, coordinate.y, 1e-12) << joint;
    EXPECT_LT((body.J - coordinate.J).cwiseAbs().maxCoeff(), 1e-12) << joint;
    EXPECT_NEAR(body.Jdot_qdot, coordinate.Jdot_qdot, 1e-10) << joint;  // 0: a coordinate is linear in q
  }
}

TEST(BodyEulerAngleTask, MatchesManifoldFiniteDifferencesOnTheQuaternionBase) {
  const Twins t = LoadTwins();
  const MultibodyModel& m = *t.quaternion;
  Eigen::VectorXd xq(m.nq() + m.nv());
  EulerStateToQuaternion(GenericEulerState(*t.euler), xq);
  const Eigen::VectorXd q0 = xq.head(m.nq()), v = xq.tail(m.nv());
  // Along q(s) = Integrate(q0, v, s), the exact flow of the constant velocity v: ẏ = J v and ÿ = J̇ q̇.
  auto y_at = [&](const BodyEulerAngleTask& task, double s) {
    Eigen::VectorXd q(m.nq());
    m.Integrate(q0, v, s, q);
    return Evaluate(task, m, q, v).y;
  };
  for (const char* body : {"pelvis", "left_shank", "right_foot"})
    for (const auto& [angle, joint] : kAngles) {
      const BodyEulerAngleTask task("angle", m, body, angle);
      const TaskValue at = Evaluate(task, m, q0, v);
      const double h1 = 1e-6, h2 = 1e-4;
      const double rate = (y_at(task, h1) - y_at(task, -h1)) / (2 * h1);
      const double accel = (y_at(task, h2) - 2 * at.y + y_at(task, -h2)) / (h2 * h2);
      EXPECT_NEAR(at.J.dot(v), rate, 1e-8) << body << " " << joint;
      EXPECT_NEAR(at.Jdot_qdot, accel, 2e-6 * std::max(1.0, std::abs(accel))) << body << " " << joint;
    }
}

TEST(BodyEulerAngleTask, AgreesAcrossTheBasesAndRefusesTheSingularity) {
  const Twins t = LoadTwins();
  const Eigen::VectorXd xe = GenericEulerState(*t.euler);
  Eigen::VectorXd xq(t.quaternion->nq() + t.quaternion->nv());
  EulerStateToQuaternion(xe, xq);
  const int nv = t.euler->nv(), nq = t.quaternion->nq();
  for (const char* body : {"pelvis", "left_foot"})
    for (const auto& [angle, joint] : kAngles) {
      const TaskValue e = Evaluate(BodyEulerAngleTask("e", *t.euler, body, angle), *t.euler, xe.head(nv), xe.tail(nv));
      const TaskValue q =
          Evaluate(BodyEulerAngleTask("q", *t.quaternion, body, angle), *t.quaternion, xq.head(nq), xq.tail(nv));
      EXPECT_NEAR(e.y, q.y, 1e-12) << body << " " << joint;
      EXPECT_NEAR(e.J.dot(xe.tail(nv)), q.J.dot(xq.tail(nv)), 1e-12) << body << " " << joint;  // the angle's rate
    }
  // Pitch 90 deg: ZYX angles are singular; the task names the body and the pitch.
  Eigen::VectorXd up = xe;
  up[t.euler->VelocityIndex("base_pitch")] = M_PI / 2;
  Eigen::VectorXd xq_up(xq.size());
  EulerStateToQuaternion(up, xq_up);
  try {
    Evaluate(BodyEulerAngleTask("pelvis_pitch", *t.quaternion, "pelvis", EulerAngle::kPitch), *t.quaternion,
             xq_up.head(nq), xq_up.tail(nv));
    ADD_FAILURE() << "no error at pitch pi/2";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'pelvis_pitch'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("body 'pelvis' pitch 1.57"), std::string::npos) << e.what();
  }
}

TEST(JointPositionTask, ReadsTheJointsCoordinateOnTheQuaternionBase) {
  const Twins t = LoadTwins();
  const Eigen::VectorXd xe = GenericEulerState(*t.euler);
  Eigen::VectorXd xq(t.quaternion->nq() + t.quaternion->nv());
  EulerStateToQuaternion(xe, xq);
  const int nv = t.euler->nv(), nq = t.quaternion->nq();
  for (const char* joint : {"left_knee", "right_ankle_pitch"}) {
    const TaskValue e = Evaluate(JointPositionTask("e", *t.euler, joint), *t.euler, xe.head(nv), xe.tail(nv));
    const TaskValue q = Evaluate(JointPositionTask("q", *t.quaternion, joint), *t.quaternion, xq.head(nq), xq.tail(nv));
    EXPECT_EQ(e.y, q.y) << joint;
    EXPECT_EQ(e.J, q.J) << joint;  // the joint's column in v: the same index on both bases
  }
  try {
    JointPositionTask("yaw", *t.quaternion, "base_wz");
    ADD_FAILURE() << "a twist entry was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'base_wz' of robot 'exoskeleton' is a twist entry"), std::string::npos)
        << e.what();
  }
  MultibodyWorkspace ws(*t.quaternion);
  Eigen::VectorXd y(1), a(1);
  Eigen::MatrixXd J(1, nv);
  EXPECT_THROW(JointPositionTask("knee", *t.quaternion, "left_knee")
                   .Calc(*t.quaternion, ws, xe.head(nv), xe.tail(nv), y, J, a),  // an Euler q on the quaternion model
               std::invalid_argument);
}

TEST(JointLimitBrake, WritesTheSameRowsFromEitherBase) {
  const Twins t = LoadTwins();
  JointLimitBrakeParams p;
  p.enabled = true;
  const JointLimitBrake be(*t.euler, p, "euler"), bq(*t.quaternion, p, "quaternion");
  ASSERT_GT(be.num_rows(), 0);
  EXPECT_EQ(be.limited(), bq.limited());
  const int nv = t.euler->nv(), nq = t.quaternion->nq(), nu = t.euler->nu();
  Eigen::VectorXd xe = GenericEulerState(*t.euler);
  for (int i : be.limited()) {  // every limited joint 3 cm from a stop
    const double upper = t.euler->position_upper_limits()[i];
    xe[i] = std::isfinite(upper) ? upper - 0.03 : t.euler->position_lower_limits()[i] + 0.03;
  }
  Eigen::VectorXd xq(nq + nv);
  EulerStateToQuaternion(xe, xq);
  const Eigen::VectorXd qdd0 = Eigen::VectorXd::LinSpaced(nv, -1.0, 1.0);
  const Eigen::MatrixXd Qu = Eigen::MatrixXd::Identity(nv, nu);
  DenseQpSolver qe(nu, 0, be.num_rows()), qq(nu, 0, bq.num_rows());
  be.Fill(xe.head(nv), xe.tail(nv), qdd0, Qu, Eigen::MatrixXd(nv, 0), 0, qe);
  bq.Fill(xq.head(nq), xq.tail(nv), qdd0, Qu, Eigen::MatrixXd(nv, 0), 0, qq);
  EXPECT_EQ(qe.A, qq.A);
  EXPECT_EQ(qe.l, qq.l);
  EXPECT_EQ(qe.u, qq.u);
  EXPECT_TRUE((qe.u.array() < 1e3).any() || (qe.l.array() > -1e3).any());  // the rows bound something
}

// The standing outputs of clf_qp_exoskeleton_test: COM and pelvis roll, pitch, yaw (base coordinates on the Euler
// base, BodyEulerAngleTask on the quaternion base).
std::vector<ClfOutput> StandingOutputs(const MultibodyModel& model) {
  std::vector<ClfOutput> outputs = {ClfOutput::RelativeDegreeTwo(
      std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kY, Axis::kZ}))};
  for (const auto& [angle, joint] : kAngles)
    outputs.push_back(ClfOutput::RelativeDegreeTwo(
        model.has_quaternion_base()
            ? std::shared_ptr<TaskSpaceTask>(std::make_shared<BodyEulerAngleTask>(joint, model, "pelvis", angle))
            : std::make_shared<JointPositionTask>(joint, model, joint)));
  return outputs;
}

ClfQpParams StandingParams(ClfQpFormulation formulation) {
  ClfQpParams params;
  params.formulation = formulation;
  params.epsilon = 0.05;
  params.contact.min_normal_force_N = 20.0;
  params.contact.friction_margin = 0.95;
  params.contact.cop_margin_m = 0.01;
  params.contact.corner_wrench_cone = true;  // the walking default's sole (corner pyramids, yaw rows)
  params.contact.corner_cone_yaw_margin_m = 0.002;
  params.joint_limit_brake.enabled = true;
  return params;
}

// The nominal standing pose pushed sideways at the pelvis, projected so that both feet stay at rest (Euler state).
Eigen::VectorXd PushedEulerState(const MultibodyModel& euler, double push_mps) {
  const ContactSet both = ContactBit(euler.ContactIndex("left_foot")) | ContactBit(euler.ContactIndex("right_foot"));
  const Eigen::VectorXd q = euler.q_nominal();
  Eigen::VectorXd v = Eigen::VectorXd::Zero(euler.nv());
  v[euler.VelocityIndex("base_y")] = push_mps;
  v[euler.VelocityIndex("base_yaw")] = 0.2;
  MultibodyWorkspace ws(euler);
  const int rows = CalcConstraintJacobian(euler, ws, q, v, both);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  v -= J.completeOrthogonalDecomposition().solve(J * v);
  Eigen::VectorXd x(2 * euler.nv());
  x << q, v;
  return x;
}

class ClfQpOnEitherBase : public ::testing::TestWithParam<ClfQpFormulation> {};

TEST_P(ClfQpOnEitherBase, SameTorquesAtTheSameState) {
  const Twins t = LoadTwins();
  const Eigen::VectorXd xe = PushedEulerState(*t.euler, 0.3);
  Eigen::VectorXd xq(t.quaternion->nq() + t.quaternion->nv());
  EulerStateToQuaternion(xe, xq);
  MultibodyWorkspace ws(*t.euler);
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(18);
  desired.head(3) = CalcComPosition(*t.euler, ws, t.euler->q_nominal()) + Eigen::Vector3d(0.01, -0.02, 0.005);
  desired.segment(6, 3) << 0.3, -0.1, 0.2;     // COM velocity target
  desired.segment(3, 3) << 0.02, -0.03, 0.05;  // roll, pitch, yaw targets
  const int l = t.euler->ContactIndex("left_foot"), r = t.euler->ContactIndex("right_foot");
  Eigen::VectorXd u[2];
  for (int k = 0; k < 2; ++k) {
    const auto& model = k == 0 ? t.euler : t.quaternion;
    ClfQpController controller("clf", model, {ContactBit(l) | ContactBit(r)}, StandingOutputs(*model),
                               StandingParams(GetParam()));
    auto context = controller.CreateDefaultLeafContext();
    context->FixInputPort(0, k == 0 ? xe : xq);
    context->FixAbstractInputPort(1, std::any(0));
    context->FixInputPort(2, desired);
    Eigen::VectorXd next = context->discrete_state();
    ASSERT_TRUE(controller.periodic_events().at(0).update(*context, &next).ok());
    context->get_mutable_discrete_state() = next;
    ASSERT_EQ(controller.diagnostics(*context).qp_status.value_or(QpStatus::kInvalidInput), QpStatus::kOptimal);
    u[k] = controller.EvalOutput(*context, "u");
  }
  std::printf("  |u| = %.3f N m, max |u_euler - u_quaternion| = %.2e N m\n", u[0].norm(),
              (u[0] - u[1]).cwiseAbs().maxCoeff());
  EXPECT_GT(u[0].norm(), 10.0);
  EXPECT_LT((u[0] - u[1]).cwiseAbs().maxCoeff(), 1e-7 * u[0].cwiseAbs().maxCoeff());
}

TEST_P(ClfQpOnEitherBase, UpdateOnTheQuaternionModelAllocatesNothingOnceRunning) {
  const Twins t = LoadTwins();
  const MultibodyModel& m = *t.quaternion;
  Eigen::VectorXd xq(m.nq() + m.nv());
  EulerStateToQuaternion(PushedEulerState(*t.euler, 0.3), xq);
  const int l = m.ContactIndex("left_foot"), r = m.ContactIndex("right_foot");
  ClfQpController controller("clf", t.quaternion, {ContactBit(l) | ContactBit(r), ContactBit(l)}, StandingOutputs(m),
                             StandingParams(GetParam()));
  auto context = controller.CreateDefaultLeafContext();
  MultibodyWorkspace ws(m);
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(18);
  desired.head(3) = CalcComPosition(m, ws, xq.head(m.nq()));
  context->FixInputPort(0, xq);
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, desired);
  const auto& update = controller.periodic_events().at(0).update;
  Eigen::VectorXd next = context->discrete_state();
  ASSERT_TRUE(update(*context, &next).ok());  // prime both modes' workspaces
  long allocations = 0;
  for (int tick = 0; tick < 100; ++tick) {
    auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0));
    fixed[m.nq() + 1] = 0.3 + 0.001 * tick;  // the base's lateral velocity changes in place
    auto& mode = const_cast<int&>(controller.EvalTypedInput<int>(*context, 1));
    mode = (tick / 25) % 2;
    context->InvalidateCache();
    allocations += test::CountAllocations([&] { ASSERT_TRUE(update(*context, &next).ok()); });
  }
  EXPECT_EQ(allocations, 0);
}

struct ClosedLoop {
  Eigen::MatrixXd com;  // 3 × samples at 10 ms
  long steps = 0, unilateral_bad = 0, friction_bad = 0, cop_bad = 0;
  int qp_failures = -1;
};

ClosedLoop RunStanding(const std::shared_ptr<const MultibodyModel>& model, const Eigen::VectorXd& x0,
                       ClfQpFormulation formulation) {
  ContactModeGraph graph;
  graph.modes = {{"double_support", {"left_foot", "right_foot"}}};
  graph.initial_mode = "double_support";
  DiagramBuilder b;
  auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, graph, Terrain::Flat()));
  ClfQpParams params = StandingParams(formulation);
  params.contact_stabilization = plant->params().dynamics;
  auto* controller = b.AddSystem(
      std::make_unique<ClfQpController>("clf", model, ActiveContactsPerMode(*plant), StandingOutputs(*model), params));
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(18);
  // Move the COM 1 cm sideways and 5 mm down, and turn the pelvis: a motion of every output.
  desired.head(3) = CalcComPosition(*model, ws, x0.head(model->nq())) + Eigen::Vector3d(0.0, 0.01, -0.005);
  desired.segment(3, 3) << 0.01, -0.01, 0.02;
  b.FixInput("clf", "desired", desired);
  b.Connect("plant", "state", "clf", "state");
  b.Connect("plant", "mode", "clf", "mode");
  b.Connect("clf", "u", "plant", "u");
  auto diagram = b.Build("standing");
  SimulatorConfig config;
  config.scheme = IntegrationScheme::kExplicitRungeKutta;
  config.relative_tolerance = 1e-9;
  config.absolute_tolerance = 1e-11;
  Simulator sim(*diagram, config);
  LeafContext& pc = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(pc, x0.head(model->nq()), x0.tail(model->nv()), "double_support");
  const ContactSet both = ContactBit(model->ContactIndex("left_foot")) | ContactBit(model->ContactIndex("right_foot"));
  ClosedLoop out;
  sim.set_monitor([&](const Context& c) {
    const LeafContext& ctx = diagram->GetSubsystemContext(*plant, c);
    const Eigen::VectorXd q = ctx.continuous_state().head(model->nq()), v = ctx.continuous_state().tail(model->nv());
    Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
    CalcConstrainedForwardDynamics(*model, ws, q, v,
                                   controller->EvalOutput(diagram->GetSubsystemContext(*controller, c), "u"), both,
                                   plant->params().dynamics, qdd, F);
    for (const char* foot : {"left_foot", "right_foot"}) {
      const int ci = model->ContactIndex(foot);
      const ContactForceCheck check =
          CheckContactForce(*model, ws, q, ci, ExtractContactWrench(*model, ws, q, both, F, ci));
      out.unilateral_bad += check.unilateral_ok ? 0 : 1;
      out.friction_bad += check.friction_ok ? 0 : 1;
      out.cop_bad += check.cop_ok ? 0 : 1;
    }
    ++out.steps;
    return EventStatus::Succeeded();
  });
  const int samples = 41;
  out.com.resize(3, samples);
  for (int k = 0; k < samples; ++k) {
    const SimulatorStatus status = sim.AdvanceTo(0.01 * k);
    EXPECT_TRUE(status.ok()) << status.ToString();
    out.com.col(k) = CalcComPosition(*model, ws, pc.continuous_state().head(model->nq()));
  }
  out.qp_failures = static_cast<int>(
      controller->EvalOutput(diagram->GetSubsystemContext(*controller, sim.get_context()), "qp_failures")[0]);
  return out;
}

TEST_P(ClfQpOnEitherBase, SameClosedLoopOnEachBasesPlant) {
  const Twins t = LoadTwins();
  const Eigen::VectorXd xe = PushedEulerState(*t.euler, 0.3);
  Eigen::VectorXd xq(t.quaternion->nq() + t.quaternion->nv());
  EulerStateToQuaternion(xe, xq);
  const ClosedLoop e = RunStanding(t.euler, xe, GetParam()), q = RunStanding(t.quaternion, xq, GetParam());
  const double gap = (e.com - q.com).cwiseAbs().maxCoeff();
  std::printf("  0.4 s: COM moved %.1f mm; max COM gap Euler vs quaternion %.2e m; %ld / %ld steps\n",
              1e3 * (e.com.col(40) - e.com.col(0)).norm(), gap, e.steps, q.steps);
  for (const ClosedLoop* run : {&e, &q}) {
    EXPECT_GT(run->steps, 300);
    EXPECT_EQ(run->unilateral_bad, 0);
    EXPECT_EQ(run->friction_bad, 0);
    EXPECT_EQ(run->cop_bad, 0);
    EXPECT_EQ(run->qp_failures, 0);
  }
  EXPECT_GT((e.com.col(40) - e.com.col(0)).norm(), 5e-3);  // the COM moved toward its new target
  EXPECT_LT(gap, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Formulations, ClfQpOnEitherBase,
                         ::testing::Values(ClfQpFormulation::kEliminateContactForces,
                                           ClfQpFormulation::kAugmentedInput));

}  // namespace
}  // namespace rome
