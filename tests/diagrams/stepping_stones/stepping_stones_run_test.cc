// RunSteppingStones: build → run → result in the few lines of the header, and the success rule: the supervisor's
// planned end is a success, the time limit is not, a missed stone is a failure.
#include "diagrams/stepping_stones/stepping_stones_run.h"

#include <gtest/gtest.h>

namespace rome {
namespace {

TEST(SteppingStonesRun, BuildRunResult) {
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 6;
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 8), params);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  // A monitor of the caller's own: it sees every accepted step of the run, and stays after it (the run removes only its
  // own).
  long user_monitor_calls = 0;
  sim.add_monitor([&](const Context&) { return ++user_monitor_calls, EventStatus::Succeeded(); }, "user");
  const SteppingStonesResult r = RunSteppingStones(d, sim);
  EXPECT_EQ(sim.num_monitors(), 1);
  // Every accepted step but the last: the supervisor ends the run at that step's touchdown, before the monitors run.
  EXPECT_EQ(user_monitor_calls, r.integrator.steps - 1);

  ASSERT_TRUE(r.success) << r.status.ToString();
  EXPECT_EQ(r.status.kind_name(), "success");
  EXPECT_EQ(r.status.message, "completed 6 steps");
  ASSERT_EQ(r.steps.size(), 6u);
  EXPECT_FALSE(r.fell);
  EXPECT_EQ(r.contact.violations, 0);
  EXPECT_GT(r.contact.samples, 1000);
  // The run ends at the 6th touchdown (the supervisor's planned end), not at the time limit.
  EXPECT_NEAR(r.sim_time_s, r.steps.back().start_time_s + r.steps.back().duration_s, 1e-12);
  // The COM starts initial_com_x_m from the first stone's centre (SteppingStonesInitialState) and ends near the stone
  // of the 6th step (x = 6 × 0.4 m, within one step).
  EXPECT_NEAR(r.x_start_m, params.initial_com_x_m, 1e-9);
  EXPECT_NEAR(r.x_end_m, 2.4, 0.4);
  EXPECT_NEAR(r.mean_forward_speed_mps(), (r.x_end_m - r.x_start_m) / r.sim_time_s, 1e-12);
  for (const StepRecord& s : r.steps) EXPECT_LE(s.foothold_error_m, r.max_foothold_error_m);
  EXPECT_LT(r.max_foothold_error_m, 0.02);
  EXPECT_EQ(r.controller_kind, "TaskSpaceQpController");
  EXPECT_EQ(r.integrator.guard_events, static_cast<long>(r.integrator.events.size()));
}

TEST(SteppingStonesRun, TimeLimitIsNoSuccessAndAMissedStoneIsAFailure) {
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 6;
  {
    SteppingStonesDiagram d = BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 8), params);
    Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
    SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
    SteppingStonesRunOptions options;
    options.max_time_s = 1.0;
    const SteppingStonesResult r = RunSteppingStones(d, sim, options);
    EXPECT_FALSE(r.success);
    EXPECT_EQ(r.status.kind_name(), "limit");
    EXPECT_EQ(r.status.message, "reached the time limit t = 1 s");
    EXPECT_EQ(r.sim_time_s, 1.0);
    EXPECT_LT(r.steps.size(), 6u);
  }
  // E* = 4 m²/s² (eight times the paper's) on random stones (seed 1): the robot overshoots its stone.
  params.target_orbital_energy = 4.0;
  params.supervisor.max_steps = 10;
  RandomSteppingStonesParams stones;
  stones.num_stones = 12;
  stones.seed = 1;
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(RandomSteppingStones(stones), params);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  const SteppingStonesResult r = RunSteppingStones(d, sim);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.status.kind_name(), "failure");
  EXPECT_FALSE(r.fell);
  EXPECT_NE(r.status.message.find("missed its stone"), std::string::npos) << r.status.message;
  ASSERT_FALSE(r.steps.empty());
  EXPECT_NE(r.steps.back().stone, r.steps.back().planned_stone);
}

}  // namespace
}  // namespace rome
