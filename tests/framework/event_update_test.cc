// Event-triggered updates, typed ports, context cloning and termination kinds (framework/system.h, simulator.h).
// Expected event times come from the bouncing ball's closed form (BouncingBall::AnalyticImpactTimes is the
// textbook formula t_k = t_0 + Σ 2 e^j v_0 / g, independent of the integrator).
#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/classic/bouncing_ball.h"

namespace rome {
namespace {

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-12;
  c.absolute_tolerance = 1e-12;
  return c;
}

// Counts guard events through an event update: xd = [count, time of the last event, ball height seen].
class EventCounter final : public LeafSystem {
 public:
  EventCounter(std::string name, EventTrigger trigger) : LeafSystem(std::move(name)) {
    DeclareInputPort("height", 1);
    DeclareDiscreteState(Eigen::Vector3d::Zero());
    DeclareEventUpdate("count", std::move(trigger), [this](const LeafContext& c, const EventRecord& e, State* next) {
      next->discrete[0] += 1;
      next->discrete[1] = e.time;
      next->discrete[2] = EvalInput(c, 0)[0];
      times_seen.push_back(c.time());
      return EventStatus::Succeeded();
    });
    DeclareOutputPort(
        "count", 1, [](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[0]; },
        Feedthrough::None());
  }
  mutable std::vector<double> times_seen;
};

// Copies an upstream counter's count in its own event update: it must see the count after the upstream update.
class Follower final : public LeafSystem {
 public:
  Follower() : LeafSystem("follower") {
    DeclareInputPort("count", 1);
    DeclareDiscreteState(Eigen::VectorXd::Zero(1));
    DeclareEventUpdate("copy", EventTrigger::AnyGuard(), [this](const LeafContext& c, const EventRecord&, State* next) {
      next->discrete[0] = EvalInput(c, 0)[0];
      return EventStatus::Succeeded();
    });
  }
};

struct BallDiagram {
  std::unique_ptr<Diagram> diagram;
  const BouncingBall* ball;
  const EventCounter* counter;
};

BallDiagram MakeBallDiagram(EventTrigger trigger, bool follower = false) {
  DiagramBuilder b;
  BallDiagram d;
  d.ball = b.AddSystem(std::make_unique<BouncingBall>(
      "ball", BouncingBallParams{.restitution = 0.8, .gravity = 9.81, .initial_height = 1.0}));
  b.AddSystem(std::make_unique<Demultiplexer>("demux", std::vector<int>{1, 1}));
  d.counter = b.AddSystem(std::make_unique<EventCounter>("counter", std::move(trigger)));
  b.Connect("ball", "state", "demux", "u");
  b.Connect("demux", "y0", "counter", "height");
  if (follower) {
    b.AddSystem(std::make_unique<Follower>());
    b.Connect("counter", "count", "follower", "count");
  }
  d.diagram = b.Build("balls");
  return d;
}

TEST(EventUpdate, CounterSeesExactlyTheGuardEventsAtTheirTimes) {
  BallDiagram d = MakeBallDiagram(EventTrigger::Guards({{"ball", "ground_contact"}}));
  Simulator sim(*d.diagram, Tight());
  BouncingBall reference("ref", {.restitution = 0.8, .gravity = 9.81, .initial_height = 1.0});
  const auto expected = reference.AnalyticImpactTimes(4);
  ASSERT_TRUE(sim.AdvanceTo(expected.back() + 0.01).ok());
  const LeafContext& cc = d.diagram->GetSubsystemContext(*d.counter, sim.get_context());
  EXPECT_EQ(cc.discrete_state()[0], 4.0);
  ASSERT_EQ(d.counter->times_seen.size(), 4u);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(d.counter->times_seen[k], expected[k], 1e-9) << "event " << k;
  EXPECT_NEAR(cc.discrete_state()[1], expected[3], 1e-9);
  EXPECT_NEAR(cc.discrete_state()[2], 0.0, 1e-9);  // the update reads the ball at the ground
}

TEST(EventUpdate, PrefixTriggerAndAnyGuardMatchTheSameEvents) {
  BallDiagram a = MakeBallDiagram(EventTrigger::Guards({{"ball", "ground_*"}}));
  BallDiagram b = MakeBallDiagram(EventTrigger::AnyGuard());
  Simulator sa(*a.diagram, Tight()), sb(*b.diagram, Tight());
  ASSERT_TRUE(sa.AdvanceTo(2.0).ok());
  ASSERT_TRUE(sb.AdvanceTo(2.0).ok());
  EXPECT_EQ(a.counter->times_seen.size(), static_cast<size_t>(sa.statistics().guard_events));
  EXPECT_EQ(a.counter->times_seen, b.counter->times_seen);
}

TEST(EventUpdate, LaterSystemsSeeEarlierEventUpdates) {
  BallDiagram d = MakeBallDiagram(EventTrigger::AnyGuard(), /*follower=*/true);
  Simulator sim(*d.diagram, Tight());
  ASSERT_TRUE(sim.AdvanceTo(1.5).ok());
  const LeafSystem& follower = d.diagram->GetLeafByPath("follower");
  const double count = d.diagram->GetSubsystemContext(*d.counter, sim.get_context()).discrete_state()[0];
  EXPECT_GE(count, 2.0);
  EXPECT_EQ(d.diagram->GetSubsystemContext(follower, sim.get_context()).discrete_state()[0], count);
}

TEST(EventUpdate, UnknownGuardOrSystemIsAOneLineError) {
  BallDiagram d = MakeBallDiagram(EventTrigger::Guards({{"ball", "touchdown"}}));
  try {
    Simulator sim(*d.diagram);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "system 'counter': event update 'count' names guard 'touchdown' of system 'ball', which has no such "
              "guard (it has "
              "'ground_contact')");
  }
  BallDiagram d2 = MakeBallDiagram(EventTrigger::Guards({{"plant", "ground_contact"}}));
  try {
    Simulator sim(*d2.diagram);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "system 'counter': event update 'count' names system 'plant', which is not in 'balls'");
  }
}

// ---- Typed ports ----

class ModeSource final : public LeafSystem {
 public:
  explicit ModeSource(int mode) : LeafSystem("source") {
    DeclareTypedOutputPort<int>(
        "mode", [mode](const LeafContext&, int* y) { *y = mode; }, Feedthrough::None());
  }
};
class ModeSink final : public LeafSystem {
 public:
  explicit ModeSink(bool typed) : LeafSystem("sink") {
    if (typed)
      DeclareTypedInputPort<int>("mode");
    else
      DeclareInputPort("mode", 1);
    DeclareOutputPort("twice", 1,
                      [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = 2.0 * EvalTypedInput<int>(c, 0); });
  }
};

TEST(TypedPorts, IntFlowsThroughAConnection) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<ModeSource>(3));
  auto* sink = b.AddSystem(std::make_unique<ModeSink>(true));
  b.Connect("source", "mode", "sink", "mode");
  auto d = b.Build("typed");
  auto ctx = d->CreateDefaultContext();
  EXPECT_EQ(sink->EvalOutput(d->GetSubsystemContext(*sink, *ctx), "twice")[0], 6.0);
}

TEST(TypedPorts, BuildRejectsATypeMismatchWordForWord) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<ModeSource>(1));
  b.AddSystem(std::make_unique<ModeSink>(false));
  b.Connect("source", "mode", "sink", "mode");
  try {
    b.Build("typed");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "DiagramBuilder::Build('typed'): type mismatch: output port 'mode' of system 'source' carries int but "
              "input port 'mode' of "
              "system 'sink' takes a vector of size 1");
  }
}

TEST(TypedPorts, ReadingAsTheWrongTypeNamesSystemPortAndTypes) {
  ModeSource source(2);
  auto ctx = source.CreateDefaultContext();
  EXPECT_EQ(source.EvalTypedOutput<int>(*ctx, "mode"), 2);
  try {
    source.EvalTypedOutput<double>(*ctx, "mode");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "system 'source': output port 'mode' carries int, not double");
  }
  try {
    source.EvalOutput(*ctx, "mode");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "system 'source': output port 'mode' carries int; read it with EvalTypedOutput<T>, not as a vector");
  }
  ModeSink sink(true);
  auto sctx = sink.CreateDefaultContext();
  EXPECT_THROW(sink.FixTypedInputPort(*sctx, 0, 1.5), std::invalid_argument);  // a double into an int port
  sink.FixTypedInputPort(*sctx, 0, 4);
  EXPECT_EQ(sink.EvalOutput(*sctx, "twice")[0], 8.0);
}

TEST(TypedPorts, LoggerReadsColumnsByElementName) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<BouncingBall>("ball", BouncingBallParams{}));
  b.AddSystem(std::make_unique<ModeSource>(5));
  auto* logger = AddVectorLogger(b, "logger", {{"ball", "state"}, {"source", "mode"}}, 0.1);
  auto d = b.Build("log");
  Simulator sim(*d);
  ASSERT_TRUE(sim.AdvanceTo(0.35).ok());
  const auto& log = logger->log(d->GetSubsystemContext(*logger, sim.get_context()));
  ASSERT_EQ(log.times.size(), 4u);
  const int mode_col = logger->ColumnIndex("source.mode");
  for (const auto& row : log.samples) EXPECT_EQ(row[mode_col], 5.0);
  EXPECT_THROW(logger->ColumnIndex("ball.nothing"), std::runtime_error);
}

// ---- Context cloning ----

TEST(ContextClone, BranchesAreIndependentAndReproduceEachOther) {
  BallDiagram d = MakeBallDiagram(EventTrigger::AnyGuard(), /*follower=*/true);
  Simulator sim(*d.diagram, Tight());
  ASSERT_TRUE(sim.AdvanceTo(0.7).ok());  // after the first impact (t ≈ 0.4515 s)
  const auto& ball_ctx = d.diagram->GetSubsystemContext(*d.ball, sim.get_context());
  const Eigen::VectorXd x_at_branch = ball_ctx.continuous_state();
  Simulator a(*d.diagram, sim.get_context().Clone(), Tight());
  Simulator b(*d.diagram, sim.get_context().Clone(), Tight());
  ASSERT_TRUE(a.AdvanceTo(2.0).ok());
  // The original is untouched by the branch.
  EXPECT_EQ(sim.get_context().time(), 0.7);
  EXPECT_EQ(ball_ctx.continuous_state(), x_at_branch);
  ASSERT_TRUE(b.AdvanceTo(2.0).ok());
  const auto& xa = d.diagram->GetSubsystemContext(*d.ball, a.get_context()).continuous_state();
  const auto& xb = d.diagram->GetSubsystemContext(*d.ball, b.get_context()).continuous_state();
  EXPECT_EQ(xa, xb);
  EXPECT_EQ(a.statistics().guard_events, b.statistics().guard_events);
  // The branch continues the original run: same state as running the original on.
  ASSERT_TRUE(sim.AdvanceTo(2.0).ok());
  EXPECT_NEAR((ball_ctx.continuous_state() - xa).norm(), 0.0, 1e-9);
  // The clone's counter went on from the original's count at the branch (1 impact before 0.7 s).
  const double count_a = d.diagram->GetSubsystemContext(*d.counter, a.get_context()).discrete_state()[0];
  const double count_orig = d.diagram->GetSubsystemContext(*d.counter, sim.get_context()).discrete_state()[0];
  EXPECT_EQ(count_a, count_orig);
  EXPECT_GE(count_a, 3.0);
}

// ---- Termination kinds ----

class Ender final : public LeafSystem {
 public:
  Ender(double at, bool fail) : LeafSystem("ender") {
    DeclarePeriodicPublish(at, at, [fail](const LeafContext&) {
      return fail ? EventStatus::Failed("robot fell") : EventStatus::ReachedTermination("goal reached");
    });
  }
};

TEST(SimulatorStatus, TellsSuccessFailureAndLimitApart) {
  Ender success(0.5, false), failure(0.5, true);
  Simulator s1(success), s2(failure), s3(success);
  const SimulatorStatus a = s1.AdvanceTo(1.0), b = s2.AdvanceTo(1.0), c = s3.AdvanceTo(0.2);
  EXPECT_EQ(a.kind(), SimulatorStatus::Kind::kSuccess);
  EXPECT_EQ(a.kind_name(), "success");
  EXPECT_EQ(b.kind(), SimulatorStatus::Kind::kFailure);
  EXPECT_EQ(b.kind_name(), "failure");
  EXPECT_EQ(b.time, 0.5);
  EXPECT_EQ(c.kind(), SimulatorStatus::Kind::kLimit);
  EXPECT_EQ(c.kind_name(), "limit");
}

}  // namespace
}  // namespace rome
