// controllers_benchmark: µs per TaskSpaceQpController update on AMBER (tasks, M, h, contact Jacobian, QP assembly,
// warm-started DenseQpSolver solve, GRF extraction), in single support (paper outputs, Eq. (19)) and double support.
//   ./controllers_benchmark
#include <cmath>

#include <benchmark/benchmark.h>

#include "systems/controllers/task_space_qp_controller.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

void Run(benchmark::State& state, bool double_support) {
  auto model = test::LoadRobot("amber");
  const ContactSet set = double_support ? (ContactBit(0) | ContactBit(1)) : ContactBit(0);
  std::vector<std::shared_ptr<const TaskSpaceTask>> tasks =
      double_support ? std::vector<std::shared_ptr<const TaskSpaceTask>>{std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                                                                          std::make_shared<BodyPitchTask>("torso_pitch", *model, "torso")}
                     : test::AmberWalkingTasks(*model);
  TaskSpaceQpController controller("tsc", model, {set}, tasks);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = double_support ? test::AmberDoubleSupportPose(*model) : test::AmberSingleSupportPose(*model);
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

void BM_AmberSingleSupport(benchmark::State& state) { Run(state, false); }
void BM_AmberDoubleSupport(benchmark::State& state) { Run(state, true); }
BENCHMARK(BM_AmberSingleSupport)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AmberDoubleSupport)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
