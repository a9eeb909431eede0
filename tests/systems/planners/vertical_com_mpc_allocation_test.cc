// VerticalComMpc::Solve() and VerticalComMpcSystem's periodic update allocate no heap memory once constructed.
// Global operator new (and, outside sanitizer builds, malloc/calloc/realloc, which Eigen uses) are replaced in
// this test binary and count calls while the hot path runs.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "systems/planners/vertical_com_mpc.h"
#include "systems/planners/vertical_com_mpc_system.h"

#include "tests/common/allocation_counter.h"  // replaces operator new/malloc in this binary

namespace rome {
namespace {

using rome::test::CountAllocations;

TEST(VerticalComMpcAllocation, CounterSeesAllocations) {
  const long n = CountAllocations([] {
    Eigen::VectorXd v(1000);
    v.setZero();
    std::vector<int> w(10);
    (void)w;
  });
  EXPECT_GE(n, 1);
}

TEST(VerticalComMpcAllocation, SolveDoesNotAllocate) {
  for (auto terminal :
       {VerticalComMpcParams::TerminalCondition::kEquality, VerticalComMpcParams::TerminalCondition::kWeightedCost}) {
    VerticalComMpcParams params;
    params.terminal_condition = terminal;
    VerticalComMpc mpc(params);
    QpStatus s1, s2, s3, s4;
    const long n = CountAllocations([&] {
      s1 = mpc.Solve(0.82, -0.05, 0.80, 0.25, 0.35);  // cold, unconstrained
      s2 = mpc.Solve(0.80, 0.5, 0.735, -1.5, 0.3);    // contact constraint active
      s3 = mpc.Solve(0.80, 0.5, 0.735, -1.5, 0.299);  // warm
      s4 = mpc.Solve(0.8, 2.0, 0.8, -3.0, 0.3);       // infeasible for the equality version: relaxed
    });
    EXPECT_EQ(n, 0);
    EXPECT_EQ(s1, QpStatus::kOptimal);
    EXPECT_EQ(s2, QpStatus::kOptimal);
    EXPECT_EQ(s3, QpStatus::kOptimal);
    EXPECT_EQ(s4, QpStatus::kOptimal);  // relaxed terminal for the equality version
    EXPECT_EQ(mpc.terminal_relaxed(), terminal == VerticalComMpcParams::TerminalCondition::kEquality);
  }
}

TEST(VerticalComMpcAllocation, PeriodicUpdateDoesNotAllocate) {
  VerticalComMpcSystem system("mpc");
  auto context = system.CreateDefaultLeafContext();
  system.FixInputPort(*context, 0, Eigen::Vector2d(0.80, 0.5));
  system.FixInputPort(*context, 1, Eigen::Vector3d(0.735, -1.5, 0.3));
  Eigen::VectorXd next = context->discrete_state();
  const auto& update = system.periodic_events().at(0).update;
  EventStatus status;
  const long n = CountAllocations([&] {
    for (int k = 0; k < 5; ++k) {
      context->SetTime(1e-3 * k);
      next = context->discrete_state();
      status = update(*context, &next);
    }
  });
  EXPECT_EQ(n, 0);
  EXPECT_TRUE(status.ok());
  EXPECT_EQ(next[VerticalComMpcSystem::kFailures], 0.0);
  EXPECT_EQ(next[VerticalComMpcSystem::kLastStatus], 0.0);
}

}  // namespace
}  // namespace rome
