// The hopping CLF-QP (ClfQpController with the augmented input [u; F], hopping Eq. (45)-(51), and the per-domain
// outputs of MakeHoppingOutputs, Eq. (41)-(44)) on 3D Cassie with live springs and achilles rods, in double support
// on line feet:
//   * under the Landing output set Cassie crouches from its nominal leg length by 8 cm and holds it: the virtual leg
//     lengths reach the command, the COM stays above the support centre, and at rest the plant's total normal force
//     equals m g (Newton, with the robot at rest); the plant's own contact forces are unilateral, inside the friction
//     cone and with the CoP between toe and heel at every integrator step (the plant's contact_violation output);
//   * the QP's planned ground forces agree with the plant's (both from J q̈ + J̇ q̇ = stabilisation);
//   * the periodic update allocates no heap memory once running, in all three domains.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "diagrams/hopping/hopping_outputs.h"
#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "framework/simulator_presets.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/allocation_counter.h"
#include "tests/diagrams/hopping/spec_leg_length.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> LoadCassie() {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
}

ClfQpParams HoppingQpParams(const HybridContactPlant& plant) {
  ClfQpParams p;
  p.formulation = ClfQpFormulation::kAugmentedInput;
  p.update_period_s = 5e-4;  // 2 kHz (hopping paper)
  p.epsilon = 0.1;
  p.contact_stabilization = plant.params().dynamics;
  return p;
}

// Centre of the four sole points (toe and heel of both feet), world x, y.
Eigen::Vector2d SupportCentre(const MultibodyModel& model, const Eigen::VectorXd& q) {
  MultibodyWorkspace ws(model);
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int k = 0; k < model.num_contacts(); ++k)
    for (int p = 0; p < 2; ++p)
      c += CalcContactPointPosition(model, ws, q, k, p).head<2>() / (2.0 * model.num_contacts());
  return c;
}

// Quintic from a to b over [t0, t1] with zero end rates and accelerations: value, rate, acceleration.
Eigen::Vector3d Quintic(double t, double t0, double t1, double a, double b) {
  const double T = t1 - t0, s = std::clamp((t - t0) / T, 0.0, 1.0);
  const double p = 10 * s * s * s - 15 * s * s * s * s + 6 * s * s * s * s * s;
  const double dp = (30 * s * s - 60 * s * s * s + 30 * s * s * s * s) / T,
               ddp = (60 * s - 180 * s * s + 120 * s * s * s) / (T * T);
  const bool inside = t > t0 && t < t1;
  return {a + (b - a) * p, inside ? (b - a) * dp : 0.0, inside ? (b - a) * ddp : 0.0};
}

// Jump outputs (H_pitch instead of the pelvis pitch) or Landing outputs.
class HoppingCrouch : public ::testing::TestWithParam<std::string> {};

TEST_P(HoppingCrouch, CrouchAndHoldWithPhysicalContactForces) {
  auto model = LoadCassie();
  const int nv = model->nv();
  const ContactModeGraph graph = ContactModeGraph::JumpFlightLanding("left_foot", "right_foot");
  DiagramBuilder b;
  auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, graph, Terrain::Flat()));
  auto* controller = b.AddSystem(std::make_unique<ClfQpController>("clf", model, ActiveContactsPerMode(*plant),
                                                                   MakeHoppingOutputs(*model, test::SpecLegLength),
                                                                   HoppingQpParams(*plant)));
  const Eigen::VectorXd q0 = model->q_nominal();
  double L0 = 0, dL0 = 0;
  test::SpecLegLength(q0[model->VelocityIndex("left_knee")], &L0, &dL0);
  const double crouch = 0.08, t0 = 0.3, t1 = 1.3;
  const Eigen::Vector2d centre = SupportCentre(*model, q0);
  const HoppingOutputLayout layout = MakeHoppingOutputLayout();
  const int ny = layout.size;
  ASSERT_EQ(controller->num_outputs(), ny);
  b.AddSystem(std::make_unique<TrajectorySource>("reference", 3 * ny,
                                                 [=, layout = layout](double t, Eigen::Ref<Eigen::VectorXd> d) {
                                                   d.setZero();
                                                   const Eigen::Vector3d L = Quintic(t, t0, t1, L0, L0 - crouch);
                                                   for (int leg : {layout.leg_left, layout.leg_right})
                                                     for (int k = 0; k < 3; ++k) d[k * ny + leg] = L[k];
                                                   d[layout.com_x] = centre.x();
                                                   d[layout.com_y] = centre.y();
                                                 }));
  b.Connect("reference", "y", "clf", "desired");
  b.Connect("plant", "state", "clf", "state");
  b.Connect("plant", "mode", "clf", "mode");
  b.Connect("clf", "u", "plant", "u");
  auto diagram = b.Build("cassie_crouch");
  // The hopping diagram's integrator (explicit Bogacki-Shampine carrying its step over the 2 kHz samples), at the
  // tighter tolerances this test has always used; with CVODE's BDF here the 2.5 s took 9.8 s in Release (128 s under
  // the sanitizers), almost all of it in the finite-difference Jacobians of each restart.
  Simulator sim(*diagram, ExplicitRestartingSimulatorConfig(1e-6, 1e-8));
  LeafContext& pc = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(pc, q0, Eigen::VectorXd::Zero(nv), GetParam());
  MultibodyWorkspace ws(*model);
  long steps = 0, violations = 0;
  double max_qp_plant_force_gap = 0.0, min_fz = 1e9;
  sim.set_monitor([&](const Context& c) {
    const LeafContext& ctx = diagram->GetSubsystemContext(*plant, c);
    const Eigen::VectorXd& viol = plant->EvalOutput(ctx, "contact_violation");
    violations += (viol.array() != 0.0).count();
    const Eigen::VectorXd& f = plant->EvalOutput(ctx, "contact_forces");
    min_fz = std::min({min_fz, f[2], f[5]});
    ++steps;
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(2.5);
  ASSERT_TRUE(status.ok()) << status.ToString();
  const LeafContext& pctx = diagram->GetSubsystemContext(*plant, sim.get_context());
  const LeafContext& cctx = diagram->GetSubsystemContext(*controller, sim.get_context());
  const Eigen::VectorXd x = pctx.continuous_state();
  const Eigen::VectorXd q = x.head(nv), v = x.tail(nv);
  double L_left = 0, L_right = 0, unused = 0;
  test::SpecLegLength(q[model->VelocityIndex("left_knee")], &L_left, &unused);
  test::SpecLegLength(q[model->VelocityIndex("right_knee")], &L_right, &unused);
  const Eigen::Vector3d com = CalcComPosition(*model, ws, q);
  const Eigen::VectorXd& f = plant->EvalOutput(pctx, "contact_forces");
  const Eigen::VectorXd& f_qp = controller->EvalOutput(cctx, "contact_forces");
  max_qp_plant_force_gap = (f - f_qp).cwiseAbs().maxCoeff();
  const double weight = model->total_mass() * 9.81;
  std::printf(
      "  %ld steps; L command %.4f m, L_left %.4f, L_right %.4f; COM xy error %.2e m; total F_z %.2f N vs m g %.2f N; "
      "min F_z %.1f N;\n"
      "  |v| %.2e; pelvis z %.4f m (nominal %.4f); QP vs plant force gap %.2e N; qp_failures %.0f\n",
      steps, L0 - crouch, L_left, L_right, (com.head<2>() - centre).norm(), f[2] + f[5], weight, min_fz, v.norm(), q[2],
      q0[2], max_qp_plant_force_gap, controller->EvalOutput(cctx, "qp_failures")[0]);
  EXPECT_GT(steps, 200);
  EXPECT_EQ(violations, 0);
  EXPECT_GT(min_fz, 0.0);
  EXPECT_EQ(controller->EvalOutput(cctx, "qp_failures")[0], 0.0);
  EXPECT_NEAR(L_left, L0 - crouch, 2e-3);
  EXPECT_NEAR(L_right, L0 - crouch, 2e-3);
  EXPECT_LT((com.head<2>() - centre).norm(), 5e-3);
  EXPECT_LT(v.norm(), 0.05);
  EXPECT_NEAR(f[2] + f[5], weight, 0.01 * weight);
  EXPECT_LT(q[2], q0[2] - 0.05);  // the pelvis went down with the legs
  EXPECT_LT(max_qp_plant_force_gap, 0.05 * weight);
}

// (Under the Jump outputs, starting from undeflected springs is a near free fall onto the springs: the virtual leg
// lengths and H_pitch leave the pelvis pitch free, and the first samples slip. The hopping diagram enters Jump only
// after settling under Landing; tests/diagrams/hopping/hopping_diagram_test.cc covers that.)
INSTANTIATE_TEST_SUITE_P(Domains, HoppingCrouch, ::testing::Values("landing"));

TEST(HoppingController, UpdateAllocatesNothingInAnyDomain) {
  auto model = LoadCassie();
  HybridContactPlant plant("plant", model, ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"),
                           Terrain::Flat());
  ClfQpController controller("clf", model, ActiveContactsPerMode(plant),
                             MakeHoppingOutputs(*model, test::SpecLegLength), HoppingQpParams(plant));
  auto context = controller.CreateDefaultLeafContext();
  const int nv = model->nv();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nv);
  x.head(nv) = model->q_nominal();
  const HoppingOutputLayout layout = MakeHoppingOutputLayout();
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(3 * layout.size);
  desired.segment(layout.leg_left, 2).setConstant(0.85);
  for (int i = 0; i < model->nu(); ++i) desired[layout.motors + i] = model->q_nominal()[model->actuators()[i].v_index];
  context->FixInputPort(0, x);
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, desired);
  const auto& update = controller.periodic_events().at(0).update;
  Eigen::VectorXd next = context->discrete_state();
  auto& mode = const_cast<int&>(controller.EvalTypedInput<int>(*context, 1));
  for (int m = 0; m < 3; ++m) {  // prime every domain's QP once
    mode = m;
    context->InvalidateCache();
    ASSERT_TRUE(update(*context, &next).ok());
  }
  long allocations = 0;
  for (int tick = 0; tick < 90; ++tick) {
    auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0));
    fixed[nv + 2] = -0.1 + 0.002 * tick;
    mode = (tick / 30) % 3;
    context->InvalidateCache();
    allocations += test::CountAllocations([&] { ASSERT_TRUE(update(*context, &next).ok()); });
  }
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace rome
