// TaskSpaceQpController: the periodic update (tasks, M, h, J, QP assembly, warm-started solve, GRF extraction)
// allocates no heap memory once the context exists. Global operator new and, outside sanitizer builds, glibc's
// malloc family are replaced in this binary and count allocations while updates run. Kept in its own binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "systems/controllers/task_space_qp_controller.h"
#include "tests/systems/controllers/amber_test_setup.h"

#include "tests/common/allocation_counter.h"  // replaces operator new/malloc in this binary

namespace rome {
namespace {

// Fixes the controller's inputs (state, mode 0, desired outputs) and runs one update, which sizes everything lazily
// built. Returns the next discrete state to reuse.
Eigen::VectorXd FixInputsAndPrime(const TaskSpaceQpController& controller, LeafContext& context,
                                  const Eigen::VectorXd& x, const Eigen::VectorXd& desired) {
  context.FixInputPort(0, x);
  context.FixAbstractInputPort(1, std::any(0));
  context.FixInputPort(2, desired);
  Eigen::VectorXd next = context.discrete_state();
  EXPECT_TRUE(controller.periodic_events().at(0).update(context, &next).ok());
  return next;
}

TEST(TaskSpaceQpControllerAllocation, CountingWorks) {
  static double* volatile sink = nullptr;
  EXPECT_EQ(rome::test::CountAllocations([] { sink = new double[16]; }), 1);
  delete[] sink;
}

// With and without predict_hold_drift (its forward dynamics at the held u run from the second tick of each mode on:
// the time advances by one period per tick and each answer is held).
class TaskSpaceQpControllerAllocationDrift : public ::testing::TestWithParam<bool> {};

TEST_P(TaskSpaceQpControllerAllocationDrift, PeriodicUpdateDoesNotAllocate) {
  auto model = test::LoadRobot("amber");
  // Two modes (left stance, double support): the update switches between their QPs.
  const ContactSet left = ContactBit(0), both = ContactBit(0) | ContactBit(1);
  const auto tasks = test::AmberWalkingTasks(*model);
  TaskSpaceQpParams params;
  params.predict_hold_drift = GetParam();
  TaskSpaceQpController controller("tsc", model, {left, both}, tasks, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q_ss = test::AmberSingleSupportPose(*model), q_ds = test::AmberDoubleSupportPose(*model);
  Eigen::VectorXd x_ss(14), x_ds(14), v = Eigen::VectorXd::Zero(7);
  x_ss << q_ss, v;
  x_ds << q_ds, v;
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(12);
  desired.head(4) = test::TaskValues(*model, tasks, q_ss, v) + Eigen::Vector4d(0.02, -0.01, 0.03, 0.02);
  Eigen::VectorXd next = FixInputsAndPrime(controller, *context, x_ss, desired);
  const auto& update = controller.periodic_events().at(0).update;
  long allocations = 0;
  for (int tick = 0; tick < 200; ++tick) {
    // Change the state in place (a fixed input keeps its storage) and switch modes every 50 ticks.
    auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0));
    const bool ds = (tick / 50) % 2 == 1;
    fixed = ds ? x_ds : x_ss;
    fixed[7 + 3] = 0.1 * std::sin(0.1 * tick);  // hip velocity, so J̇q̇ and the PD terms change
    auto& mode = const_cast<int&>(controller.EvalTypedInput<int>(*context, 1));
    mode = ds ? 1 : 0;
    context->SetTime(params.update_period_s * (tick + 1));
    context->get_mutable_discrete_state() = next;  // the answer is held, as the simulator does
    context->InvalidateCache();
    g_allocations = 0;
    g_counting = true;
    const EventStatus status = update(*context, &next);
    g_counting = false;
    allocations += g_allocations;
    ASSERT_TRUE(status.ok()) << status.message;
    ASSERT_EQ(controller.last_qp(*context).status(), QpStatus::kOptimal)
        << controller.last_qp(*context).status_message();
  }
  EXPECT_EQ(allocations, 0);
}
INSTANTIATE_TEST_SUITE_P(HoldDrift, TaskSpaceQpControllerAllocationDrift, ::testing::Bool());

TEST(TaskSpaceQpControllerAllocation, RelaxedFallbackDoesNotAllocate) {
  // An unattainable normal-force bound makes every QP infeasible; the fallback re-solves without the GRF rows.
  auto model = test::LoadRobot("amber");
  const auto tasks = test::AmberWalkingTasks(*model);
  TaskSpaceQpParams params;
  params.min_normal_force_N = 3.0 * model->total_mass() * 9.81;
  TaskSpaceQpController controller("tsc", model, {ContactBit(0)}, tasks, params);
  auto context = controller.CreateDefaultLeafContext();
  const Eigen::VectorXd q = test::AmberSingleSupportPose(*model), v = Eigen::VectorXd::Zero(7);
  Eigen::VectorXd x(14);
  x << q, v;
  Eigen::VectorXd desired = Eigen::VectorXd::Zero(12);
  desired.head(4) = test::TaskValues(*model, tasks, q, v);
  Eigen::VectorXd next = FixInputsAndPrime(controller, *context, x, desired);
  const auto& update = controller.periodic_events().at(0).update;
  long allocations = 0;
  for (int tick = 0; tick < 50; ++tick) {
    auto& fixed = const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0));
    fixed[7 + 3] = 0.1 * std::sin(0.1 * tick);
    context->InvalidateCache();
    EventStatus status;
    allocations += test::CountAllocations([&] { status = update(*context, &next); });
    ASSERT_TRUE(status.ok()) << status.message;
  }
  context->get_mutable_discrete_state() = next;
  EXPECT_EQ(controller.diagnostics(*context).relaxed, 51);
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace rome
