// Simulator: event times against closed forms, Zeno policy, exact sampling, energy conservation, modes.
#include "framework/simulator.h"

#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "systems/classic/bouncing_ball.h"

namespace rome {
namespace {

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-12;
  c.absolute_tolerance = 1e-12;
  return c;
}

TEST(Simulator, BouncingBallImpactTimesMatchClosedForm) {
  BouncingBall ball("ball", {.restitution = 0.8, .gravity = 9.81, .initial_height = 1.0});
  // The four schemes, plus the explicit Runge-Kutta scheme with its second embedded pair (index 4).
  for (int variant = 0; variant < 5; ++variant) {
    const IntegrationScheme scheme =
        variant < 4 ? static_cast<IntegrationScheme>(variant) : IntegrationScheme::kExplicitRungeKutta;
    SimulatorConfig config = Tight();
    config.scheme = scheme;
    if (variant >= 4) config.explicit_rk_method = ExplicitRungeKuttaMethod::kBogackiShampine32;
    Simulator sim(ball, config);
    const auto expected = ball.AnalyticImpactTimes(5);
    ASSERT_TRUE(sim.AdvanceTo(expected.back() + 0.01).ok());
    const auto& events = sim.statistics().events;
    ASSERT_EQ(events.size(), 5u);
    for (int k = 0; k < 5; ++k) {
      EXPECT_NEAR(events[k].time, expected[k], 1e-9) << "impact " << k;
      EXPECT_EQ(events[k].guard, "ground_contact");
    }
    // Energy after the k-th impact is e^{2k} of the initial: check the state right after the last impact.
    const auto& x = static_cast<const LeafContext&>(sim.get_context()).continuous_state();
    const double energy = 0.5 * x[1] * x[1] + 9.81 * x[0];
    EXPECT_NEAR(energy, 9.81 * 1.0 * std::pow(0.8, 10), 1e-8);
  }
}

TEST(Simulator, RestartWithLastStepKeepsImpactTimesUnderPeriodicUpdates) {
  // The ball sampled by a 1 kHz zero-order hold: every sample restarts the integrator (with the option, at the step
  // size reached), every impact resets the state (never at the carried step: the root finder's look-ahead after a reset
  // at a zero guard is a fraction of the first step, and a carried step missed impacts). Impact times to 1e-9 s.
  const BouncingBallParams params{.restitution = 0.8, .gravity = 9.81, .initial_height = 1.0};
  const auto expected = BouncingBall("reference", params).AnalyticImpactTimes(5);
  double first_step_after_impact[2] = {0, 0};
  for (bool carry : {false, true}) {
    DiagramBuilder builder;
    builder.AddSystem(std::make_unique<BouncingBall>("ball", params));
    builder.AddSystem(std::make_unique<ZeroOrderHold>("zoh", 1e-3, 2));
    builder.Connect("ball", "state", "zoh", "u");
    auto diagram = builder.Build();
    SimulatorConfig config = Tight();
    config.scheme = IntegrationScheme::kExplicitRungeKutta;
    config.explicit_rk_method = ExplicitRungeKuttaMethod::kBogackiShampine32;
    config.restart_with_last_step = carry;
    Simulator sim(*diagram, config);
    ASSERT_TRUE(sim.AdvanceTo(expected.back() + 0.01).ok());
    const auto& events = sim.statistics().events;
    ASSERT_EQ(events.size(), 5u) << "carry " << carry;
    for (int k = 0; k < 5; ++k) EXPECT_NEAR(events[k].time, expected[k], 1e-9) << "carry " << carry << ", impact " << k;
    EXPECT_GT(sim.statistics().restarts, 1000) << "the hold restarts the integrator at every sample";
    first_step_after_impact[carry] = sim.statistics().max_initial_step_after_reset_s;
  }
  // After an impact both runs start with ARKODE's own estimate (nearly the same state, so nearly the same step), not
  // with the step carried from before the impact.
  ASSERT_GT(first_step_after_impact[0], 0.0);
  EXPECT_NEAR(first_step_after_impact[1], first_step_after_impact[0], 0.5 * first_step_after_impact[0]);
}

TEST(Simulator, GuardSignBeforeAtAndAfterEvent) {
  BouncingBall ball("ball", {.restitution = 0.8});
  Simulator sim(ball, Tight());
  const double t1 = ball.AnalyticImpactTimes(1)[0];
  sim.AdvanceTo(t1 - 1e-6);
  const auto& c = static_cast<const LeafContext&>(sim.get_context());
  EXPECT_GT(c.continuous_state()[0], 0.0);
  EXPECT_LT(c.continuous_state()[1], 0.0);
  sim.AdvanceTo(t1 + 1e-6);
  EXPECT_EQ(sim.statistics().guard_events, 1);
  EXPECT_NEAR(sim.statistics().events[0].time, t1, 1e-10);
  EXPECT_GT(c.continuous_state()[1], 0.0);  // moving up after the reset
  EXPECT_GT(c.continuous_state()[0], 0.0);
}

TEST(Simulator, ZenoBallEndsWithClearStatus) {
  BouncingBall ball("ball", {.restitution = 0.5, .initial_height = 1.0, .rest_velocity_cutoff = 0.0});
  Simulator sim(ball, Tight());
  const double t_zeno = ball.AnalyticImpactTimes(1)[0] * (1 + 0.5) / (1 - 0.5);
  const SimulatorStatus status = sim.AdvanceTo(10.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kZeno) << status.ToString();
  EXPECT_EQ(status.system, "ball");
  EXPECT_NE(status.message.find("ground_contact"), std::string::npos) << status.message;
  EXPECT_NEAR(status.time, t_zeno, 1e-4);  // stopped close to the accumulation point
  EXPECT_LT(status.time, t_zeno + 1e-9);
  // A terminated simulator keeps returning its terminal status.
  EXPECT_EQ(sim.AdvanceTo(11.0).reason, SimulatorStatus::Reason::kZeno);
  // The throwing policy.
  SimulatorConfig config = Tight();
  config.event_policy.throw_on_violation = true;
  Simulator sim2(ball, config);
  EXPECT_THROW(sim2.AdvanceTo(10.0), std::runtime_error);
}

TEST(Simulator, RestVelocityCutoffStopsTheBall) {
  BouncingBall ball("ball", {.restitution = 0.5, .rest_velocity_cutoff = 0.1});
  Simulator sim(ball, Tight());
  ASSERT_TRUE(sim.AdvanceTo(5.0).ok());
  const auto& c = static_cast<const LeafContext&>(sim.get_context());
  EXPECT_EQ(c.mode(), 1);
  EXPECT_EQ(c.continuous_state()[0], 0.0);
  EXPECT_EQ(static_cast<int>(sim.statistics().events.size()), static_cast<int>(ball.AnalyticImpactTimes(100).size()));
}

// A discrete counter: x_{k+1} = x_k + 1 every period.
class Counter final : public LeafSystem {
 public:
  explicit Counter(double period) : LeafSystem("counter") {
    DeclareDiscreteState(Eigen::VectorXd::Zero(1));
    DeclarePeriodicDiscreteUpdate(period, 0.0, [](const LeafContext& c, Eigen::VectorXd* xd) {
      (*xd)[0] = c.discrete_state()[0] + 1;
      return EventStatus::Succeeded();
    });
    DeclareOutputPort(
        "count", 1, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state(); }, Feedthrough::None());
  }
};

TEST(Simulator, DiscreteCounterUpdatesExactlyOncePerSample) {
  Counter counter(1e-3);
  Simulator sim(counter);
  ASSERT_TRUE(sim.AdvanceTo(1.0).ok());
  EXPECT_EQ(static_cast<const LeafContext&>(sim.get_context()).discrete_state()[0], 1000.0);
  EXPECT_EQ(sim.get_context().time(), 1.0);
  // AdvanceTo can be called repeatedly: 500 more in the next 0.5 s.
  ASSERT_TRUE(sim.AdvanceTo(1.5).ok());
  EXPECT_EQ(static_cast<const LeafContext&>(sim.get_context()).discrete_state()[0], 1500.0);
}

// ẋ = a x + b u, integrator plant.
class FirstOrderPlant final : public LeafSystem {
 public:
  FirstOrderPlant(double a, double b, double x0) : LeafSystem("plant"), a_(a), b_(b) {
    DeclareInputPort("u", 1);
    DeclareContinuousState(Eigen::VectorXd::Constant(1, x0));
    DeclareOutputPort(
        "x", 1, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = a_ * c.continuous_state()[0] + b_ * EvalInput(c, 0)[0];
  }

 private:
  double a_, b_;
};

// ẋ = a x + b u under u_k = −K x(t_k) held over each period h (a zero-order hold), exported output "x".
std::unique_ptr<Diagram> BuildZeroOrderHoldLoop(double a, double b, double K, double h, double x0) {
  DiagramBuilder builder;
  builder.AddSystem(std::make_unique<FirstOrderPlant>(a, b, x0));
  builder.AddSystem(std::make_unique<Gain>("controller", -K, 1));
  builder.AddSystem(std::make_unique<ZeroOrderHold>("zoh", h, 1));
  builder.Connect("plant", "x", "controller", "u");
  builder.Connect("controller", "y", "zoh", "u");
  builder.Connect("zoh", "y", "plant", "u");
  builder.ExportOutput("plant", "x");
  return builder.Build();
}

TEST(Simulator, ZeroOrderHeldControlMatchesExactDiscretisation) {
  // Plant ẋ = a x + b u under u_k = −K x(t_k) held over each period h: x_{k+1} = (Φ − Γ K) x_k,
  // Φ = e^{a h}, Γ = (e^{a h} − 1) b / a.
  const double a = 0.7, b = 2.0, K = 1.5, h = 0.01, x0 = 1.0;
  auto diagram = BuildZeroOrderHoldLoop(a, b, K, h, x0);
  Simulator sim(*diagram, Tight());
  const double Phi = std::exp(a * h), Gamma = (std::exp(a * h) - 1) * b / a;
  double x = x0;
  for (int k = 1; k <= 100; ++k) {
    x = (Phi - Gamma * K) * x;
    ASSERT_TRUE(sim.AdvanceTo(k * h).ok());
    ASSERT_NEAR(diagram->EvalOutput(sim.get_context(), "x")[0], x, 1e-9) << "sample " << k;
  }
  EXPECT_EQ(sim.statistics().discrete_samples, 100);
}

TEST(Simulator, ZeroOrderHoldRestartsAndJacobianCounts) {
  // The discretisation above, integrated by BDF, by Dormand-Prince, and by Dormand-Prince restarting each sample with
  // the step size it ended the previous one with. Every sample changes the held u, so the integrator restarts at each
  // of the 100 samples; CVODE's dense difference-quotient Jacobian costs one derivative evaluation per state (nx = 1).
  const double a = 0.7, b = 2.0, K = 1.5, h = 0.01, x0 = 1.0;
  const double Phi = std::exp(a * h), Gamma = (std::exp(a * h) - 1) * b / a;
  long rk_steps[2] = {0, 0};
  for (int variant = 0; variant < 3; ++variant) {
    auto diagram = BuildZeroOrderHoldLoop(a, b, K, h, x0);
    SimulatorConfig config = Tight();
    config.scheme = variant == 0 ? IntegrationScheme::kBdf : IntegrationScheme::kExplicitRungeKutta;
    config.restart_with_last_step = variant == 2;
    Simulator sim(*diagram, config);
    double x = x0;
    for (int k = 1; k <= 100; ++k) {
      x = (Phi - Gamma * K) * x;
      ASSERT_TRUE(sim.AdvanceTo(k * h).ok());
      ASSERT_NEAR(diagram->EvalOutput(sim.get_context(), "x")[0], x, 1e-9) << "variant " << variant << ", sample " << k;
    }
    const SimulatorStatistics& s = sim.statistics();
    EXPECT_EQ(s.restarts, 100) << "variant " << variant;
    if (variant == 0) {
      EXPECT_GE(s.jacobian_evals, s.restarts);  // a restarted BDF starts with a new Jacobian
      EXPECT_EQ(s.jacobian_rhs_evals, 1 * s.jacobian_evals);
      EXPECT_GT(s.rhs_evals, s.jacobian_rhs_evals);
      EXPECT_GT(s.nonlinear_iterations, 0);
    } else {
      EXPECT_EQ(s.jacobian_evals, 0);
      EXPECT_EQ(s.jacobian_rhs_evals, 0);
      EXPECT_EQ(s.nonlinear_iterations, 0);
      rk_steps[variant - 1] = s.steps;
    }
  }
  // Starting each sample with the last step size skips ARKODE's cautious first steps.
  EXPECT_LT(rk_steps[1], rk_steps[0]);
}

TEST(Simulator, RestartWithLastStepTakesOneStepPerSampleWhenTheErrorTestAllows) {
  // The zero-order-held loop above at a loose tolerance, where the error test allows steps longer than the 10 ms sample
  // period. Every interval ends with a step clipped to the sample time; restarting the next interval with that clipped
  // size (what ARKODE reports as its next step) split each interval into two steps. Restarting with the size the
  // clipped step's own error estimate asks for takes one step per interval. The state still matches the exact
  // discretisation to the tolerance's order.
  const double a = 0.7, b = 2.0, K = 1.5, h = 0.01, x0 = 1.0;
  const double Phi = std::exp(a * h), Gamma = (std::exp(a * h) - 1) * b / a;
  for (ExplicitRungeKuttaMethod method :
       {ExplicitRungeKuttaMethod::kBogackiShampine32, ExplicitRungeKuttaMethod::kDormandPrince54}) {
    auto diagram = BuildZeroOrderHoldLoop(a, b, K, h, x0);
    SimulatorConfig config;
    config.scheme = IntegrationScheme::kExplicitRungeKutta;
    config.explicit_rk_method = method;
    config.relative_tolerance = 1e-6;
    config.absolute_tolerance = 1e-9;
    config.restart_with_last_step = true;
    Simulator sim(*diagram, config);
    double x = x0;
    for (int k = 1; k <= 200; ++k) {
      x = (Phi - Gamma * K) * x;
      ASSERT_TRUE(sim.AdvanceTo(k * h).ok());
      ASSERT_NEAR(diagram->EvalOutput(sim.get_context(), "x")[0], x, 1e-6 * std::abs(x) + 1e-8) << "sample " << k;
    }
    const SimulatorStatistics& s = sim.statistics();
    // A few extra steps for ARKODE's first estimate; none per interval.
    EXPECT_LE(s.steps, s.restarts + 10) << "method " << static_cast<int>(method) << ": " << s.steps << " steps, "
                                        << s.restarts << " restarts";
    EXPECT_LE(s.error_test_failures, 5);
  }
}

// Undamped pendulum: θ̈ = −(g/l) sin θ.
class Pendulum final : public LeafSystem {
 public:
  Pendulum() : LeafSystem("pendulum") { DeclareContinuousState(Eigen::Vector2d(2.5, 0.0)); }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = c.continuous_state()[1];
    (*xdot)[1] = -(9.81 / 0.8) * std::sin(c.continuous_state()[0]);
  }
  static double Energy(const Eigen::VectorXd& x) { return 0.5 * 0.8 * 0.8 * x[1] * x[1] - 9.81 * 0.8 * std::cos(x[0]); }
};

TEST(Simulator, UndampedPendulumConservesEnergy) {
  Pendulum p;
  for (int variant = 0; variant < 5; ++variant) {
    const IntegrationScheme scheme =
        variant < 4 ? static_cast<IntegrationScheme>(variant) : IntegrationScheme::kExplicitRungeKutta;
    SimulatorConfig config = Tight();
    config.scheme = scheme;
    if (variant == 4) config.explicit_rk_method = ExplicitRungeKuttaMethod::kBogackiShampine32;
    config.relative_tolerance = 1e-13;
    config.absolute_tolerance = 1e-14;
    Simulator sim(p, config);
    const double e0 = Pendulum::Energy(static_cast<const LeafContext&>(sim.get_context()).continuous_state());
    double worst = 0;
    sim.set_monitor([&](const Context& c) {
      const double e = Pendulum::Energy(static_cast<const LeafContext&>(c).continuous_state());
      worst = std::max(worst, std::abs(e - e0) / std::abs(e0));
      return EventStatus::Succeeded();
    });
    ASSERT_TRUE(sim.AdvanceTo(10.0).ok());
    EXPECT_LT(worst, 1e-8) << "variant " << variant;
    EXPECT_GT(sim.statistics().steps, 100);
    EXPECT_GT(sim.statistics().rhs_evals, sim.statistics().steps);
  }
}

// Thermostat: temperature T with heater on (mode 1) or off (mode 0).
// Ṫ = −k (T − T_ambient) + heating (mode 1). Switch off at T_high (rising), on at T_low (falling).
class Thermostat final : public LeafSystem {
 public:
  static constexpr double k = 0.5, ambient = 10.0, heating = 10.0, low = 18.0, high = 22.0;
  Thermostat() : LeafSystem("thermostat") {
    DeclareModes({"off", "on"}, 1);
    DeclareContinuousState(Eigen::VectorXd::Constant(1, 15.0));
    DeclareGuard(
        "too_hot", 1, [](const LeafContext& c) { return c.continuous_state()[0] - high; }, CrossingDirection::kRising,
        [](const LeafContext&, int, State* s) {
          s->mode = 0;
          return EventStatus::Succeeded();
        });
    DeclareGuard(
        "too_cold", 0, [](const LeafContext& c) { return c.continuous_state()[0] - low; }, CrossingDirection::kFalling,
        [](const LeafContext&, int, State* s) {
          s->mode = 1;
          return EventStatus::Succeeded();
        });
  }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = -k * (c.continuous_state()[0] - ambient) + (c.mode() == 1 ? heating : 0.0);
  }
};

TEST(Simulator, ThermostatSwitchesAtThresholds) {
  Thermostat th;
  Simulator sim(th, Tight());
  ASSERT_TRUE(sim.AdvanceTo(30.0).ok());
  const auto& ev = sim.statistics().events;
  ASSERT_GE(ev.size(), 4u);
  // Closed form: heating from T0 to high: T(t) = T_eq + (T0 − T_eq) e^{−k t}, T_eq = ambient + heating/k = 30.
  const double T_on = Thermostat::ambient + Thermostat::heating / Thermostat::k;
  const double t_first = std::log((15.0 - T_on) / (Thermostat::high - T_on)) / Thermostat::k;
  EXPECT_NEAR(ev[0].time, t_first, 1e-9);
  const double t_cool =
      std::log((Thermostat::high - Thermostat::ambient) / (Thermostat::low - Thermostat::ambient)) / Thermostat::k;
  const double t_heat = std::log((Thermostat::low - T_on) / (Thermostat::high - T_on)) / Thermostat::k;
  for (size_t i = 1; i < ev.size(); ++i) {
    const bool was_on = ev[i - 1].guard == "too_hot";
    EXPECT_EQ(ev[i].guard, was_on ? "too_cold" : "too_hot");
    EXPECT_NEAR(ev[i].time - ev[i - 1].time, was_on ? t_cool : t_heat, 1e-8);
    EXPECT_EQ(ev[i].mode_after, was_on ? 1 : 0);
  }
}

// A system that ends the run with a reason, and one that produces NaN.
class Faller final : public LeafSystem {
 public:
  explicit Faller(bool produce_nan) : LeafSystem("robot"), nan_(produce_nan) {
    DeclareContinuousState(Eigen::Vector2d(1.0, 0.0));
    DeclareGuard(
        "fell", kAllModes, [](const LeafContext& c) { return c.continuous_state()[0] - 0.5; },
        CrossingDirection::kFalling,
        [](const LeafContext&, int, State*) {
          return EventStatus::ReachedTermination("robot fell: height below 0.5 m");
        });
  }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = c.continuous_state()[1];
    (*xdot)[1] = nan_ && c.time() > 0.1 ? std::nan("") : -9.81;
  }

 private:
  bool nan_;
};

TEST(Simulator, SystemEndsRunWithReason) {
  Faller f(false);
  Simulator sim(f, Tight());
  const auto status = sim.AdvanceTo(5.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kReachedTermination);
  EXPECT_EQ(status.system, "robot");
  EXPECT_NE(status.message.find("robot fell"), std::string::npos);
  EXPECT_NEAR(status.time, std::sqrt(2 * 0.5 / 9.81), 1e-9);
}

TEST(Simulator, NonFiniteDerivativeIsReportedWithSystemName) {
  Faller f(true);
  Simulator sim(f, Tight());
  const auto status = sim.AdvanceTo(5.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed);
  EXPECT_NE(status.ToString().find("robot"), std::string::npos) << status.ToString();
}

TEST(Simulator, MonitorCanTerminate) {
  BouncingBall ball;
  Simulator sim(ball);
  sim.set_monitor([](const Context& c) {
    return c.time() > 0.2 ? EventStatus::ReachedTermination("enough") : EventStatus::Succeeded();
  });
  const auto status = sim.AdvanceTo(5.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kReachedTermination);
  EXPECT_EQ(status.message, "enough");
}

TEST(Simulator, MonitorsRunInOrderAndTheFirstVerdictEndsTheRun) {
  // Three monitors: a counter, one that fails once the ball first falls below 0.5 m, and one that would end the run
  // as a success at the same instant. The run must end at the first accepted step below 0.5 m (free fall from 1 m:
  // h(t) = 1 − g t²/2 crosses 0.5 m at t = sqrt(1/g)), named after the second monitor, and the third must not have
  // run at that step (it runs after the second).
  BouncingBall ball("ball", {.restitution = 0.8, .gravity = 9.81, .initial_height = 1.0});
  SimulatorConfig config = Tight();
  config.max_step_s = 1e-3;  // accepted steps at most 1 ms apart
  Simulator sim(ball, config);
  int calls_first = 0, calls_third = 0;
  sim.add_monitor(
      [&](const Context&) {
        ++calls_first;
        return EventStatus::Succeeded();
      },
      "counter");
  sim.add_monitor(
      [](const Context& c) {
        const double h = static_cast<const LeafContext&>(c).continuous_state()[0];
        return h < 0.5 ? EventStatus::Failed("below half height") : EventStatus::Succeeded();
      },
      "height_check");
  sim.add_monitor(
      [&](const Context& c) {
        ++calls_third;
        const double h = static_cast<const LeafContext&>(c).continuous_state()[0];
        return h < 0.5 ? EventStatus::ReachedTermination("must not be reached") : EventStatus::Succeeded();
      },
      "late");
  EXPECT_EQ(sim.num_monitors(), 3);
  const SimulatorStatus status = sim.AdvanceTo(5.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed);
  EXPECT_EQ(status.system, "height_check");
  EXPECT_EQ(status.message, "below half height");
  const double t_half = std::sqrt(1.0 / 9.81);
  EXPECT_GE(status.time, t_half);
  EXPECT_LE(status.time, t_half + 1e-3 + 1e-12);
  EXPECT_EQ(calls_third, calls_first - 1);  // the step that ended the run did not reach the third monitor
  // set_monitor replaces all of them: a fresh run with one monitor that never objects reaches the time limit.
  Simulator sim2(ball, config);
  sim2.add_monitor([](const Context&) { return EventStatus::Failed("replaced"); });
  sim2.set_monitor([](const Context&) { return EventStatus::Succeeded(); });
  EXPECT_EQ(sim2.num_monitors(), 1);
  EXPECT_TRUE(sim2.AdvanceTo(0.1).ok());
  sim2.set_monitor(nullptr);
  EXPECT_EQ(sim2.num_monitors(), 0);
  EXPECT_THROW(sim2.add_monitor(nullptr, "empty"), std::invalid_argument);
}

TEST(Simulator, EventLimitEndsTheRunAtTheNthImpact) {
  // Closed form (bouncing_ball.h): t1 = sqrt(2 h0 / g), t_{k+1} = t_k + 2 e^k sqrt(2 g h0) / g; after the k-th impact
  // the velocity is e^k sqrt(2 g h0) upwards.
  const double e = 0.8, g = 9.81, h0 = 1.0;
  const int n = 3;
  double t_n = std::sqrt(2 * h0 / g);
  for (int k = 1; k < n; ++k) t_n += 2 * std::pow(e, k) * std::sqrt(2 * g * h0) / g;
  BouncingBall ball("ball", {.restitution = e, .gravity = g, .initial_height = h0});
  SimulatorConfig config = Tight();
  config.max_guard_events = n;
  Simulator sim(ball, config);
  const SimulatorStatus status = sim.AdvanceTo(100.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kReachedEventLimit);
  EXPECT_EQ(status.kind(), SimulatorStatus::Kind::kLimit);
  EXPECT_EQ(status.kind_name(), "limit");
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message.find("3 guard events"), std::string::npos) << status.message;
  EXPECT_NEAR(status.time, t_n, 1e-9);
  EXPECT_EQ(sim.statistics().guard_events, n);
  // The run ends after the n-th reset: the ball leaves the ground at e^n sqrt(2 g h0).
  const auto& x = static_cast<const LeafContext&>(sim.get_context()).continuous_state();
  EXPECT_NEAR(x[0], 0.0, 1e-9);
  EXPECT_NEAR(x[1], std::pow(e, n) * std::sqrt(2 * g * h0), 1e-7);
  // The run has ended: a later call returns the same status without advancing.
  EXPECT_EQ(sim.AdvanceTo(200.0).reason, SimulatorStatus::Reason::kReachedEventLimit);
  EXPECT_NEAR(sim.get_context().time(), t_n, 1e-9);
  // Refused: a negative limit.
  config.max_guard_events = -1;
  Simulator bad(ball, config);
  EXPECT_THROW(bad.AdvanceTo(1.0), std::invalid_argument);
}

TEST(Simulator, TimeLimitIsNamedAndIsNoVerdict) {
  BouncingBall ball("ball", {.restitution = 0.8, .gravity = 9.81, .initial_height = 1.0});
  Simulator sim(ball, Tight());
  const SimulatorStatus status = sim.AdvanceTo(0.25);
  EXPECT_TRUE(status.ok());
  EXPECT_EQ(status.kind(), SimulatorStatus::Kind::kLimit);
  EXPECT_EQ(status.message, "reached the time limit t = 0.25 s");
  EXPECT_EQ(status.ToString(), "reached the time limit t = 0.25 s");
  for (const char* verdict : {"success", "fail", "terminat"})
    EXPECT_EQ(status.ToString().find(verdict), std::string::npos) << verdict;
}

TEST(Simulator, ExceptionInDynamicsPropagates) {
  FirstOrderPlant plant(1, 1, 0);  // input not fixed: EvalInput throws naming the port
  Simulator sim(plant);
  try {
    sim.AdvanceTo(1.0);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("input port 'u' of system 'plant' is not connected"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

// e = 0: no rebound, the ball stays on the ground after its first impact (it must not fall through the floor);
// a ball released on the ground stays there.
TEST(Simulator, BallWithoutReboundOrHeightStaysOnTheGround) {
  for (const BouncingBallParams& p : {BouncingBallParams{.restitution = 0.0, .initial_height = 1.0},
                                      BouncingBallParams{.restitution = 0.8, .initial_height = 0.0}}) {
    BouncingBall ball("ball", p);
    Simulator sim(ball, Tight());
    ASSERT_TRUE(sim.AdvanceTo(3.0).ok());
    const auto& x = static_cast<const LeafContext&>(sim.get_context()).continuous_state();
    EXPECT_EQ(x[0], 0.0) << "e = " << p.restitution << ", h0 = " << p.initial_height;
    EXPECT_EQ(x[1], 0.0);
    EXPECT_EQ(sim.statistics().guard_events, p.initial_height > 0 ? 1 : 0);
    if (p.initial_height > 0) { EXPECT_NEAR(sim.statistics().events[0].time, std::sqrt(2.0 / 9.81), 1e-9); }
  }
}

}  // namespace
}  // namespace rome
