// ClfQpController on the 3D exoskeleton (18 DOF) standing in double support on flat feet: under a lateral push the
// plant's own contact wrenches keep each centre of pressure inside its sole, the normal forces positive and the
// forces inside the friction cone over every integrator step (checked with CheckContactForce on the plant's
// forces, not the QP's), and the update allocates no heap memory once running. Both formulations.
#include <gtest/gtest.h>

#include <cstdio>

#include "framework/diagram.h"
#include "framework/simulator.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/allocation_counter.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

std::vector<ClfOutput> StandingOutputs(const MultibodyModel& model) {
  return {ClfOutput::RelativeDegreeTwo(
              std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kY, Axis::kZ})),
          ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("roll", model, "base_roll")),
          ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pitch", model, "base_pitch")),
          ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("yaw", model, "base_yaw"))};
}

// Nominal standing pose, at rest except a lateral push of the pelvis (projected so that both feet stay at rest).
Eigen::VectorXd PushedState(const MultibodyModel& model, ContactSet both, double push_mps) {
  const Eigen::VectorXd q = model.q_nominal();
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
  v[model.VelocityIndex("base_y")] = push_mps;
  MultibodyWorkspace ws(model);
  const int rows = CalcConstraintJacobian(model, ws, q, v, both);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  v -= J.completeOrthogonalDecomposition().solve(J * v);
  Eigen::VectorXd x(2 * model.nv());
  x << q, v;
  return x;
}

class ExoskeletonStanding : public ::testing::TestWithParam<ClfQpFormulation> {};

TEST_P(ExoskeletonStanding, LateralPushKeepsThePlantsCopInsideEachSole) {
  auto model = test::LoadRobot("exoskeleton");
  const int l = model->ContactIndex("left_foot"), r = model->ContactIndex("right_foot");
  const ContactSet both = ContactBit(l) | ContactBit(r);
  MultibodyWorkspace ws(*model);
  // The nominal pose stands: both soles at z = 0.
  for (int c : {l, r}) ASSERT_NEAR(CalcContactHeight(*model, ws, model->q_nominal(), c), 0.0, 1e-6);

  ContactModeGraph graph;
  graph.modes = {{"double_support", {"left_foot", "right_foot"}}};
  graph.initial_mode = "double_support";
  DiagramBuilder b;
  auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, graph, Terrain::Flat()));
  ClfQpParams params;
  params.formulation = GetParam();
  params.epsilon = 0.05;
  params.contact.min_normal_force_N = 20.0;
  params.contact.friction_margin = 0.95;
  params.contact_stabilization = plant->params().dynamics;
  const auto outputs = StandingOutputs(*model);
  auto* controller =
      b.AddSystem(std::make_unique<ClfQpController>("clf", model, ActiveContactsPerMode(*plant), outputs, params));
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(18);
  desired.head(3) = CalcComPosition(*model, ws, model->q_nominal());  // hold the COM; roll, pitch, yaw at 0
  b.FixInput("clf", "desired", desired);
  b.Connect("plant", "state", "clf", "state");
  b.Connect("plant", "mode", "clf", "mode");
  b.Connect("clf", "u", "plant", "u");
  auto diagram = b.Build("exo_standing");
  SimulatorConfig config;
  config.scheme = IntegrationScheme::kExplicitRungeKutta;
  config.relative_tolerance = 1e-7;
  config.absolute_tolerance = 1e-9;
  Simulator sim(*diagram, config);
  const Eigen::VectorXd x0 = PushedState(*model, both, 0.3);
  LeafContext& pc = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(pc, x0.head(model->nv()), x0.tail(model->nv()), "double_support");
  long steps = 0, cop_outside = 0, unilateral_bad = 0, friction_bad = 0;
  double worst_cop_margin = 1.0, min_fz = 1e9;
  sim.set_monitor([&](const Context& c) {
    const LeafContext& ctx = diagram->GetSubsystemContext(*plant, c);
    const Eigen::VectorXd q = ctx.continuous_state().head(model->nv());
    const Eigen::VectorXd& f = plant->EvalOutput(ctx, "contact_forces");
    (void)f;
    // The plant's wrench on each foot, from its own constrained dynamics at this state and input.
    Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
    CalcConstrainedForwardDynamics(*model, ws, q, ctx.continuous_state().tail(model->nv()),
                                   controller->EvalOutput(diagram->GetSubsystemContext(*controller, c), "u"), both,
                                   plant->params().dynamics, qdd, F);
    for (int cidx : {l, r}) {
      const ContactForceCheck check =
          CheckContactForce(*model, ws, q, cidx, ExtractContactWrench(*model, ws, q, both, F, cidx));
      cop_outside += check.cop_ok ? 0 : 1;
      unilateral_bad += check.unilateral_ok ? 0 : 1;
      friction_bad += check.friction_ok ? 0 : 1;
      min_fz = std::min(min_fz, check.normal_force_N);
      // Distance of the CoP from the sole's edge (the sole spans x in [-0.07, 0.18] m, y in [-0.05, 0.05] m about the
      // ankle; here only its sign matters: CheckContactForce decides inside/outside).
      worst_cop_margin = std::min(worst_cop_margin, check.cop_ok ? 1.0 : -1.0);
    }
    ++steps;
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(0.6);
  EXPECT_EQ(status.kind(), SimulatorStatus::Kind::kLimit) << status.ToString();
  EXPECT_GT(steps, 500);
  EXPECT_EQ(cop_outside, 0);
  EXPECT_EQ(unilateral_bad, 0);
  EXPECT_EQ(friction_bad, 0);
  const LeafContext& cc = diagram->GetSubsystemContext(*controller, sim.get_context());
  EXPECT_EQ(controller->EvalOutput(cc, "qp_failures")[0], 0.0);
  // The push is absorbed: the pelvis has stopped moving sideways and the COM is back near its target.
  const Eigen::VectorXd& x = pc.continuous_state();
  const Eigen::Vector3d com = CalcComPosition(*model, ws, x.head(model->nv()));
  std::printf("  after 0.6 s: COM error %.2e m, lateral COM speed %.2e m/s, min F_z %.1f N, %ld steps\n",
              (com - desired.head(3)).norm(), CalcComVelocity(*model, ws, x.head(model->nv()), x.tail(model->nv())).y(),
              min_fz, steps);
  EXPECT_LT((com - desired.head(3)).norm(), 0.02);
  (void)worst_cop_margin;
}

TEST_P(ExoskeletonStanding, UpdateAllocatesNothingOnceRunning) {
  auto model = test::LoadRobot("exoskeleton");
  const int l = model->ContactIndex("left_foot"), r = model->ContactIndex("right_foot");
  const ContactSet both = ContactBit(l) | ContactBit(r);
  ClfQpParams params;
  params.formulation = GetParam();
  params.contact.min_normal_force_N = 20.0;
  ClfQpController controller("clf", model, {both, ContactBit(l)}, StandingOutputs(*model), params);
  auto context = controller.CreateDefaultLeafContext();
  Eigen::VectorXd x = PushedState(*model, both, 0.3);
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(18);
  desired.head(3) = CalcComPosition(*model, ws, model->q_nominal());
  context->FixInputPort(0, x);
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, desired);
  const auto& update = controller.periodic_events().at(0).update;
  Eigen::VectorXd next = context->discrete_state();
  ASSERT_TRUE(update(*context, &next).ok());  // prime
  long allocations = 0;
  for (int tick = 0; tick < 100; ++tick) {
    auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0));
    fixed[model->nv() + 1] = 0.3 + 0.001 * tick;  // the state changes in place
    auto& mode = const_cast<int&>(controller.EvalTypedInput<int>(*context, 1));
    mode = (tick / 25) % 2;  // switch between the two modes' QPs
    context->InvalidateCache();
    allocations += test::CountAllocations([&] { ASSERT_TRUE(update(*context, &next).ok()); });
  }
  EXPECT_EQ(allocations, 0);
  context->get_mutable_discrete_state() = next;
  EXPECT_EQ(controller.diagnostics(*context).qp_failures, 0);
}

INSTANTIATE_TEST_SUITE_P(Formulations, ExoskeletonStanding,
                         ::testing::Values(ClfQpFormulation::kEliminateContactForces,
                                           ClfQpFormulation::kAugmentedInput));

}  // namespace
}  // namespace rome
