// HybridContactPlant contact events against closed forms: lift-off of a ball on a table pulled down faster than g,
// slip of a block pushed sideways, a graph with no mode to lift off into, touchdown from flight.
#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/plants/contact_force_statistics.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kG = 9.81;  // MultibodyModel gravity [m/s^2]

std::shared_ptr<const MultibodyModel> LoadTestModel(const std::string& robot) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("tests/systems/plants/data/" + robot + ".rome.json"), {.euler_floating_base = true}));
}

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-10;
  c.absolute_tolerance = 1e-12;
  return c;
}

// One contact, "stance" (in contact) and "flight" (none); no lift-off transition (the plant finds "flight" as the
// mode with the remaining contacts), touchdown back to stance if asked.
ContactModeGraph StanceFlight(const std::string& contact, bool with_touchdown) {
  ContactModeGraph g;
  g.modes = {{"stance", {contact}}, {"flight", {}}};
  if (with_touchdown) g.transitions = {{"flight", "stance", ContactModeGraph::Kind::kTouchdown, contact}};
  g.initial_mode = "stance";
  return g;
}

struct RampDiagram {
  std::unique_ptr<Diagram> diagram;
  const HybridContactPlant* plant = nullptr;
};

// Plant driven by u(t) = rate * t on its single actuator.
RampDiagram BuildRamp(std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph, double rate) {
  DiagramBuilder b;
  RampDiagram d;
  d.plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, std::move(graph), Terrain::Flat()));
  b.AddSystem(std::make_unique<TrajectorySource>(
      "ramp", 1, [rate](double t, Eigen::Ref<Eigen::VectorXd> out) { out[0] = rate * t; }));
  b.Connect("ramp", "y", "plant", "u");
  d.diagram = b.Build("ramp_diagram");
  return d;
}

// In the table's frame, a table accelerating downwards with a(t) = j t adds the fictitious force m j t upwards on
// the ball: u(t) = m j t. Normal force m (g - j t) reaches 0 at t* = g / j; afterwards z'' = j (t - t*).
TEST(ContactEvents, BallLiftsOffAPulledDownTableAtGOverJ) {
  auto model = LoadTestModel("ball_on_table");
  const double m = 2.0, j = 30.0, t_star = kG / j;
  RampDiagram d = BuildRamp(model, StanceFlight("ball", false), m * j);
  SimulatorConfig config = Tight();
  config.max_step_s =
      0.01;  // the stance is a linear problem: without a cap there are only a couple of steps to monitor
  Simulator sim(*d.diagram, config);
  const LeafContext& ctx = d.diagram->GetSubsystemContext(*d.plant, sim.get_context());
  const int stance = d.plant->GetModeIndex("stance"), flight = d.plant->GetModeIndex("flight");
  double min_fn = std::numeric_limits<double>::infinity(), worst_fn_error = 0;
  int stance_steps = 0;
  sim.set_monitor([&](const Context&) {
    if (ctx.mode() != stance) return EventStatus::Succeeded();
    const Eigen::VectorXd& f = d.plant->EvalOutput(ctx, "contact_forces");
    min_fn = std::min(min_fn, f[2]);
    worst_fn_error = std::max(worst_fn_error, std::abs(f[2] - m * (kG - j * ctx.time())));
    ++stance_steps;
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(t_star + 0.2);
  ASSERT_TRUE(status.ok()) << status.ToString();
  ASSERT_EQ(sim.statistics().events.size(), 1u);
  const EventRecord& ev = sim.statistics().events[0];
  EXPECT_EQ(ev.guard, "liftoff_ball");
  EXPECT_EQ(ev.mode_before, stance);
  EXPECT_EQ(ev.mode_after, flight);
  EXPECT_NEAR(ev.time, t_star, 1e-9);
  std::printf("lift-off at t = %.15f s, g/j = %.15f s, error %.3e s\n", ev.time, t_star, ev.time - t_star);
  EXPECT_GE(stance_steps, 30);
  EXPECT_GE(min_fn, 0.0);
  EXPECT_LT(worst_fn_error, 1e-9 * m * kG);
  // Free flight after the lift-off: z - z0 = j (t - t*)^3 / 6.
  const double tau = ctx.time() - t_star;
  EXPECT_EQ(ctx.mode(), flight);
  EXPECT_NEAR(ctx.continuous_state()[0] - 0.1, j * tau * tau * tau / 6, 1e-8);
  EXPECT_EQ(d.plant->EvalOutput(ctx, "contact_forces").norm(), 0.0);
}

// Block (2 kg, mu = 0.5) pushed sideways with u = k t: |F_t| = k t, F_n = m g, slip at t = mu m g / k.
TEST(ContactEvents, PushedBlockSlipsWhenThePushReachesMuTimesTheWeight) {
  auto model = LoadTestModel("pushed_block");
  const double m = 2.0, mu = 0.5, k = 4.0, t_slip = mu * m * kG / k;
  ASSERT_EQ(model->contacts()[0].friction_coefficient, mu);
  RampDiagram d = BuildRamp(model, StanceFlight("block_bottom", false), k);
  Simulator sim(*d.diagram, Tight());
  const LeafContext& ctx = d.diagram->GetSubsystemContext(*d.plant, sim.get_context());
  double worst = 0;
  sim.set_monitor([&](const Context&) {
    const Eigen::VectorXd& f = d.plant->EvalOutput(ctx, "contact_forces");
    worst = std::max({worst, std::abs(f[0] + k * ctx.time()), std::abs(f[1]), std::abs(f[2] - m * kG)});
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(2 * t_slip);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << status.ToString();
  EXPECT_EQ(status.system, "plant");
  EXPECT_NEAR(status.time, t_slip, 1e-9);
  std::printf("slip at t = %.15f s, mu m g / k = %.15f s, error %.3e s\n", status.time, t_slip, status.time - t_slip);
  EXPECT_EQ(status.message,
            "'block_bottom' slipped at t = 2.4525 s: |F_t|/F_n = 0.5 reached the friction coefficient mu = 0.5 (|F_t| "
            "= 9.81 N, "
            "F_n = 19.62 N)");
  ASSERT_EQ(sim.statistics().events.size(), 1u);
  EXPECT_EQ(sim.statistics().events[0].guard, "slip");
  EXPECT_EQ(sim.statistics().events[0].component, 0);
  EXPECT_LT(worst, 1e-9 * m * kG);
}

// The same block lifted with u_z = m g t / T while a tiny constant push c holds sideways: |F_t| = c, F_n = m g (1 -
// t/T), so |F_t| reaches mu F_n at t = T (1 - c / (mu m g)), an instant before F_n reaches 0. The run ends as a slip,
// and the message says the contact was unloading (the ratio of two near-zero forces alone reads like a violent slip).
TEST(ContactEvents, AContactUnloadingWithATangentialForceLeftSlipsAtTheConesApexAndSaysSo) {
  auto model = LoadTestModel("lifted_block");
  const double m = 2.0, mu = 0.5, c = 1e-9, T = 1.0, t_slip = T * (1 - c / (mu * m * kG));
  ASSERT_EQ(model->actuators().size(), 2u);
  DiagramBuilder b;
  b.AddSystem(
      std::make_unique<HybridContactPlant>("plant", model, StanceFlight("block_bottom", false), Terrain::Flat()));
  b.AddSystem(std::make_unique<TrajectorySource>("ramp", 2, [&](double t, Eigen::Ref<Eigen::VectorXd> out) {
    out[0] = c;
    out[1] = m * kG * t / T;
  }));
  b.Connect("ramp", "y", "plant", "u");
  auto diagram = b.Build("lifted_block");
  Simulator sim(*diagram, Tight());
  const SimulatorStatus status = sim.AdvanceTo(2 * T);
  ASSERT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << status.ToString();
  EXPECT_EQ(status.system, "plant");
  EXPECT_NEAR(status.time, t_slip, 1e-9);
  EXPECT_EQ(sim.statistics().events.back().guard, "slip");
  EXPECT_NE(status.message.find("'block_bottom' slipped"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("the contact was unloading"), std::string::npos) << status.message;
  std::printf("%s\n", status.message.c_str());
}

TEST(ContactEvents, LiftOffWithNoModeToLiftOffIntoFails) {
  auto model = LoadTestModel("ball_on_table");
  ContactModeGraph graph;
  graph.modes = {{"stance", {"ball"}}};
  const double m = 2.0, j = 30.0;
  RampDiagram d = BuildRamp(model, graph, m * j);
  Simulator sim(*d.diagram, Tight());
  const SimulatorStatus status = sim.AdvanceTo(1.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << status.ToString();
  EXPECT_EQ(status.system, "plant");
  EXPECT_NEAR(status.time, kG / j, 1e-9);
  EXPECT_EQ(status.message,
            "'ball' lifted off at t = 0.327 s (normal force 0 N in mode 'stance'), but the contact-mode graph has no "
            "mode to lift off into");
}

// Ball released h above the ground in flight (u = 0): touchdown at sqrt(2 h / g), plastic impact, then at rest.
TEST(ContactEvents, BallTouchesDownFromFlightAtTheFreeFallTime) {
  auto model = LoadTestModel("ball_on_table");
  HybridContactPlant plant("plant", model, StanceFlight("ball", true), Terrain::Flat());
  auto context = plant.CreateDefaultLeafContext();
  const double h = 0.3, t_td = std::sqrt(2 * h / kG);
  ASSERT_GT(t_td, plant.params().min_time_in_mode_s);  // SetState holds the guard for min_time_in_mode_s
  plant.SetState(*context, Eigen::VectorXd::Constant(1, 0.1 + h), Eigen::VectorXd::Zero(1), "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(1));
  const LeafContext* ctx = context.get();
  Simulator sim(plant, std::move(context), Tight());
  const SimulatorStatus status = sim.AdvanceTo(t_td + 0.2);
  ASSERT_TRUE(status.ok()) << status.ToString();
  ASSERT_EQ(sim.statistics().events.size(), 1u);
  const EventRecord& ev = sim.statistics().events[0];
  EXPECT_EQ(ev.guard, "touchdown_ball");
  EXPECT_EQ(ev.mode_after, plant.GetModeIndex("stance"));
  EXPECT_NEAR(ev.time, t_td, 1e-9);
  std::printf("touchdown at t = %.15f s, sqrt(2h/g) = %.15f s, error %.3e s\n", ev.time, t_td, ev.time - t_td);
  EXPECT_NEAR(ctx->continuous_state()[0], 0.1, 1e-9);
  EXPECT_NEAR(ctx->continuous_state()[1], 0.0, 1e-12);
  EXPECT_NEAR(plant.EvalOutput(*ctx, "contact_forces")[2], 2.0 * kG, 1e-9);
}

// A force that jumps out of bounds at another system's discrete update never crosses 0 while integrating: the plant
// checks right after every event. Input u(t) = step(t - t_jump) * u_jump, sampled by a zero-order hold at t_jump.
struct HeldStepDiagram {
  std::unique_ptr<Diagram> diagram;
  const HybridContactPlant* plant = nullptr;
};
HeldStepDiagram BuildHeldStep(std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph, double t_jump,
                              double u_jump) {
  DiagramBuilder b;
  HeldStepDiagram d;
  d.plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, std::move(graph), Terrain::Flat()));
  b.AddSystem(std::make_unique<TrajectorySource>(
      "step", 1, [=](double t, Eigen::Ref<Eigen::VectorXd> out) { out[0] = t < 0.5 * t_jump ? 0.0 : u_jump; }));
  b.AddSystem(std::make_unique<ZeroOrderHold>("hold", t_jump, 1));
  b.Connect("step", "y", "hold", "u");
  b.Connect("hold", "y", "plant", "u");
  d.diagram = b.Build("held_step");
  return d;
}

// Held lift of 3 m g from t = 0.25 s: F_n jumps from m g to -2 m g at the sample, the ball lifts off then.
TEST(ContactEvents, NormalForceJumpingBelowZeroAtADiscreteUpdateLiftsOffAtOnce) {
  auto model = LoadTestModel("ball_on_table");
  const double m = 2.0, t_jump = 0.25;
  HeldStepDiagram d = BuildHeldStep(model, StanceFlight("ball", false), t_jump, 3 * m * kG);
  Simulator sim(*d.diagram, Tight());
  const LeafContext& ctx = d.diagram->GetSubsystemContext(*d.plant, sim.get_context());
  const SimulatorStatus status = sim.AdvanceTo(t_jump + 0.1);
  ASSERT_TRUE(status.ok()) << status.ToString();
  ASSERT_EQ(sim.statistics().events.size(), 1u);
  const EventRecord& ev = sim.statistics().events[0];
  EXPECT_EQ(ev.guard, "liftoff_ball");
  EXPECT_EQ(ev.mode_after, d.plant->GetModeIndex("flight"));
  EXPECT_NEAR(ev.time, t_jump + d.plant->params().immediate_event_delay_s, 1e-12);
  // Then free flight under 3 m g - m g: z - z0 = g (t - t_jump)^2.
  const double tau = ctx.time() - t_jump;
  EXPECT_NEAR(ctx.continuous_state()[0] - 0.1, kG * tau * tau, 1e-8);
}

// Held push of 1.5 mu m g from t = 0.25 s: outside the friction cone at once, the run fails at the sample.
TEST(ContactEvents, PushJumpingOutOfTheFrictionConeAtADiscreteUpdateFails) {
  auto model = LoadTestModel("pushed_block");
  const double m = 2.0, mu = 0.5, t_jump = 0.25;
  HeldStepDiagram d = BuildHeldStep(model, StanceFlight("block_bottom", false), t_jump, 1.5 * mu * m * kG);
  Simulator sim(*d.diagram, Tight());
  const SimulatorStatus status = sim.AdvanceTo(1.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << status.ToString();
  EXPECT_NEAR(status.time, t_jump + d.plant->params().immediate_event_delay_s, 1e-12);
  EXPECT_EQ(status.message,
            "'block_bottom' slipped at t = 0.25 s: |F_t|/F_n = 0.75 exceeded the friction coefficient mu = 0.5 (|F_t| "
            "= 14.715 N, "
            "F_n = 19.62 N; already outside the cone right after an event)");
}

// The lifted block held at u = (c, m g + d) from t = 0.25 s, with 0 < d < event_tolerance_N: F_n = -d jumps just
// below 0 (within the tolerance, so no lift-off) while |F_t| = c stays, outside the cone at once. The message says the
// contact pulls (F_n < 0) instead of printing a negative |F_t|/F_n.
TEST(ContactEvents, APullingContactWithATangentialForceSaysSoInsteadOfANegativeRatio) {
  auto model = LoadTestModel("lifted_block");
  const double m = 2.0, t_jump = 0.25, c = 1.0;
  DiagramBuilder b;
  auto* plant = b.AddSystem(
      std::make_unique<HybridContactPlant>("plant", model, StanceFlight("block_bottom", false), Terrain::Flat()));
  const double d = 0.5 * plant->params().event_tolerance_N;
  b.AddSystem(std::make_unique<TrajectorySource>("step", 2, [=](double t, Eigen::Ref<Eigen::VectorXd> out) {
    out[0] = t < 0.5 * t_jump ? 0.0 : c;
    out[1] = t < 0.5 * t_jump ? 0.0 : m * kG + d;
  }));
  b.AddSystem(std::make_unique<ZeroOrderHold>("hold", t_jump, 2));
  b.Connect("step", "y", "hold", "u");
  b.Connect("hold", "y", "plant", "u");
  auto diagram = b.Build("held_pull");
  Simulator sim(*diagram, Tight());
  const SimulatorStatus status = sim.AdvanceTo(1.0);
  ASSERT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << status.ToString();
  EXPECT_NEAR(status.time, t_jump + plant->params().immediate_event_delay_s, 1e-12);
  EXPECT_EQ(sim.statistics().events.back().guard, "slip");
  EXPECT_NE(status.message.find("'block_bottom' slipped at t = 0.25 s: pulling contact (F_n = -5e-07 N < 0) with a "
                                "tangential force |F_t| = 1 N left (mu = 0.5; already outside the cone right after "
                                "an event)"),
            std::string::npos)
      << status.message;
  EXPECT_EQ(status.message.find("|F_t|/F_n"), std::string::npos) << status.message;
  std::printf("%s\n", status.message.c_str());
}

// AlternatingSingleSupport("a", "b") on two independent balls. Ball a stands, pulled up by u_a = m j t: it lifts off
// at t1 = g / j into flight. Ball b falls freely from h_b and lands at t2 = sqrt(2 h_b / g), only 20 ms after t1 (less
// than min_time_in_mode_s): b was not in contact before flight, so its touchdown is armed at once and is found at t2.
TEST(ContactEvents, AlternatingSingleSupportLiftsOffIntoFlightAndLandsTheOtherFootAtOnce) {
  auto model = LoadTestModel("two_balls");
  const double m = 2.0, t1 = 0.2, j = kG / t1, t2 = 0.22, h_b = 0.5 * kG * t2 * t2;
  DiagramBuilder b;
  auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>(
      "plant", model, ContactModeGraph::AlternatingSingleSupport("a", "b"), Terrain::Flat()));
  ASSERT_LT(t2 - t1, plant->params().min_time_in_mode_s);
  ASSERT_GT(t1, plant->params().min_time_in_mode_s);  // SetState holds both touchdown guards that long
  b.AddSystem(std::make_unique<TrajectorySource>(
      "lift", 2, [=](double t, Eigen::Ref<Eigen::VectorXd> out) { out << m * j * t, 0.0; }));
  b.Connect("lift", "y", "plant", "u");
  auto diagram = b.Build("two_balls");
  Simulator sim(*diagram, Tight());
  LeafContext& ctx = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(ctx, Eigen::Vector2d(0.1, 0.1 + h_b), Eigen::Vector2d::Zero(), "a_stance");
  const SimulatorStatus status = sim.AdvanceTo(0.3);
  ASSERT_TRUE(status.ok()) << status.ToString();
  const auto& events = sim.statistics().events;
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].guard, "liftoff_a");
  EXPECT_EQ(events[0].mode_before, 0);
  EXPECT_EQ(events[0].mode_after, 2);
  EXPECT_NEAR(events[0].time, t1, 1e-9);
  EXPECT_EQ(events[1].guard, "touchdown_b");
  EXPECT_EQ(events[1].mode_after, 1);
  EXPECT_NEAR(events[1].time, t2, 1e-9);
  std::printf("lift-off of a at %.3e s from g/j, touchdown of b at %.3e s from sqrt(2 h / g)\n", events[0].time - t1,
              events[1].time - t2);
  // Discrete state: mode began at t2; a left the ground at t1.
  EXPECT_EQ(ctx.discrete_state()[0], events[1].time);
  EXPECT_EQ(ctx.discrete_state()[1], events[0].time);
}

TEST(ContactEvents, AlternatingSingleSupportHasAFlightModeAtIndexTwo) {
  const ContactModeGraph g = ContactModeGraph::AlternatingSingleSupport("l", "r");
  ASSERT_EQ(g.modes.size(), 3u);
  EXPECT_EQ(g.modes[0].name, "l_stance");
  EXPECT_EQ(g.modes[1].name, "r_stance");
  EXPECT_EQ(g.modes[2].name, "flight");
  EXPECT_TRUE(g.modes[2].contacts.empty());
  auto has = [&](const std::string& from, const std::string& to, ContactModeGraph::Kind kind, const std::string& c) {
    for (const auto& t : g.transitions)
      if (t.from == from && t.to == to && t.kind == kind && t.contact == c) return true;
    return false;
  };
  EXPECT_TRUE(has("l_stance", "flight", ContactModeGraph::Kind::kLiftoff, "l"));
  EXPECT_TRUE(has("r_stance", "flight", ContactModeGraph::Kind::kLiftoff, "r"));
  EXPECT_TRUE(has("flight", "l_stance", ContactModeGraph::Kind::kTouchdown, "l"));
  EXPECT_TRUE(has("flight", "r_stance", ContactModeGraph::Kind::kTouchdown, "r"));
  EXPECT_TRUE(has("l_stance", "r_stance", ContactModeGraph::Kind::kTouchdown, "r"));
  EXPECT_TRUE(has("r_stance", "l_stance", ContactModeGraph::Kind::kTouchdown, "l"));
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

// Counts the plant's touchdowns through an event update triggered by the plant's "touchdown_*" guards only, and
// records, at each, the plant's mode and the time (the update runs right after the reset).
class TouchdownCounter final : public LeafSystem {
 public:
  TouchdownCounter() : LeafSystem("counter") {
    DeclareTypedInputPort<int>("mode");
    DeclareDiscreteState(Eigen::VectorXd::Zero(1));
    DeclareEventUpdate("count_touchdowns", EventTrigger::Guards({{"plant", "touchdown_*"}}),
                       [this](const LeafContext& c, const EventRecord& e, State* next) {
                         next->discrete[0] += 1;
                         seen.push_back({c.time(), e.guard, EvalTypedInput<int>(c, 0)});
                         return EventStatus::Succeeded();
                       });
  }
  struct Seen {
    double time;
    std::string guard;
    int mode;
  };
  mutable std::vector<Seen> seen;
};

// A ball in flight dropped from h bounces plastically: one touchdown at sqrt(2h/g); then a ramp lifts it off again at
// a known time (lift-offs must not reach the counter) and it lands a second time. The counter sees exactly the
// plant's touchdowns, at their times, in the post-impact mode.
TEST(ContactEvents, AnEventUpdateSeesExactlyThePlantsTouchdowns) {
  auto model = LoadTestModel("ball_on_table");
  DiagramBuilder b;
  auto* plant =
      b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, StanceFlight("ball", true), Terrain::Flat()));
  // u = 0 until 0.5 s, then 3 m g upwards for 0.05 s (lift-off at 0.5 s), then 0: the ball flies and lands again.
  const double m = 2.0;
  b.AddSystem(std::make_unique<TrajectorySource>("push", 1, [m](double t, Eigen::Ref<Eigen::VectorXd> out) {
    out[0] = (t >= 0.5 && t < 0.55) ? 3.0 * m * kG : 0.0;
  }));
  auto* hold = b.AddSystem(std::make_unique<ZeroOrderHold>("hold", 0.05, 1));
  b.Connect("push", "y", "hold", "u");
  b.Connect("hold", "y", "plant", "u");
  auto* counter = b.AddSystem(std::make_unique<TouchdownCounter>());
  b.Connect("plant", "mode", "counter", "mode");
  auto diagram = b.Build("touchdowns");
  (void)hold;
  Simulator sim(*diagram, Tight());
  const double h = 0.3, t_td = std::sqrt(2 * h / kG);
  plant->SetState(diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context()),
                  Eigen::VectorXd::Constant(1, 0.1 + h), Eigen::VectorXd::Zero(1), "flight");
  const SimulatorStatus status = sim.AdvanceTo(1.5);
  ASSERT_TRUE(status.ok()) << status.ToString();
  std::vector<EventRecord> touchdowns;
  int liftoffs = 0;
  for (const EventRecord& e : sim.statistics().events) {
    if (e.guard == "touchdown_ball") touchdowns.push_back(e);
    if (e.guard == "liftoff_ball") ++liftoffs;
  }
  ASSERT_EQ(touchdowns.size(), 2u);
  EXPECT_EQ(liftoffs, 1);
  EXPECT_NEAR(touchdowns[0].time, t_td, 1e-9);
  // Held push of 3 m g for 0.05 s from rest: net acceleration 2 g up, then free flight; lands when
  // z = g t1² (up, after t1 = 0.05 s with speed 2 g t1) returns: t_land = t1 + (2 g t1 + sqrt((2 g t1)² + 2 g · g t1²))
  // / g.
  const double t1 = 0.05, v1 = 2 * kG * t1, z1 = kG * t1 * t1;
  const double t_land = 0.5 + t1 + (v1 + std::sqrt(v1 * v1 + 2 * kG * z1)) / kG;
  EXPECT_NEAR(touchdowns[1].time, t_land, 1e-8);
  ASSERT_EQ(counter->seen.size(), touchdowns.size());
  for (size_t k = 0; k < touchdowns.size(); ++k) {
    EXPECT_EQ(counter->seen[k].time, touchdowns[k].time);
    EXPECT_EQ(counter->seen[k].guard, "touchdown_ball");
    EXPECT_EQ(counter->seen[k].mode, plant->GetModeIndex("stance"));
  }
  EXPECT_EQ(diagram->GetSubsystemContext(*counter, sim.get_context()).discrete_state()[0], 2.0);
  std::printf("touchdowns at %.12f s (sqrt(2h/g) %.12f) and %.12f s (closed form %.12f)\n", touchdowns[0].time, t_td,
              touchdowns[1].time, t_land);
}

TEST(ContactEvents, BadGuardAndContactNamesAreOneLineErrors) {
  auto model = LoadTestModel("ball_on_table");
  ContactModeGraph g = StanceFlight("ball", true);
  g.modes[0].contacts = {"bal"};
  try {
    HybridContactPlant("plant", model, g, Terrain::Flat());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "system 'plant': mode 'stance' names contact 'bal', which robot 'ball_on_table' does not have");
  }
  DiagramBuilder b;
  b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, StanceFlight("ball", true), Terrain::Flat()));
  b.FixInput("plant", "u", Eigen::VectorXd::Zero(1));
  class Listener final : public LeafSystem {
   public:
    Listener() : LeafSystem("listener") {
      DeclareEventUpdate("on_touchdown", EventTrigger::Guards({{"plant", "touchdown_bal"}}),
                         [](const LeafContext&, const EventRecord&, State*) { return EventStatus::Succeeded(); });
    }
  };
  b.AddSystem(std::make_unique<Listener>());
  auto diagram = b.Build("bad");
  try {
    Simulator sim(*diagram);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.substr(0, what.find(" (it has")),
              "system 'listener': event update 'on_touchdown' names guard 'touchdown_bal' of system 'plant', which has "
              "no such guard");
    EXPECT_NE(what.find("'touchdown_ball'"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rome

// The contact check's rule, against numbers worked by hand: round-off at a clamped cone (Bullet's sliding foot,
// measured |F_t|/F_n = 0.8 (1 + 7.8e-9) at F_n = 181.209 N) is not a violation; a 1e-4 excess, a pull of 1e-3 N or NaN
// is.
TEST(ContactForceStatistics, ViolationRuleSeparatesRoundOffFromSliding) {
  const rome::ContactForceStatistics stats;
  const double fn = 181.209, mu = 0.8;
  EXPECT_FALSE(stats.Violates(fn, mu * fn * (1 + 7.8e-9), mu));  // excess 1.1e-6 N: above the absolute 1e-6 N alone
  EXPECT_FALSE(stats.Violates(fn, mu * fn, mu));
  EXPECT_TRUE(stats.Violates(fn, mu * fn * (1 + 1e-4), mu));  // 0.0145 N beyond the cone
  EXPECT_TRUE(stats.Violates(-1e-3, 0.0, mu));
  EXPECT_FALSE(stats.Violates(-5e-7, 0.0, mu));
  EXPECT_TRUE(stats.Violates(std::nan(""), 0.0, mu));
  EXPECT_TRUE(stats.Violates(fn, std::nan(""), mu));
  EXPECT_TRUE(stats.Violates(0.0, 1e-5, mu));  // no normal force, a tangential one
}
