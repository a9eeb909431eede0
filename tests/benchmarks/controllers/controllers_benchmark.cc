// controllers_benchmark: µs per controller update (outputs, M, h, contact Jacobian, QP assembly, warm-started
// DenseQpSolver solve, GRF extraction):
//   TaskSpaceQpController on AMBER, single support (paper outputs, Eq. (19)) and double support;
//   ClfQpController on AMBER single support (the same outputs, both formulations) and on the 18-DOF exoskeleton in
//   double support on flat feet (COM and pelvis roll/pitch/yaw, both formulations); ClfQpController on 3D Cassie with
//   the hopping outputs and the augmented input in each domain (Jump with H_pitch, Landing, Flight).
//   ./controllers_benchmark
#include <cmath>

#include <benchmark/benchmark.h>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/multibody/multibody_kinematics.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

void Run(benchmark::State& state, bool double_support) {
  auto model = test::LoadRobot("amber");
  const ContactSet set = double_support ? (ContactBit(0) | ContactBit(1)) : ContactBit(0);
  std::vector<std::shared_ptr<const TaskSpaceTask>> tasks =
      double_support
          ? std::vector<std::shared_ptr<const TaskSpaceTask>>{std::make_shared<ComPositionTask>(
                                                                  "com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                                                              std::make_shared<BodyPitchTask>("torso_pitch", *model,
                                                                                              "torso")}
          : test::AmberWalkingTasks(*model);
  TaskSpaceQpController controller("tsc", model, {set}, tasks);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q =
      double_support ? test::AmberDoubleSupportPose(*model) : test::AmberSingleSupportPose(*model);
  Eigen::VectorXd x(14);
  x << q, Eigen::VectorXd::Zero(7);
  const int ny = controller.num_task_outputs();
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(3 * ny);
  desired.head(ny) = test::TaskValues(*model, tasks, q, Eigen::VectorXd::Zero(7)) + Eigen::VectorXd::Constant(ny, 0.01);
  context->FixInputPort(0, x);
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, desired);
  const auto& update = controller.periodic_events().at(0).update;
  Eigen::VectorXd next = context->discrete_state();
  auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0));
  int tick = 0;
  for (auto _ : state) {
    fixed[7 + 3] = 0.1 * std::sin(0.01 * ++tick);  // a new state each tick (no kinematics caching across ticks)
    fixed[2] = 0.01 * std::cos(0.01 * tick);
    context->InvalidateCache();
    benchmark::DoNotOptimize(update(*context, &next));
  }
  state.counters["qp_iterations"] = controller.last_qp(*context).iterations();
}

// A new state each tick: `perturb` writes small changes into the fixed state input.
template <class Controller>
void Loop(benchmark::State& state, const Controller& controller, LeafContext& context, int nv) {
  const auto& update = controller.periodic_events().at(0).update;
  Eigen::VectorXd next = context.discrete_state();
  auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(context, 0));
  const Eigen::VectorXd x0 = fixed;
  int tick = 0;
  for (auto _ : state) {
    ++tick;
    fixed[nv + 1] = x0[nv + 1] + 0.01 * std::sin(0.01 * tick);
    fixed[2] = x0[2] + 0.001 * std::cos(0.01 * tick);
    context.InvalidateCache();
    benchmark::DoNotOptimize(update(context, &next));
  }
  state.counters["qp_iterations"] = controller.last_qp(context).iterations();
  context.get_mutable_discrete_state() = next;
  state.counters["qp_failures"] = controller.EvalOutput(context, "qp_failures")[0];
}

void ClfAmber(benchmark::State& state, ClfQpFormulation formulation) {
  auto model = test::LoadRobot("amber");
  const auto tasks = test::AmberWalkingTasks(*model);
  std::vector<ClfOutput> outputs;
  for (const auto& t : tasks) outputs.push_back(ClfOutput::RelativeDegreeTwo(t));
  ClfQpParams params;
  params.formulation = formulation;
  params.epsilon = 0.03;
  ClfQpController controller("clf", model, {ContactBit(0)}, outputs, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = test::AmberSingleSupportPose(*model);
  Eigen::VectorXd x(14);
  x << q, Eigen::VectorXd::Zero(7);
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(12);
  desired.head(4) = test::TaskValues(*model, tasks, q, Eigen::VectorXd::Zero(7)) + Eigen::VectorXd::Constant(4, 0.01);
  context->FixInputPort(0, x);
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, desired);
  Loop(state, controller, *context, 7);
}

void ClfExoskeleton(benchmark::State& state, ClfQpFormulation formulation) {
  auto model = test::LoadRobot("exoskeleton");
  const ContactSet both = ContactBit(model->ContactIndex("left_foot")) | ContactBit(model->ContactIndex("right_foot"));
  std::vector<ClfOutput> outputs = {
      ClfOutput::RelativeDegreeTwo(
          std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kY, Axis::kZ})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("roll", *model, "base_roll")),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pitch", *model, "base_pitch")),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("yaw", *model, "base_yaw"))};
  ClfQpParams params;
  params.formulation = formulation;
  params.contact.min_normal_force_N = 20.0;
  ClfQpController controller("clf", model, {both}, outputs, params);
  auto context = controller.CreateDefaultLeafContext();
  const int nv = model->nv();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nv);
  x.head(nv) = model->q_nominal();
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(18);
  desired.head(3) = CalcComPosition(*model, ws, model->q_nominal()) + Eigen::Vector3d(0.01, 0.02, -0.01);
  context->FixInputPort(0, x);
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, desired);
  Loop(state, controller, *context, nv);
}

// Cassie (22 DOF, springs, achilles rods) with the hopping outputs (diagrams/hopping) and the augmented input [u; F]
// (hopping Eq. (45)-(51)): 10 torques + 12 constraint forces (two line feet, two rods) + δ; domain `mode`.
void ClfCassieHopping(benchmark::State& state, int mode) {
  auto model = test::LoadRobot("cassie");
  HybridContactPlant plant("plant", model, ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"),
                           Terrain::Flat());
  const LegLengthTable leg_length(*model);
  HoppingOutputParams outputs;
  outputs.jump_tracks_momentum = mode == HoppingDomain::kJump;  // the paper's Jump set (H_pitch) in the jump case
  ClfQpParams params = HoppingDiagramParams::DefaultControllerParams();
  params.contact_stabilization = plant.params().dynamics;
  ClfQpController controller("clf", model, ActiveContactsPerMode(plant),
                             MakeHoppingOutputs(*model, leg_length, outputs), params);
  const HoppingOutputLayout layout = MakeHoppingOutputLayout(outputs);
  auto context = controller.CreateDefaultLeafContext();
  const int nv = model->nv();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nv);
  x.head(nv) = model->q_nominal();
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(3 * layout.size);
  desired.segment(layout.leg_left, 2).setConstant(0.85);
  for (int i = 0; i < model->nu(); ++i)
    desired[layout.motors + i] = model->q_nominal()[model->actuators()[i].v_index] + 0.01;
  context->FixInputPort(0, x);
  context->FixAbstractInputPort(1, std::any(mode));
  context->FixInputPort(2, desired);
  Loop(state, controller, *context, nv);
}

void BM_AmberSingleSupport(benchmark::State& state) { Run(state, false); }
void BM_ClfQpCassieHoppingJumpAugmented(benchmark::State& state) { ClfCassieHopping(state, HoppingDomain::kJump); }
void BM_ClfQpCassieHoppingLandingAugmented(benchmark::State& state) {
  ClfCassieHopping(state, HoppingDomain::kLanding);
}
void BM_ClfQpCassieHoppingFlightAugmented(benchmark::State& state) { ClfCassieHopping(state, HoppingDomain::kFlight); }
void BM_ClfQpAmberSingleSupportEliminated(benchmark::State& state) {
  ClfAmber(state, ClfQpFormulation::kEliminateContactForces);
}
void BM_ClfQpAmberSingleSupportAugmented(benchmark::State& state) {
  ClfAmber(state, ClfQpFormulation::kAugmentedInput);
}
void BM_ClfQpExoskeletonDoubleSupportEliminated(benchmark::State& state) {
  ClfExoskeleton(state, ClfQpFormulation::kEliminateContactForces);
}
void BM_ClfQpExoskeletonDoubleSupportAugmented(benchmark::State& state) {
  ClfExoskeleton(state, ClfQpFormulation::kAugmentedInput);
}
BENCHMARK(BM_ClfQpAmberSingleSupportEliminated)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClfQpCassieHoppingJumpAugmented)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClfQpCassieHoppingLandingAugmented)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClfQpCassieHoppingFlightAugmented)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClfQpAmberSingleSupportAugmented)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClfQpExoskeletonDoubleSupportEliminated)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ClfQpExoskeletonDoubleSupportAugmented)->Unit(benchmark::kMicrosecond);
void BM_AmberDoubleSupport(benchmark::State& state) { Run(state, true); }
BENCHMARK(BM_AmberSingleSupport)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AmberDoubleSupport)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
